#pragma once
// Memory caps of a run's receivers, derived from the run's grid: whatever a
// sender announces, a process never buffers more than these.

#include <cstddef>
#include <cstdint>

#include "dynapath/limits.h"
#include "protocol/fragments.h"

namespace dynapath::protocol {

// Cells of the largest grid the protocol accepts.
inline constexpr int64_t kMaxGridCells = static_cast<int64_t>(kMaxGridSide) * kMaxGridSide;

// dynapath serve's messages. Names of sources and clients (what the
// service keeps per source: its last sequence number).
inline constexpr size_t kMaxPeerNameChars = 64;
// Cells of one obstacle update, points of one obstacle_points_t (a whole
// map travels as an occupancy grid).
inline constexpr int32_t kMaxUpdateCells = 65536;
// Starts of one path request the wire accepts (the service answers at most
// its --max-starts of them and refuses larger requests with a status).
inline constexpr int32_t kMaxRequestStarts = 65536;

// Federated training of convQ's model (model_round_t, model_shards_t):
// learners of a training and the largest maze side a round may ask for
// (train-model's mazes are 16 to 48 cells a side).
inline constexpr int32_t kMaxModelLearners = 256;
inline constexpr int32_t kMaxModelMazeSide = 512;

// An upper bound of the encoded size of any message of a run whose grid has
// `cells` cells. The largest are job batches of warm-started nodes (per cell:
// its code, 8 table values, two start counters: 41 bytes, 73 with the double
// tables of --semantics report), the final tables (32 or 64 bytes per cell) and policies (3 bytes
// per cell and 16 per region); a batch's jobs cover the grid at most twice over (a node and its
// children), and a round's shards hold at most one update per table entry
// and learner.
int64_t LargestMessageBytes(int64_t cells);

// The Bus's fragment caps for such a run: one largest message at a time
// plus as much again of partial ones (a resend overlapping a new message),
// 64 partial messages, 30 s lifetime (milliseconds).
FragmentLimits BusFragmentLimits(int64_t cells);

}  // namespace dynapath::protocol
