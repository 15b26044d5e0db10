#pragma once
// The learners' and the retraining strategy's parameters by name, as one
// table: every line of DYNAPATH_SINGLE_AGENT_OPTIONS, DYNAPATH_FEDASYNQ_OPTIONS
// and DYNAPATH_RETRAINING_THRESHOLDS (core/include/dynapath/learner_options.h),
// with its name, default,
// the report's value, range, help and the approaches that read it. The
// command line, config and study files, `dynapath params`, params.toml and
// the study manifest all read this table, so a parameter added to a list is
// everywhere at once.

#include <string>
#include <string_view>
#include <vector>

#include "dynapath/approach.h"
#include "dynapath/planner.h"
#include "dynapath/result.h"

namespace dynapath {

// Which part of the planner's options a parameter sets.
enum class ParameterGroup { kSingleAgent, kFederated, kStrategy };

struct Parameter {
  std::string name;  // "epsilon-start": the option, config and study key
  ParameterGroup group;
  bool integer;  // an int member (else a double)
  double default_value;
  double report_value;  // what `--semantics report` presets
  double min, max;      // inclusive
  std::string_view help;
};

// Every parameter, in the lists' order (single agent, federated, strategy).
const std::vector<Parameter>& Parameters();

// The approaches that read the parameters of `group`, in `all` order.
std::vector<Approach> ApproachesReading(ParameterGroup group);

// The value of parameter `index` in `options` (ints exactly, as double).
double ParameterValue(const PlannerOptions& options, size_t index);
// Sets parameter `index`, after checking the value: an error naming the
// parameter (Error::Option) when it is out of range, not a number, or not
// integral for an int parameter.
Status SetParameter(PlannerOptions& options, size_t index, double value);
// Applies the report's values of every parameter (`--semantics report`'s
// preset).
void ApplyReportPreset(PlannerOptions& options);

// A value as text: ints as integers, doubles in their shortest exact form
// (both read back as TOML numbers).
std::string ParameterText(const Parameter& parameter, double value);

// The parameters whose report value differs from the default, as
// "name value" words (empty when they are all the same).
std::string ReportPresetText();

}  // namespace dynapath
