// The parameter table of dynapath/parameters.h, expanded from the option
// lists, and its reads and writes of PlannerOptions' members.
#include "dynapath/parameters.h"

#include <charconv>
#include <cmath>

#include "core/plan/approach_registry.h"

namespace dynapath {
namespace {

// "epsilon_start" -> "epsilon-start".
std::string Dashed(std::string name) {
  for (char& c : name) c = c == '_' ? '-' : c;
  return name;
}

template <typename T>
constexpr bool kIsInt = std::is_same_v<T, int>;

}  // namespace

const std::vector<Parameter>& Parameters() {
  static const std::vector<Parameter> parameters = {
#define DYNAPATH_PARAMETER(group, member, type, default_value, report, min, max, help) \
  Parameter{Dashed(#member),                                                           \
            ParameterGroup::group,                                                     \
            kIsInt<type>,                                                              \
            static_cast<double>(default_value),                                        \
            static_cast<double>(report),                                               \
            static_cast<double>(min),                                                  \
            static_cast<double>(max),                                                  \
            help},
#define DYNAPATH_SINGLE_AGENT_PARAMETER(...) DYNAPATH_PARAMETER(kSingleAgent, __VA_ARGS__)
#define DYNAPATH_FEDASYNQ_PARAMETER(...) DYNAPATH_PARAMETER(kFederated, __VA_ARGS__)
#define DYNAPATH_STRATEGY_PARAMETER(...) DYNAPATH_PARAMETER(kStrategy, __VA_ARGS__)
      DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_SINGLE_AGENT_PARAMETER)
          DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_FEDASYNQ_PARAMETER)
              DYNAPATH_RETRAINING_THRESHOLDS(DYNAPATH_STRATEGY_PARAMETER)
#undef DYNAPATH_STRATEGY_PARAMETER
#undef DYNAPATH_FEDASYNQ_PARAMETER
#undef DYNAPATH_SINGLE_AGENT_PARAMETER
#undef DYNAPATH_PARAMETER
  };
  return parameters;
}

std::vector<Approach> ApproachesReading(ParameterGroup group) {
  std::vector<Approach> readers;
  for (const ApproachSpec& spec : ApproachRegistry()) {
    bool reads = false;
    switch (group) {
      case ParameterGroup::kSingleAgent:
        reads = spec.learner == LearnerKind::kSingleAgent;
        break;
      case ParameterGroup::kFederated:
        reads = spec.learner == LearnerKind::kFedAsynQ;
        break;
      case ParameterGroup::kStrategy:
        // Only the tree strategy has thresholds (leaves-only retrains every
        // changed leaf).
        reads = spec.make_strategy == &MakeTreeStrategy;
        break;
    }
    if (reads) readers.push_back(spec.approach);
  }
  return readers;
}

// The members in the table's order; `visit(index, member)` for each.
template <typename Options, typename Visit>
void ForEachMember(Options& options, Visit visit) {
  size_t index = 0;
#define DYNAPATH_VISIT(part, member, ...) visit(index++, options.part.member);
#define DYNAPATH_VISIT_SINGLE_AGENT(...) DYNAPATH_VISIT(single_agent, __VA_ARGS__)
#define DYNAPATH_VISIT_FEDASYNQ(...) DYNAPATH_VISIT(federated, __VA_ARGS__)
#define DYNAPATH_VISIT_STRATEGY(...) DYNAPATH_VISIT(thresholds, __VA_ARGS__)
  DYNAPATH_SINGLE_AGENT_OPTIONS(DYNAPATH_VISIT_SINGLE_AGENT)
  DYNAPATH_FEDASYNQ_OPTIONS(DYNAPATH_VISIT_FEDASYNQ)
  DYNAPATH_RETRAINING_THRESHOLDS(DYNAPATH_VISIT_STRATEGY)
#undef DYNAPATH_VISIT_STRATEGY
#undef DYNAPATH_VISIT_FEDASYNQ
#undef DYNAPATH_VISIT_SINGLE_AGENT
#undef DYNAPATH_VISIT
}

double ParameterValue(const PlannerOptions& options, size_t index) {
  double value = 0.0;
  ForEachMember(options, [&](size_t i, const auto& member) {
    if (i == index) value = static_cast<double>(member);
  });
  return value;
}

Status SetParameter(PlannerOptions& options, size_t index, double value) {
  const Parameter& parameter = Parameters().at(index);
  // NaN fails both comparisons.
  if (!(value >= parameter.min && value <= parameter.max) ||
      (parameter.integer && value != std::floor(value))) {
    const char* kind = parameter.integer ? "an integer" : "a number";
    return Error::Option(parameter.name, std::string("must be ") + kind + " from " +
                                             ParameterText(parameter, parameter.min) + " to " +
                                             ParameterText(parameter, parameter.max) + ", got " +
                                             ParameterText(parameter, value));
  }
  ForEachMember(options, [&](size_t i, auto& member) {
    if (i == index) member = static_cast<std::decay_t<decltype(member)>>(value);
  });
  return Ok{};
}

void ApplyReportPreset(PlannerOptions& options) {
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    // The report's values are in range by construction (tested).
    (void)SetParameter(options, i, parameters[i].report_value);
  }
}

std::string ParameterText(const Parameter& parameter, double value) {
  if (parameter.integer && value == std::floor(value) && std::fabs(value) < 1e18) {
    return std::to_string(static_cast<long long>(value));
  }
  char text[64];
  const std::to_chars_result written = std::to_chars(text, text + sizeof(text), value);
  std::string out(text, written.ptr);
  // A TOML float needs a '.' or an exponent.
  if (out.find_first_of(".eEin") == std::string::npos) out += ".0";
  return out;
}

std::string ReportPresetText() {
  std::string text;
  for (const Parameter& parameter : Parameters()) {
    if (parameter.report_value == parameter.default_value) continue;
    text += (text.empty() ? "" : " ") + parameter.name + " " +
            ParameterText(parameter, parameter.report_value);
  }
  return text;
}

}  // namespace dynapath
