#pragma once
// The learner and strategy parameters (dynapath/parameters.h) as options of
// `dynapath run`, `dynapath experiment`, the coordinator and config / study
// files: one option per parameter, declared from the table, checked once,
// and the params.toml a run writes beside its result files.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dynapath/parameters.h"
#include "dynapath/planner.h"
#include "dynapath/result.h"
#include "runtime/option_group.h"

namespace dynapath::runtime {

// The parameters as given: one entry per line of Parameters() (in
// `integers` for an int parameter, `reals` for a double), unset when not
// given, so `--semantics report`'s preset applies under what is given.
struct ParameterOptions {
  std::vector<std::optional<long long>> integers =
      std::vector<std::optional<long long>>(Parameters().size());
  std::vector<std::optional<double>> reals =
      std::vector<std::optional<double>>(Parameters().size());
};

// --max-episodes, --epsilon-start, ... --escalate-below: every parameter.
void DeclareParameterOptions(OptionGroup& group, ParameterOptions& options);

// Sets the given parameters in `planner` (over the defaults, or the report
// preset applied before); the first out of range is an Error::Option naming
// it.
Status ApplyParameterOptions(const ParameterOptions& given, PlannerOptions& planner);

// Every parameter with its value in `planner`, as `name = value` lines that
// `--config` reads back.
std::string ParameterLines(const PlannerOptions& planner);
// The same after a comment line (`dynapath params --format toml`); with
// `learner_seed`, a last line `learner-seed = N` (--learner-seed). A run's
// params.toml holds more (runtime::RunPlanToml).
std::string ParametersToml(const PlannerOptions& planner,
                           std::optional<uint64_t> learner_seed = std::nullopt);

}  // namespace dynapath::runtime
