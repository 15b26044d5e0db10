#pragma once
// The approaches by their exact result-file names. The list itself is
// core/include/dynapath/approach_list.h; what each approach is made of,
// core/plan/approach_registry.h.

#include <optional>
#include <string>
#include <vector>

#include "dynapath/approach_list.h"
#include "dynapath/result.h"

namespace dynapath {

// One enumerator per line of core/include/dynapath/approach_list.h.
enum class Approach {
#define DYNAPATH_APPROACH_ENUMERATOR(id, ...) id,
  DYNAPATH_APPROACHES(DYNAPATH_APPROACH_ENUMERATOR)
#undef DYNAPATH_APPROACH_ENUMERATOR
};

// The approaches of `all`, in the order of core/include/dynapath/approach_list.h
// (SPEC section 9's, then ours), without DYNAPATH_APPROACHES_OUTSIDE_ALL's.
const std::vector<Approach>& AllApproaches();
// Every registered approach (`all` and those named explicitly only).
const std::vector<Approach>& RegisteredApproaches();

// The result-file name ("A* Static", "fedAsynQ_EqAvg", ...).
std::string ApproachName(Approach approach);

// Case-insensitive exact name.
std::optional<Approach> ParseApproach(const std::string& name);

// Comma-separated names, or "all". Duplicates are dropped, order is kept.
Result<std::vector<Approach>> ParseApproachList(const std::string& list);
// The same of a list's items (each trimmed): names, or the one item "all".
Result<std::vector<Approach>> ParseApproachList(const std::vector<std::string>& names);

// True for the approaches that train a learner (Q-learning).
bool IsLearningApproach(Approach approach);

// "A* Static, A* Oracle, ..., Incremental Oracle, convQ": every registered
// name in the registry's order, for help texts.
std::string ApproachNamesText();

}  // namespace dynapath
