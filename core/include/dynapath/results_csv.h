#pragma once
// The two result files of SPEC section 9, in the report's columns.
//
// results_detailed.csv:
//   Approach,Size,Difficulty,TimeStep,NumChanges,AdaptTime,SuccessRate,
//   AvgPathLength,NodesTrained,HighestLevel
// results.csv:
//   Approach,Size,Difficulty,InitialTime,AdaptTimePerStep,AvgSuccessRate,
//   AvgPathLength
// Times are seconds. Numbers are written with 10 significant digits.

#include <string>
#include <vector>

#include "dynapath/experiment.h"
#include "dynapath/result.h"

namespace dynapath {

std::string DetailedResultsCsv(const std::vector<ApproachRun>& runs);
std::string SummaryResultsCsv(const std::vector<ApproachRun>& runs);

// Writes DIR/results.csv and DIR/results_detailed.csv atomically (creating DIR).
Status WriteResultFiles(const std::vector<ApproachRun>& runs, const std::string& directory);

}  // namespace dynapath
