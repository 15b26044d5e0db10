#include <spdlog/spdlog.h>

#include <cstdio>
#include <thread>

#include "core/experiment.h"
#include "core/local_trainer.h"
#include "core/results_csv.h"
#include "core/thread_pool.h"
#include "tools/cli/commands.h"
#include "tools/cli/scenario_options.h"

namespace dynapath::cli {
namespace {

// Logs one line per approach every few seconds, and at its end.
class ProgressLog {
 public:
  explicit ProgressLog(Clock clock) : clock_(std::move(clock)) {}

  void operator()(const ApproachRun& run, int total_steps) {
    const int step = run.steps.back().time_step;
    const double now = clock_();
    const bool finished = step == total_steps;
    if (!finished && step != 0 && now - last_ < kIntervalSeconds) return;
    last_ = now;
    const StepRecord& record = run.steps.back();
    if (step == 0) {
      spdlog::info("{} {} {}: initial training {:.3f} s, success rate {:.4f}, path length {:.3f}",
                   ApproachName(run.approach), run.size_label, run.difficulty_label,
                   run.initial_seconds, record.success_rate, record.average_path_length);
    } else {
      spdlog::info("{} {} {}: step {}/{}, success rate {:.4f}, adaptation {:.4f} s/step",
                   ApproachName(run.approach), run.size_label, run.difficulty_label, step,
                   total_steps, record.success_rate, run.AdaptSecondsPerStep());
    }
  }

 private:
  static constexpr double kIntervalSeconds = 2.0;
  Clock clock_;
  double last_ = 0.0;
};

}  // namespace

int RunCommand(const std::vector<std::string>& args) {
  ArgParser parser(
      "dynapath run [--local] [options]",
      "Runs the chosen approaches on one shared maze and change sequence and writes\n"
      "DIR/results.csv and DIR/results_detailed.csv (the report's columns).\n"
      "--local runs everything in this process on a thread pool (the only mode so far).");
  parser.AddFlag("local", "run in this process (default)");
  AddScenarioOptions(parser);
  parser.AddOption("approach", "LIST",
                   "comma-separated approaches: A* Static, A* Oracle, BFS Oracle, "
                   "onlyTrainLeafNodes, singleAgent, fedAsynQ_EqAvg, fedAsynQ_ImAvg; or all",
                   "all");
  parser.AddOption("threads", "N", "worker threads (results do not depend on it)",
                   "hardware threads");
  parser.AddOption("out", "DIR", "output directory", "results");
  parser.AddOption("leaf-limit", "N", "largest quadtree leaf side", "20");
  parser.AddOption(
      "bootstrap", "SCOPE",
      "actions the Q-update's max ranges over: in-grid or in-region (docs/DECISIONS.md)",
      "in-grid");
  AddLogLevelOption(parser);
  auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "dynapath run: %s\n", message.c_str());
    return kExitUsage;
  };
  if (Status status = parser.Parse(args); !status) return usage_error(status.error().message);
  if (parser.WantsHelp()) {
    std::fputs(parser.Help().c_str(), stdout);
    return 0;
  }
  if (Status status = ApplyLogLevel(parser); !status) return usage_error(status.error().message);
  Result<std::vector<Approach>> approaches = ParseApproachList(parser.Get("approach", "all"));
  if (!approaches) return usage_error(approaches.error().message);
  const long long hardware = std::max(1u, std::thread::hardware_concurrency());
  Result<long long> threads = parser.GetInt("threads", hardware, 1, 1024);
  if (!threads) return usage_error(threads.error().message);
  Result<long long> leaf_limit = parser.GetInt("leaf-limit", QuadTree::kDefaultLeafLimit, 1, 10000);
  if (!leaf_limit) return usage_error(leaf_limit.error().message);
  Result<ScenarioSetup> setup = ResolveScenario(parser);
  if (!setup) return usage_error(setup.error().message);
  const std::string out = parser.Get("out", "results");
  const std::string bootstrap = parser.Get("bootstrap", "in-grid");
  if (bootstrap != "in-grid" && bootstrap != "in-region") {
    return usage_error("option --bootstrap must be in-grid or in-region, got '" + bootstrap + "'");
  }

  PlannerOptions options;
  options.run_seed = setup->seed;
  options.leaf_limit = static_cast<int>(*leaf_limit);
  options.bootstrap = bootstrap == "in-grid" ? Bootstrap::kInGrid : Bootstrap::kInRegion;
  spdlog::info("maze {} {} ({}), {} time steps, {} approaches, {} threads",
               setup->labels.size_label, setup->labels.difficulty_label, setup->source,
               setup->scenario.changes.steps.size(), approaches->size(), *threads);

  ThreadPool pool(static_cast<int>(*threads));
  LocalTrainer trainer(pool);
  std::vector<ApproachRun> runs;
  for (Approach approach : *approaches) {
    ProgressLog progress(SteadyClock());
    runs.push_back(RunApproach(setup->scenario, approach, options, &trainer, setup->labels,
                               SteadyClock(), std::ref(progress)));
    const ApproachRun& run = runs.back();
    spdlog::info(
        "{}: initial {:.3f} s, adaptation {:.4f} s/step, success rate {:.4f}, path length {:.3f}",
        ApproachName(approach), run.initial_seconds, run.AdaptSecondsPerStep(),
        run.AverageSuccessRate(), run.AveragePathLength());
    // Written after every approach, so an interrupted run keeps what finished.
    if (Status status = WriteResultFiles(runs, out); !status) {
      spdlog::error("{}", status.error().message);
      return kExitFailure;
    }
  }
  std::printf("%s", SummaryResultsCsv(runs).c_str());
  spdlog::info("wrote {}/results.csv and {}/results_detailed.csv", out, out);
  return 0;
}

}  // namespace dynapath::cli
