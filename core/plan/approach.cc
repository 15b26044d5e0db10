#include "dynapath/approach.h"

#include <algorithm>

#include "core/plan/approach_registry.h"
#include "dynapath/text_util.h"

namespace dynapath {

const std::vector<Approach>& RegisteredApproaches() {
  static const std::vector<Approach> registered = [] {
    std::vector<Approach> approaches;
    for (const ApproachSpec& spec : ApproachRegistry()) approaches.push_back(spec.approach);
    return approaches;
  }();
  return registered;
}

const std::vector<Approach>& AllApproaches() {
  static const std::vector<Approach> all = [] {
    static constexpr Approach kOutside[] = {
#define DYNAPATH_OUTSIDE_ALL(id) Approach::id,
        DYNAPATH_APPROACHES_OUTSIDE_ALL(DYNAPATH_OUTSIDE_ALL)
#undef DYNAPATH_OUTSIDE_ALL
    };
    std::vector<Approach> approaches;
    for (Approach approach : RegisteredApproaches()) {
      if (std::find(std::begin(kOutside), std::end(kOutside), approach) == std::end(kOutside)) {
        approaches.push_back(approach);
      }
    }
    return approaches;
  }();
  return all;
}

std::string ApproachName(Approach approach) { return GetApproachSpec(approach).name; }

std::optional<Approach> ParseApproach(const std::string& name) {
  const std::string wanted = ToLower(Trim(name));
  for (Approach approach : RegisteredApproaches()) {
    if (ToLower(ApproachName(approach)) == wanted) return approach;
  }
  return std::nullopt;
}

std::string ApproachNamesText() {
  std::string names;
  for (Approach a : RegisteredApproaches()) names += (names.empty() ? "" : ", ") + ApproachName(a);
  return names;
}

Result<std::vector<Approach>> ParseApproachList(const std::string& list) {
  return ParseApproachList(Split(list, ','));
}

Result<std::vector<Approach>> ParseApproachList(const std::vector<std::string>& names) {
  if (names.size() == 1 && ToLower(Trim(names.front())) == "all") return AllApproaches();
  std::vector<Approach> approaches;
  for (const std::string& name : names) {
    const std::string piece = Trim(name);
    const std::optional<Approach> approach = ParseApproach(piece);
    if (!approach) {
      return Error{"unknown approach '" + piece + "' (expected one of: " + ApproachNamesText() +
                   ", or all)"};
    }
    if (std::find(approaches.begin(), approaches.end(), *approach) == approaches.end()) {
      approaches.push_back(*approach);
    }
  }
  return approaches;
}

bool IsLearningApproach(Approach approach) { return GetApproachSpec(approach).learner.has_value(); }

}  // namespace dynapath
