#include "dynapath/results_csv.h"

#include <cstdio>
#include <filesystem>

#include "dynapath/text_file.h"

namespace dynapath {
namespace {

std::string Number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::string Prefix(const ApproachRun& run) {
  return run.Label() + "," + run.size_label + "," + run.difficulty_label;
}

}  // namespace

std::string DetailedResultsCsv(const std::vector<ApproachRun>& runs) {
  std::string csv =
      "Approach,Size,Difficulty,TimeStep,NumChanges,AdaptTime,SuccessRate,AvgPathLength,"
      "NodesTrained,HighestLevel\n";
  for (const ApproachRun& run : runs) {
    for (const StepRecord& step : run.steps) {
      csv += Prefix(run) + "," + std::to_string(step.time_step) + "," +
             std::to_string(step.num_changes) + "," + Number(step.adapt_seconds) + "," +
             Number(step.success_rate) + "," + Number(step.average_path_length) + "," +
             std::to_string(step.nodes_trained) + "," + std::to_string(step.highest_level) + "\n";
    }
  }
  return csv;
}

std::string SummaryResultsCsv(const std::vector<ApproachRun>& runs) {
  std::string csv =
      "Approach,Size,Difficulty,InitialTime,AdaptTimePerStep,AvgSuccessRate,AvgPathLength\n";
  for (const ApproachRun& run : runs) {
    csv += Prefix(run) + "," + Number(run.initial_seconds) + "," +
           Number(run.AdaptSecondsPerStep()) + "," + Number(run.AverageSuccessRate()) + "," +
           Number(run.AveragePathLength()) + "\n";
  }
  return csv;
}

Status WriteResultFiles(const std::vector<ApproachRun>& runs, const std::string& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error) return Error::Io(directory + ": cannot create directory: " + error.message());
  Status status =
      WriteTextFileAtomically(directory + "/results_detailed.csv", DetailedResultsCsv(runs));
  if (!status) return status;
  return WriteTextFileAtomically(directory + "/results.csv", SummaryResultsCsv(runs));
}

}  // namespace dynapath
