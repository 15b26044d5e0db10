#pragma once
// The options dynapath render and dynapath view share, declared once: which
// run and approach to show, and pixels per cell side.

#include <optional>
#include <string>

#include "dynapath/result.h"
#include "runtime/option_group.h"

namespace dynapath::view {

struct ShowOptions {
  std::optional<std::string> run_id;    // unset: render all runs, view the latest heard
  std::optional<std::string> approach;  // unset: render all, view follows the latest
  std::optional<long long> cell_px;     // unset: the picture picks its size
};
void DeclareShowOptions(runtime::OptionGroup& group, ShowOptions& options);
// Checks --run-id and --cell; the cell size is 0 when not given.
Status CheckShowOptions(const ShowOptions& options);
Result<int> ResolveCellOption(const std::optional<long long>& cell_px);

}  // namespace dynapath::view
