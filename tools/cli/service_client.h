#pragma once
// The CLI's side of a client of `dynapath serve` (query, feed, robots): the
// client itself is runtime's (runtime/service_client.h, shared with the
// Python module); here its --timeout option and --from cells.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "dynapath/change_sequence.h"
#include "dynapath/goal_paths.h"
#include "dynapath/grid.h"
#include "dynapath/result.h"
#include "runtime/option_group.h"
#include "runtime/service_client.h"

namespace dynapath::cli {

using runtime::kSecondReplySeconds;
using runtime::ServiceClient;

// --timeout of query and feed: how long to wait for the service.
void DeclareServiceWaitOption(runtime::OptionGroup& group, double& seconds);
// --source of the commands that publish obstacle updates (feed, query);
// `default_text` is the help's default ("feed-PID").
void DeclareUpdateSourceOption(runtime::OptionGroup& group, std::optional<std::string>& source,
                               const std::string& default_text);
// --xy, --resolution and --origin of the commands that publish a change
// sequence (feed, robots): obstacle changes in metres instead of cells.
struct MetresOptions {
  bool xy = false;
  std::optional<double> resolution;
  std::optional<std::string> origin;
};
void DeclareMetresOptions(runtime::OptionGroup& group, MetresOptions& options);
// The map's frame when --xy is given (the service's: a ROS map's YAML via
// `maze_path`, else --resolution and --origin, as serve resolves them),
// nullopt without --xy; an error for a bad frame, or --resolution or
// --origin without --xy.
Result<std::optional<MapFrame>> ResolveMetresOptions(const MetresOptions& options,
                                                     const std::optional<std::string>& maze_path,
                                                     const Grid& grid);
// Publishes one time step's changes of `grid` as the `sequence`-th update
// of `source` for the maze of fingerprint `maze`: an obstacle_update_t on
// MAP_UPDATES, or with a frame an obstacle_points_t on MAP_POINTS whose
// points are the changed cells' centres, in the step's order.
void PublishStep(ServiceClient& client, const ChangeStep& step, const Grid& grid,
                 const std::optional<MapFrame>& frame, const std::string& source, int64_t sequence,
                 uint64_t maze, int64_t utime);

// "R,C" as a cell, or an error naming the option.
Result<std::pair<int32_t, int32_t>> ParseCell(const std::string& text);

}  // namespace dynapath::cli
