// The spread of a learning approach over learner seed streams on one maze.
//
// The report's code is not deterministic from run to run (SPEC section 10),
// so comparing one of our runs with its runs compares two draws; this runs
// the same maze and change sequence with N learner streams and prints each
// stream's summary (SPEC section 9), so the report code's runs can be placed
// inside or outside our spread. Stream 0 is `dynapath run`'s (run seed =
// maze seed); stream k > 0 uses run seed = maze seed + k * 1000003, which
// changes every learner's random numbers and nothing else.
//
// Usage: semantics_spread SIZE DIFFICULTY SEED APPROACH STREAMS [ours|report|report-float] [DETAIL_CSV]
//   e.g. semantics_spread 50 hard 102 fedAsynQ_ImAvg 7 report
// report-float: the report code's rules with our float tables instead of its
// double ones (not a run option: it separates what the precision does).
// DETAIL_CSV, if given, receives every stream's per-step rows.

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/experiment.h"
#include "dynapath/local_trainer.h"
#include "dynapath/parameters.h"
#include "dynapath/scenario.h"
#include "dynapath/thread_pool.h"

namespace {

int Usage() {
  std::fprintf(stderr,
               "usage: semantics_spread SIZE easy|medium|hard SEED APPROACH STREAMS "
               "[ours|report|report-float] [DETAIL_CSV]\n");
  return 2;
}

// A whole decimal number in [low, high], or nothing.
std::optional<long> Number(const char* text, long low, long high) {
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno != 0 || value < low || value > high) return {};
  return value;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace dynapath;
  if (argc < 6 || argc > 8) return Usage();
  const std::optional<long> size = Number(argv[1], 2, 4096);
  const std::string difficulty_name = argv[2];
  const std::optional<long> seed = Number(argv[3], 0, 0xFFFFFFFFL);
  const std::optional<Approach> approach = ParseApproach(argv[4]);
  const std::optional<long> streams = Number(argv[5], 1, 1000);
  const std::string semantics = argc >= 7 ? argv[6] : "report";
  Difficulty difficulty;
  if (difficulty_name == "easy") {
    difficulty = Difficulty::kEasy;
  } else if (difficulty_name == "medium") {
    difficulty = Difficulty::kMedium;
  } else if (difficulty_name == "hard") {
    difficulty = Difficulty::kHard;
  } else {
    return Usage();
  }
  if (!size || !seed || !approach || !streams || (semantics != "ours" && semantics != "report" && semantics != "report-float")) {
    return Usage();
  }
  std::ofstream detail;
  if (argc == 8) {
    detail.open(argv[7]);
    if (!detail) {
      std::fprintf(stderr, "cannot write %s\n", argv[7]);
      return 1;
    }
    detail << "Stream,TimeStep,NumChanges,SuccessRate,AvgPathLength,NodesRetrained,HighestLevel\n";
  }

  const int rows = static_cast<int>(*size);
  const Scenario scenario = GenerateScenario(rows, rows, difficulty, static_cast<unsigned>(*seed));
  ThreadPool pool(1);
  LocalTrainer trainer(pool);
  const char* difficulty_label[] = {"Easy", "Medium", "Hard"};
  const RunLabels labels{std::to_string(rows), difficulty_label[static_cast<int>(difficulty)]};
  std::vector<double> success, length;
  std::printf("Stream,RunSeed,AvgSuccessRate,AvgPathLength,NodesTrained\n");
  for (long k = 0; k < *streams; ++k) {
    PlannerOptions options;
    options.run_seed = static_cast<uint64_t>(*seed) + static_cast<uint64_t>(k) * 1000003u;
    options.semantics = semantics == "ours" ? Semantics::kOurs : Semantics::kReport;
    // As `dynapath run --semantics report`: the report's parameter values.
    if (options.semantics == Semantics::kReport) ApplyReportPreset(options);
    if (semantics == "report-float") options.table_precision = QPrecision::kFloat;
    const ApproachRun run = RunApproach(scenario, *approach, options, &trainer, labels);
    int trained = 0;
    for (const StepRecord& step : run.steps) {
      trained += step.nodes_trained;
      if (detail) {
        detail << k << ',' << step.time_step << ',' << step.num_changes << ',' << step.success_rate
               << ',' << step.average_path_length << ',' << step.nodes_trained << ','
               << step.highest_level << '\n';
      }
    }
    success.push_back(run.AverageSuccessRate());
    length.push_back(run.AveragePathLength());
    std::printf("%ld,%llu,%.4f,%.3f,%d\n", k, static_cast<unsigned long long>(options.run_seed),
                success.back(), length.back(), trained);
    std::fflush(stdout);
  }
  std::printf("# success min %.4f median %.4f max %.4f; path min %.3f median %.3f max %.3f\n",
              *std::min_element(success.begin(), success.end()), Median(success),
              *std::max_element(success.begin(), success.end()),
              *std::min_element(length.begin(), length.end()), Median(length),
              *std::max_element(length.begin(), length.end()));
  return 0;
}
