#pragma once
// --cell, shared by dynapath render and dynapath view: pixels per cell side.

#include <optional>

#include "core/result.h"
#include "runtime/option_group.h"

namespace dynapath::view {

void DeclareCellOption(runtime::OptionGroup& group, std::optional<long long>& cell_px);
// 0 when not given (the picture picks its own size), else 1..kMaxCellPx.
Result<int> ResolveCellOption(const std::optional<long long>& cell_px);

}  // namespace dynapath::view
