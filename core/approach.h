#pragma once
// The seven approaches of SPEC section 9 and the Incremental Oracle (issue
// 11), by their exact result-file names.

#include <optional>
#include <string>
#include <vector>

#include "core/result.h"

namespace dynapath {

enum class Approach {
  kAStarStatic,
  kAStarOracle,
  kBfsOracle,
  kOnlyTrainLeafNodes,
  kSingleAgent,
  kFedAsynQEqAvg,
  kFedAsynQImAvg,
  kIncrementalOracle,  // BFS Oracle's figures, repaired per step (not in the report)
};

// All approaches in the order of SPEC section 9, then the Incremental Oracle
// (the order of `all`).
const std::vector<Approach>& AllApproaches();

// "A* Static", "A* Oracle", "BFS Oracle", "onlyTrainLeafNodes",
// "singleAgent", "fedAsynQ_EqAvg", "fedAsynQ_ImAvg", "Incremental Oracle".
std::string ApproachName(Approach approach);

// Case-insensitive exact name.
std::optional<Approach> ParseApproach(const std::string& name);

// Comma-separated names, or "all". Duplicates are dropped, order is kept.
Result<std::vector<Approach>> ParseApproachList(const std::string& list);

// True for the four Q-learning approaches.
bool IsLearningApproach(Approach approach);

}  // namespace dynapath
