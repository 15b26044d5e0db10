#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <optional>

#include "dynapath/astar_paths.h"
#include "dynapath/bfs_oracle.h"
#include "dynapath/quadtree.h"
#include "runtime/output_check.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {
namespace {

// The grid as `--save` writes it, but with every obstacle that moves during
// the run's time steps (its cell changes in the change sequence) printed
// `o`, walls staying `#`; then a legend line. The saved file keeps `#` for
// both: its format is that of every maze file.
std::string GridPrintout(const Grid& grid, const ChangeSequence& changes) {
  std::vector<uint8_t> moving(static_cast<size_t>(grid.rows()) * grid.cols(), 0);
  for (const ChangeStep& step : changes.steps) {
    for (const CellChange& change : step.changes) {
      if (change.cell >= 0 && static_cast<size_t>(change.cell) < moving.size()) {
        moving[static_cast<size_t>(change.cell)] = 1;
      }
    }
  }
  std::string text = GridToText(grid);
  size_t cell = 0;
  bool any = false;
  for (char& ch : text) {
    if (ch == '\n') continue;
    if (ch == '#' && moving[cell]) {
      ch = 'o';
      any = true;
    }
    ++cell;
  }
  text += std::string("legend: # obstacle that never moves") +
          (any ? ", o obstacle that moves during the time steps" : "") + ", . free, C station\n";
  return text;
}

}  // namespace

int MazeCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Generates (or loads) a maze and prints it (# obstacle, o an obstacle that moves\n"
      "during the time steps, . free, C station; --save writes # for both) with its\n"
      "facts: cells of each kind,\n"
      "quadtree leaves and levels, and the optimal success rate and average path\n"
      "length at time step 0.",
      "dynapath maze");
  runtime::OptionGroup group(app);
  runtime::ScenarioOptions scenario;
  runtime::DeclareScenarioOptions(group, scenario);
  long long leaf_limit_given = QuadTree::kDefaultLeafLimit;
  runtime::DeclareLeafLimitOption(group, leaf_limit_given);
  std::optional<std::string> save, save_changes;
  group.Option("--save", save, "FILE", "write the maze to FILE in the text format");
  group.Option("--save-changes", save_changes, "FILE", "write the change sequence to FILE");
  bool no_grid = false;
  group.Flag("--no-grid", no_grid, "do not print the grid itself");
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  if (int code = runtime::ParseCommandLine(app, args, "dynapath maze"); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    std::fprintf(stderr, "dynapath maze: %s\n", status.error().message.c_str());
    return kExitUsage;
  }
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(scenario);
  if (!setup) {
    std::fprintf(stderr, "dynapath maze: %s\n", setup.error().message.c_str());
    return kExitUsage;
  }
  Result<int> leaf_limit = runtime::ResolveLeafLimit(leaf_limit_given);
  if (!leaf_limit) {
    std::fprintf(stderr, "dynapath maze: %s\n", leaf_limit.error().message.c_str());
    return kExitUsage;
  }
  // Outputs checked before anything is written.
  for (const auto& [option, path] :
       {std::pair{"save", &save}, std::pair{"save-changes", &save_changes}}) {
    if (!*path) continue;
    if (Status status = runtime::CheckOutputFile(**path, option); !status) {
      std::fprintf(stderr, "dynapath maze: %s\n", status.error().message.c_str());
      return kExitUsage;
    }
  }
  const Grid& grid = setup->scenario.grid;
  if (save) {
    if (Status status = SaveGrid(grid, *save); !status) {
      std::fprintf(stderr, "dynapath maze: %s\n", status.error().message.c_str());
      return kExitFailure;
    }
  }
  if (save_changes) {
    if (Status status = SaveChanges(setup->scenario.changes, grid, *save_changes); !status) {
      std::fprintf(stderr, "dynapath maze: %s\n", status.error().message.c_str());
      return kExitFailure;
    }
  }
  if (!no_grid) std::fputs(GridPrintout(grid, setup->scenario.changes).c_str(), stdout);

  const QuadTree tree(grid.rows(), grid.cols(), static_cast<int>(*leaf_limit));
  int leaves_without_station = 0;
  for (NodeId leaf : tree.leaves()) {
    const Region& region = tree.node(leaf).region;
    bool has_station = false;
    for (int r = region.r0; r <= region.r1 && !has_station; ++r) {
      for (int c = region.c0; c <= region.c1 && !has_station; ++c) {
        has_station = grid.at(r, c) == Cell::kStation;
      }
    }
    if (!has_station) ++leaves_without_station;
  }
  std::vector<int32_t> distance, queue;
  NearestStationDistances(grid, distance, queue);
  const PolicyScore optimum = ScoreDistances(grid, distance);
  size_t moves = 0;
  for (const ChangeStep& step : setup->scenario.changes.steps) moves += step.changes.size() / 2;

  std::printf("maze:            %s, %d x %d, %s\n", setup->source.c_str(), grid.rows(), grid.cols(),
              setup->labels.difficulty_label.c_str());
  std::printf("cells:           %d free, %d obstacles, %d stations\n", grid.Count(Cell::kFree),
              grid.Count(Cell::kObstacle), grid.Count(Cell::kStation));
  std::printf(
      "quadtree:        %d levels, %d nodes, %d leaves (%d without a station), leaf limit %d\n",
      tree.level_count(), tree.node_count(), static_cast<int>(tree.leaves().size()),
      leaves_without_station, *leaf_limit);
  std::printf("optimum, step 0: success rate %g, average path length %g (%d of %d starts)\n",
              optimum.success_rate(), optimum.average_path_length(), optimum.successes,
              optimum.starts);
  std::printf("changes:         %zu time steps, %zu obstacle moves\n",
              setup->scenario.changes.steps.size(), moves);
  return 0;
}

}  // namespace dynapath::cli
