#pragma once
// Test and fuzz support: every LCM message type of the run, by name, with a
// generic decode / re-encode, so tests can loop over all types. The list is
// checked against the schema (the .lcm files) by the bounds test: a type
// added to lcmtypes/ must be added here too.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "dynapath/changes_t.hpp"
#include "dynapath/fragment_nack_t.hpp"
#include "dynapath/fragment_t.hpp"
#include "dynapath/goal_reply_t.hpp"
#include "dynapath/goal_request_t.hpp"
#include "dynapath/grid_t.hpp"
#include "dynapath/heartbeat_t.hpp"
#include "dynapath/job_batch_t.hpp"
#include "dynapath/job_result_t.hpp"
#include "dynapath/job_t.hpp"
#include "dynapath/learner_shard_t.hpp"
#include "dynapath/model_round_t.hpp"
#include "dynapath/model_shards_t.hpp"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "dynapath/occupancy_grid_t.hpp"
#include "dynapath/path_reply_t.hpp"
#include "dynapath/path_request_t.hpp"
#include "dynapath/policy_t.hpp"
#include "dynapath/shards_t.hpp"
#include "dynapath/step_report_t.hpp"
#include "dynapath/step_request_t.hpp"
#include "protocol/decode.h"

namespace dynapath::protocol::testing {

struct MessageType {
  std::string name;
  int64_t hash;
  // LCM's own generated decode, unchecked: true when it took exactly `size`
  // bytes; `reencoded` gets the message encoded again.
  std::function<bool(const uint8_t*, int, std::vector<uint8_t>* reencoded)> raw_decode;
  // The checked decode every receiver uses (DecodeExactly).
  std::function<bool(const uint8_t*, int, std::string* why)> checked_decode;
};

template <class T>
MessageType MakeMessageType() {
  MessageType type;
  type.name = T::getTypeName();
  type.hash = T::getHash();
  type.raw_decode = [](const uint8_t* data, int size, std::vector<uint8_t>* reencoded) {
    T message;
    if (message.decode(data, 0, size) != size) return false;
    if (reencoded != nullptr) {
      reencoded->resize(static_cast<size_t>(message.getEncodedSize()));
      message.encode(reencoded->data(), 0, static_cast<int>(reencoded->size()));
    }
    return true;
  };
  type.checked_decode = [](const uint8_t* data, int size, std::string* why) {
    T message;
    return DecodeExactly(data, size, message, why);
  };
  return type;
}

inline const std::vector<MessageType>& AllMessageTypes() {
  static const std::vector<MessageType> types = {
      MakeMessageType<changes_t>(),        MakeMessageType<fragment_t>(),
      MakeMessageType<fragment_nack_t>(),  MakeMessageType<grid_t>(),
      MakeMessageType<heartbeat_t>(),      MakeMessageType<job_batch_t>(),
      MakeMessageType<job_result_t>(),     MakeMessageType<job_t>(),
      MakeMessageType<learner_shard_t>(),  MakeMessageType<policy_t>(),
      MakeMessageType<shards_t>(),         MakeMessageType<step_report_t>(),
      MakeMessageType<step_request_t>(),   MakeMessageType<obstacle_update_t>(),
      MakeMessageType<occupancy_grid_t>(), MakeMessageType<path_request_t>(),
      MakeMessageType<path_reply_t>(),     MakeMessageType<goal_request_t>(),
      MakeMessageType<goal_reply_t>(),     MakeMessageType<model_round_t>(),
      MakeMessageType<model_shards_t>(),   MakeMessageType<obstacle_points_t>(),
  };
  return types;
}

}  // namespace dynapath::protocol::testing
