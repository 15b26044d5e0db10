#include "tools/view/view_options.h"

#include "protocol/channels.h"
#include "tools/view/policy_drawing.h"

namespace dynapath::view {

void DeclareShowOptions(runtime::OptionGroup& group, ShowOptions& o) {
  group.Option("--run-id", o.run_id, "ID", "only this run (of the log, or heard on the network)",
               "render: every run of the log; view: the most recent run heard");
  group.Option("--approach", o.approach, "NAME",
               "the approach to show ('A* Oracle' or its directory name A_Oracle)",
               "render: all; view: follow the latest");
  group.Option("--cell", o.cell_px, "PX", "pixels per cell side (1-64; arrows from 6 px)",
               "16 up to 50x50 cells, smaller beyond");
}

Result<int> ResolveCellOption(const std::optional<long long>& cell_px) {
  Result<long long> cell = runtime::InRange("cell", cell_px, 0, 1, kMaxCellPx);
  if (!cell) return cell.error();
  return static_cast<int>(*cell);
}

Status CheckShowOptions(const ShowOptions& o) {
  if (o.run_id) {
    if (Status status = protocol::CheckRunId(*o.run_id); !status) return status.error();
  }
  Result<int> cell = ResolveCellOption(o.cell_px);
  if (!cell) return cell.error();
  return Ok{};
}

}  // namespace dynapath::view
