// libFuzzer target: the bounds check, the checked decode and the validation
// of every message type on arbitrary bytes, then the conversions to core
// types of what passed (dynapath serve's updates and occupancy grids too). The type is the one
// whose fingerprint the bytes start with (the seeds are real messages of every type); bytes with an
// unknown fingerprint go through every type. Also a differential check: a
// message the bounds check accepts is one LCM's own decoder reads exactly.

#include <cstdint>
#include <cstdlib>
#include <string>

#include "protocol/convert.h"
#include "protocol/fragments.h"
#include "protocol/validate.h"
#include "tests/protocol/message_types.h"

namespace {

using dynapath::protocol::testing::AllMessageTypes;
using dynapath::protocol::testing::MessageType;

template <class T>
void ValidateAndConvert(const uint8_t* data, int size) {
  T message;
  if (!dynapath::protocol::DecodeExactly(data, size, message)) return;
  if constexpr (requires { dynapath::protocol::Validate(message); }) {
    if (!dynapath::protocol::Validate(message).ok()) return;
  }
  if constexpr (std::is_same_v<T, dynapath::grid_t>) {
    (void)dynapath::protocol::GridFromMessage(message);
  } else if constexpr (std::is_same_v<T, dynapath::changes_t>) {
    (void)dynapath::protocol::ChangesFromMessage(message, 64, 64);
  } else if constexpr (std::is_same_v<T, dynapath::obstacle_update_t>) {
    // The message's own maze, so that its cells are read too.
    (void)dynapath::protocol::UpdateFromMessage(message, 64, 64,
                                                static_cast<uint64_t>(message.maze_fingerprint));
  } else if constexpr (std::is_same_v<T, dynapath::occupancy_grid_t>) {
    // A map of the message's own size (the grid's), stations in one corner.
    dynapath::Grid map(message.rows, message.cols);
    map.set(0, dynapath::Cell::kStation);
    // The whole map in its own frame, then as a window of a map of 40 x 50
    // cells of 0.05 m from (-0.16, 0) m (the seeds' frame).
    (void)dynapath::protocol::UpdateFromOccupancyGrid(
        message, map,
        dynapath::MapFrame{message.resolution, message.origin_x, message.origin_y, message.rows,
                           message.cols},
        {});
    dynapath::Grid other(40, 50);
    other.set(7, dynapath::Cell::kStation);
    (void)dynapath::protocol::UpdateFromOccupancyGrid(
        message, other, dynapath::MapFrame{0.05, -0.16, 0.0, 40, 50}, {});
  } else if constexpr (std::is_same_v<T, dynapath::obstacle_points_t>) {
    (void)dynapath::protocol::UpdateFromPoints(message, dynapath::MapFrame{0.05, -1.0, 2.0, 64, 64},
                                               static_cast<uint64_t>(message.maze_fingerprint));
  } else if constexpr (std::is_same_v<T, dynapath::model_round_t>) {
    (void)dynapath::protocol::ConvQOptionsFromRound(message);
    (void)dynapath::protocol::ConvQModelFromRound(message);
  } else if constexpr (std::is_same_v<T, dynapath::model_shards_t>) {
    (void)dynapath::protocol::ConvQShardsFromMessage(message);
  } else if constexpr (std::is_same_v<T, dynapath::job_batch_t>) {
    for (int i = 0; i < message.num_jobs; ++i) (void)dynapath::protocol::JobFromBatch(message, i);
  }
}

void Check(const MessageType& type, const uint8_t* data, int size) {
  std::string why;
  if (type.checked_decode(data, size, &why)) {
    // Safe now: the bounds check passed.
    if (!type.raw_decode(data, size, nullptr)) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1 << 20)) return 0;
  const int n = static_cast<int>(size);
  const int64_t fingerprint = dynapath::protocol::PeekFingerprint(data, n);
  bool known = false;
  for (const MessageType& type : AllMessageTypes()) {
    if (type.hash == fingerprint) {
      known = true;
      Check(type, data, n);
    }
  }
  if (!known) {
    for (const MessageType& type : AllMessageTypes()) Check(type, data, n);
  }
  ValidateAndConvert<dynapath::heartbeat_t>(data, n);
  ValidateAndConvert<dynapath::step_request_t>(data, n);
  ValidateAndConvert<dynapath::grid_t>(data, n);
  ValidateAndConvert<dynapath::changes_t>(data, n);
  ValidateAndConvert<dynapath::job_batch_t>(data, n);
  ValidateAndConvert<dynapath::shards_t>(data, n);
  ValidateAndConvert<dynapath::job_result_t>(data, n);
  ValidateAndConvert<dynapath::fragment_t>(data, n);
  ValidateAndConvert<dynapath::model_round_t>(data, n);
  ValidateAndConvert<dynapath::model_shards_t>(data, n);
  ValidateAndConvert<dynapath::fragment_nack_t>(data, n);
  ValidateAndConvert<dynapath::step_report_t>(data, n);
  ValidateAndConvert<dynapath::policy_t>(data, n);
  ValidateAndConvert<dynapath::obstacle_update_t>(data, n);
  ValidateAndConvert<dynapath::occupancy_grid_t>(data, n);
  ValidateAndConvert<dynapath::obstacle_points_t>(data, n);
  ValidateAndConvert<dynapath::path_request_t>(data, n);
  ValidateAndConvert<dynapath::path_reply_t>(data, n);
  ValidateAndConvert<dynapath::goal_request_t>(data, n);
  ValidateAndConvert<dynapath::goal_reply_t>(data, n);
  return 0;
}
