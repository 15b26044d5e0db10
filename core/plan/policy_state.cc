// The checks on a policy state: consistency (after
// decoding a file) and fit (before a planner imports it).
#include "dynapath/policy_state.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <type_traits>

#include "dynapath/limits.h"
#include "dynapath/mdp.h"
#include "dynapath/quadtree.h"

namespace dynapath {
namespace {

std::string Shape(int rows, int cols) { return std::to_string(rows) + "x" + std::to_string(cols); }

std::string SemanticsName(Semantics semantics) {
  return semantics == Semantics::kReport ? "report" : "ours";
}

std::string BootstrapName(Bootstrap bootstrap) {
  switch (bootstrap) {
    case Bootstrap::kInGrid:
      return "in-grid";
    case Bootstrap::kInRegion:
      return "in-region";
    case Bootstrap::kAllStored:
      return "all-stored";
  }
  return "?";
}

template <class T>
std::string Text(T value) {
  if constexpr (std::is_floating_point_v<T>) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.17g", value);
    return buffer;
  } else {
    return std::to_string(value);
  }
}

}  // namespace

Status CheckPolicyConsistent(const PolicyState& s) {
  if (s.rows < 1 || s.cols < 1 || s.rows > kMaxGridSide || s.cols > kMaxGridSide) {
    return Error::Corrupt("shape " + Shape(s.rows, s.cols) + " is outside 1.." +
                          std::to_string(kMaxGridSide));
  }
  if (!IsLearningApproach(s.approach)) {
    return Error::Corrupt(ApproachName(s.approach) + " is not a learning approach");
  }
  if (s.leaf_limit < 1) return Error::Corrupt("leaf limit " + std::to_string(s.leaf_limit));
  const size_t nodes = static_cast<size_t>(s.node_count);
  if (s.node_count < 1 || s.training_counts.size() != nodes ||
      (!s.baselines.empty() && s.baselines.size() != nodes)) {
    return Error::Corrupt("per-node data does not match " + std::to_string(s.node_count) +
                          " nodes");
  }
  for (int64_t count : s.training_counts) {
    if (count < 0) return Error::Corrupt("negative training count");
  }
  for (double rate : s.baselines) {
    if (!(rate == -1.0 || (rate >= 0.0 && rate <= 1.0))) {
      return Error::Corrupt("baseline success rate " + Text(rate) + " is not -1 or in [0, 1]");
    }
  }
  if (s.table.precision() != s.precision ||
      s.table.size() != static_cast<size_t>(s.rows) * static_cast<size_t>(s.cols) * kNumActions) {
    return Error::Corrupt("the table does not match the shape " + Shape(s.rows, s.cols));
  }
  return Ok{};
}

Status CheckPolicyFits(const PolicyState& s, Approach approach, const PlannerOptions& options,
                       int rows, int cols) {
  auto differs = [](const std::string& what, const std::string& saved, const std::string& now) {
    return Error("the policy was saved with " + what + " " + saved + ", this run has " + now);
  };
  if (s.rows != rows || s.cols != cols) {
    return Error("the policy is for a " + Shape(s.rows, s.cols) + " maze, this maze is " +
                 Shape(rows, cols));
  }
  if (s.approach != approach) {
    return differs("approach", ApproachName(s.approach), ApproachName(approach));
  }
  if (s.leaf_limit != options.leaf_limit) {
    return differs("--leaf-limit", Text(s.leaf_limit), Text(options.leaf_limit));
  }
  if (s.semantics != options.semantics) {
    return differs("--semantics", SemanticsName(s.semantics), SemanticsName(options.semantics));
  }
  const QPrecision precision = options.table_precision.value_or(
      options.semantics == Semantics::kReport ? QPrecision::kDouble : QPrecision::kFloat);
  if (s.precision != precision) {
    return differs("table precision", s.precision == QPrecision::kFloat ? "float" : "double",
                   precision == QPrecision::kFloat ? "float" : "double");
  }
  if (s.learner.bootstrap != options.bootstrap) {
    return differs("--bootstrap", BootstrapName(s.learner.bootstrap),
                   BootstrapName(options.bootstrap));
  }
#define DYNAPATH_COMPARE_OPTION(group, member)                              \
  if (s.learner.group.member != options.group.member) {                     \
    return differs("learner option " #member, Text(s.learner.group.member), \
                   Text(options.group.member));                             \
  }
#define DYNAPATH_COMPARE_SINGLE(member, ...) DYNAPATH_COMPARE_OPTION(single_agent, member)
#define DYNAPATH_COMPARE_FEDERATED(member, ...) DYNAPATH_COMPARE_OPTION(federated, member)
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_COMPARE_SINGLE)
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_COMPARE_FEDERATED)
#undef DYNAPATH_COMPARE_FEDERATED
#undef DYNAPATH_COMPARE_SINGLE
#undef DYNAPATH_COMPARE_OPTION
#define DYNAPATH_COMPARE_THRESHOLD(member, ...)                                \
  if (s.thresholds.member != options.thresholds.member) {                      \
    return differs("retraining threshold " #member, Text(s.thresholds.member), \
                   Text(options.thresholds.member));                           \
  }
  DYNAPATH_RETRAINING_THRESHOLDS(DYNAPATH_COMPARE_THRESHOLD)
#undef DYNAPATH_COMPARE_THRESHOLD
  if (s.node_count != QuadTree(rows, cols, options.leaf_limit).node_count()) {
    return Error("the policy's quadtree has " + std::to_string(s.node_count) +
                 " nodes, this maze's has " +
                 std::to_string(QuadTree(rows, cols, options.leaf_limit).node_count()));
  }
  return Ok{};
}

}  // namespace dynapath
