#pragma once
// Goal requests of `dynapath serve` (goal_request_t -> goal_reply_t): exact
// shortest paths from starts to any goal on the service's current map
// (core's GoalPlanner: hot goals from repaired goal-rooted fields in a
// byte-bounded cache, cold ones by A*), with goals and starts as cells,
// poses in metres in the map's frame, or names from a goals file.
//
// The map follows the PathService's commits (OnCommit, the training
// thread): each committed snapshot's grid becomes the planner's grid, the
// cells that differ from the previous one its changed cells. A reply names
// the version of the commit whose grid it was answered on. Answer may run
// on any thread; one at a time (a mutex, shared with OnCommit).

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "dynapath/goal_paths.h"
#include "dynapath/goal_reply_t.hpp"
#include "dynapath/goal_request_t.hpp"
#include "dynapath/latency_histogram.h"
#include "dynapath/routes.h"
#include "runtime/option_group.h"

namespace dynapath::runtime {

struct GoalServiceConfig {
  GoalPlannerOptions planner;
  MapFrame frame;  // rows and cols: the service's grid
  std::vector<NamedGoal> goals;
  int max_starts = 64;                    // cells and poses together
  size_t reply_budget = size_t{1} << 20;  // path cells of one reply
};

struct GoalServiceStats {
  int64_t requests = 0;
  int64_t refused_too_many_starts = 0;
  int64_t refused_not_ready = 0;
  int64_t by_goal[kGoalCheckCount] = {};     // GoalCheck of each accepted request
  int64_t by_status[kGoalStatusCount] = {};  // GoalStatus of each start answered
  int64_t by_field = 0, by_search = 0;       // of the reached ones
  GoalCacheStats cache;
  LatencyHistogram latency;  // request received to reply sent, microseconds
};

class GoalService {
 public:
  explicit GoalService(GoalServiceConfig config);

  // The PathService's commit (its grid hook): the grid of `snapshot` from
  // now on, repairs driven by the cells that changed since the last one.
  void OnCommit(const std::shared_ptr<const RouteSnapshot>& snapshot);
  // The reply to `request` (its run_id and maze_fingerprint left for the
  // caller), counted.
  goal_reply_t Answer(const goal_request_t& request);
  void RecordLatency(int64_t micros);
  GoalServiceStats stats() const;
  const MapFrame& frame() const { return config_.frame; }
  // Lines for the service's summary at stop.
  static std::string Summary(const GoalServiceStats& stats);

 private:
  GoalServiceConfig config_;
  std::map<std::string, std::pair<int, int>> named_;  // name -> cell
  mutable std::mutex mutex_;                          // guards everything below
  GoalPlanner planner_;
  std::shared_ptr<const RouteSnapshot> snapshot_;  // the grid's owner
  int64_t version_ = 0;
  int time_step_ = 0;
  std::vector<int> changed_;  // scratch
  GoalServiceStats stats_;
};

// dynapath serve's options of goals and metres.
struct GoalOptions {
  std::optional<std::string> goals_file;
  std::optional<double> cache_mb;
  std::optional<double> resolution;
  std::optional<std::string> origin;
};
void DeclareGoalOptions(OptionGroup& group, GoalOptions& options);
// --resolution and --origin: the frame of a map without one (serve's, and
// the commands that publish to it in metres).
void DeclareMapFrameOptions(OptionGroup& group, std::optional<double>& resolution,
                            std::optional<std::string>& origin);
// The goal service's configuration (max_starts left at its default), or
// one clear error. `maze_path`: --maze (a ROS map has its own frame).
Result<GoalServiceConfig> ResolveGoalOptions(const GoalOptions& options,
                                             const std::optional<std::string>& maze_path,
                                             const Grid& grid);

// The map's frame: a ROS map_server YAML's resolution and origin when
// `maze_path` is one (then --resolution and --origin are refused), else
// `resolution` (default 1 m) and `origin` ("X,Y", default 0,0).
Result<MapFrame> ResolveMapFrame(const std::optional<std::string>& maze_path,
                                 const std::optional<double>& resolution,
                                 const std::optional<std::string>& origin, const Grid& grid);

// A goals file (ParseGoalsText), every goal in the map: metres turned into
// cells by `frame`; one clear error naming the file and goal otherwise.
Result<std::vector<NamedGoal>> LoadGoalsFile(const std::string& path, const MapFrame& frame);

}  // namespace dynapath::runtime
