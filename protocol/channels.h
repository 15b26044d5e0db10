#pragma once
// Channel names and run ids. Every channel of a run is DYNAPATH/<run>/<NAME>,
// so lcm-logger / lcm-spy can pick one run with the regex DYNAPATH/<run>/.*
// and two runs on one network never mix.

#include <string>
#include <string_view>

#include "dynapath/result.h"

namespace dynapath::protocol {

namespace channel {
inline constexpr std::string_view kHeartbeat = "HEARTBEAT";
inline constexpr std::string_view kEnvRequest = "ENV_REQUEST";
inline constexpr std::string_view kEnvGrid = "ENV_GRID";
inline constexpr std::string_view kEnvChanges = "ENV_CHANGES";
inline constexpr std::string_view kJobs = "JOBS";
inline constexpr std::string_view kShards = "SHARDS";
inline constexpr std::string_view kResults = "RESULTS";
inline constexpr std::string_view kReport = "REPORT";
inline constexpr std::string_view kPolicy = "POLICY";
// dynapath serve (docs/howto/SERVICE.md): obstacle updates (cells, or
// points in metres) and occupancy grids in, path requests in and replies out.
inline constexpr std::string_view kMapUpdates = "MAP_UPDATES";
inline constexpr std::string_view kMapPoints = "MAP_POINTS";
inline constexpr std::string_view kMapGrid = "MAP_GRID";
inline constexpr std::string_view kPathRequest = "PATH_REQUEST";
inline constexpr std::string_view kPathReply = "PATH_REPLY";
// Goal requests in (goal_request_t) and their replies out (goal_reply_t).
inline constexpr std::string_view kGoalRequest = "GOAL_REQUEST";
inline constexpr std::string_view kGoalReply = "GOAL_REPLY";
// Federated training of convQ's model (dynapath train-model --agents N):
// rounds out (model_round_t), learners' parameter shards back (model_shards_t).
inline constexpr std::string_view kModelRound = "MODEL_ROUND";
inline constexpr std::string_view kModelShards = "MODEL_SHARDS";
// Selective repair of fragmented messages (any channel's): fragment_nack_t.
inline constexpr std::string_view kFragmentNack = "FRAGMENT_NACK";
}  // namespace channel

// Rounds of its own shards an agent keeps to re-send (SHARDS, needs_round):
// a coordinator lagging further behind restarts the round.
inline constexpr int kAgentKeptRounds = 32;

// "DYNAPATH/<run>/<name>".
std::string ChannelName(std::string_view run_id, std::string_view name);

// Run ids are 1-64 characters of [A-Za-z0-9_-]: safe in channel regexes,
// file names and shell commands.
Status CheckRunId(std::string_view run_id);

// A fresh run id from the clock and the process id ("r20261122-153012-4242").
std::string NewRunId();

}  // namespace dynapath::protocol
