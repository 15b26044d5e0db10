#include "runtime/parameter_options.h"

namespace dynapath::runtime {
namespace {

// "10000 (1 to 10000000)": the range, for the help line.
std::string RangeText(const Parameter& parameter) {
  return ParameterText(parameter, parameter.min) + " to " + ParameterText(parameter, parameter.max);
}

}  // namespace

void DeclareParameterOptions(OptionGroup& group, ParameterOptions& o) {
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    const Parameter& p = parameters[i];
    const std::string name = "--" + p.name;
    const std::string help = std::string(p.help) + " (" + RangeText(p) + ")";
    const std::string default_text = ParameterText(p, p.default_value);
    if (p.integer) {
      group.Option(name, o.integers[i], "N", help, default_text);
    } else {
      group.Option(name, o.reals[i], "X", help, default_text);
    }
  }
}

Status ApplyParameterOptions(const ParameterOptions& given, PlannerOptions& planner) {
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    std::optional<double> value;
    if (parameters[i].integer && given.integers[i]) {
      value = static_cast<double>(*given.integers[i]);
    } else if (!parameters[i].integer && given.reals[i]) {
      value = *given.reals[i];
    }
    if (!value) continue;
    if (Status status = SetParameter(planner, i, *value); !status) return status;
  }
  return Ok{};
}

std::string ParameterLines(const PlannerOptions& planner) {
  std::string text;
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    text += parameters[i].name + " = " + ParameterText(parameters[i], ParameterValue(planner, i)) +
            "\n";
  }
  return text;
}

std::string ParametersToml(const PlannerOptions& planner, std::optional<uint64_t> learner_seed) {
  std::string text =
      "# Learner and strategy parameters (dynapath params); `dynapath run --config FILE` "
      "reads them.\n" +
      ParameterLines(planner);
  if (learner_seed) text += "learner-seed = " + std::to_string(*learner_seed) + "\n";
  return text;
}

}  // namespace dynapath::runtime
