#include "tools/view/cell_option.h"

#include "tools/view/policy_drawing.h"

namespace dynapath::view {

void DeclareCellOption(runtime::OptionGroup& group, std::optional<long long>& cell_px) {
  group.Option("--cell", cell_px, "PX", "pixels per cell side (1-64; arrows from 6 px)",
               "16 up to 50x50 cells, smaller beyond");
}

Result<int> ResolveCellOption(const std::optional<long long>& cell_px) {
  Result<long long> cell = runtime::InRange("cell", cell_px, 0, 1, kMaxCellPx);
  if (!cell) return cell.error();
  return static_cast<int>(*cell);
}

}  // namespace dynapath::view
