#include "tools/cli/service_client.h"

#include <optional>

#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/obstacle_update_t.hpp"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "runtime/goal_service.h"

namespace dynapath::cli {

void DeclareServiceWaitOption(runtime::OptionGroup& group, double& seconds) {
  group.Option("--timeout", seconds, "SECONDS",
               "how long to wait for the service (a reply, its first policy, each commit)");
}

void DeclareUpdateSourceOption(runtime::OptionGroup& group, std::optional<std::string>& source,
                               const std::string& default_text) {
  group.Option("--source", source, "NAME",
               "the updates' source name (1-64 characters; sequence numbers count per source)",
               default_text);
}

void DeclareMetresOptions(runtime::OptionGroup& group, MetresOptions& options) {
  group.Flag("--xy", options.xy,
             "publish the obstacle changes in metres (obstacle_points_t on MAP_POINTS: each "
             "changed cell's centre in the map's frame, a ROS map's own or --resolution and "
             "--origin as given to serve) instead of cells (obstacle_update_t on MAP_UPDATES)");
  runtime::DeclareMapFrameOptions(group, options.resolution, options.origin);
}

Result<std::optional<MapFrame>> ResolveMetresOptions(const MetresOptions& options,
                                                     const std::optional<std::string>& maze_path,
                                                     const Grid& grid) {
  if (!options.xy) {
    if (options.resolution || options.origin) {
      return Error("--resolution and --origin need --xy (updates in metres)");
    }
    return std::optional<MapFrame>{};
  }
  Result<MapFrame> frame =
      runtime::ResolveMapFrame(maze_path, options.resolution, options.origin, grid);
  if (!frame) return frame.error();
  return std::optional<MapFrame>{*frame};
}

void PublishStep(ServiceClient& client, const ChangeStep& step, const Grid& grid,
                 const std::optional<MapFrame>& frame, const std::string& source, int64_t sequence,
                 uint64_t maze, int64_t utime) {
  if (!frame) {
    obstacle_update_t update = protocol::UpdateToMessage(step, grid.cols(), source, sequence, maze);
    update.run_id = client.bus().run_id();
    update.utime = utime;
    client.bus().Publish(protocol::channel::kMapUpdates, update);
    return;
  }
  obstacle_points_t points{};
  points.run_id = client.bus().run_id();
  points.source = source;
  points.sequence = sequence;
  points.utime = utime;
  points.maze_fingerprint = static_cast<int64_t>(maze);
  for (const CellChange& change : step.changes) {
    points.x.push_back(frame->X(change.cell % grid.cols()));
    points.y.push_back(frame->Y(change.cell / grid.cols()));
    points.states.push_back(change.code == Cell::kObstacle ? obstacle_points_t::OBSTACLE
                                                           : obstacle_points_t::FREE);
  }
  points.num_points = static_cast<int32_t>(points.x.size());
  client.bus().Publish(protocol::channel::kMapPoints, points);
}

Result<std::pair<int32_t, int32_t>> ParseCell(const std::string& text) {
  const size_t comma = text.find(',');
  auto number = [](const std::string& part) -> std::optional<int32_t> {
    if (part.empty() || part.size() > 9) return std::nullopt;
    size_t i = part[0] == '-' ? 1 : 0;
    if (i == part.size()) return std::nullopt;
    for (size_t k = i; k < part.size(); ++k) {
      if (part[k] < '0' || part[k] > '9') return std::nullopt;
    }
    return static_cast<int32_t>(std::stol(part));
  };
  if (comma != std::string::npos) {
    const auto row = number(text.substr(0, comma));
    const auto col = number(text.substr(comma + 1));
    if (row && col) return std::make_pair(*row, *col);
  }
  return Error::Option("from", "must be ROW,COL (two integers), got '" + text + "'");
}

}  // namespace dynapath::cli
