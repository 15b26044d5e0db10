#include "core/approach.h"

#include <algorithm>

#include "core/text_util.h"

namespace dynapath {

const std::vector<Approach>& AllApproaches() {
  static const std::vector<Approach> all = {Approach::kAStarStatic,   Approach::kAStarOracle,
                                            Approach::kBfsOracle,     Approach::kOnlyTrainLeafNodes,
                                            Approach::kSingleAgent,   Approach::kFedAsynQEqAvg,
                                            Approach::kFedAsynQImAvg, Approach::kIncrementalOracle};
  return all;
}

std::string ApproachName(Approach approach) {
  switch (approach) {
    case Approach::kAStarStatic:
      return "A* Static";
    case Approach::kAStarOracle:
      return "A* Oracle";
    case Approach::kBfsOracle:
      return "BFS Oracle";
    case Approach::kOnlyTrainLeafNodes:
      return "onlyTrainLeafNodes";
    case Approach::kSingleAgent:
      return "singleAgent";
    case Approach::kFedAsynQEqAvg:
      return "fedAsynQ_EqAvg";
    case Approach::kFedAsynQImAvg:
      return "fedAsynQ_ImAvg";
    case Approach::kIncrementalOracle:
      return "Incremental Oracle";
  }
  return "?";
}

std::optional<Approach> ParseApproach(const std::string& name) {
  const std::string wanted = ToLower(Trim(name));
  for (Approach approach : AllApproaches()) {
    if (ToLower(ApproachName(approach)) == wanted) return approach;
  }
  return std::nullopt;
}

Result<std::vector<Approach>> ParseApproachList(const std::string& list) {
  if (ToLower(Trim(list)) == "all") return AllApproaches();
  std::vector<Approach> approaches;
  for (const std::string& piece : Split(list, ',')) {
    const std::optional<Approach> approach = ParseApproach(piece);
    if (!approach) {
      std::string names;
      for (Approach a : AllApproaches()) names += (names.empty() ? "" : ", ") + ApproachName(a);
      return Error{"unknown approach '" + piece + "' (expected one of: " + names + ", or all)"};
    }
    if (std::find(approaches.begin(), approaches.end(), *approach) == approaches.end()) {
      approaches.push_back(*approach);
    }
  }
  return approaches;
}

bool IsLearningApproach(Approach approach) {
  return approach == Approach::kOnlyTrainLeafNodes || approach == Approach::kSingleAgent ||
         approach == Approach::kFedAsynQEqAvg || approach == Approach::kFedAsynQImAvg;
}

}  // namespace dynapath
