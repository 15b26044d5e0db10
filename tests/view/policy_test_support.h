#pragma once
// Policies for the view tests.

#include <string>

#include "dynapath/policy_t.hpp"

namespace dynapath::view::testing {

// A rows x cols policy of free cells, no actions, no outcomes, no regions.
inline policy_t MakePolicy(int rows, int cols, const std::string& approach = "fedAsynQ_EqAvg",
                           int time_step = 3, const std::string& run_id = "r1") {
  policy_t policy{};
  policy.run_id = run_id;
  policy.approach = approach;
  policy.pass = 0;
  policy.time_step = time_step;
  policy.rows = rows;
  policy.cols = cols;
  policy.num_cells = rows * cols;
  policy.cells.assign(static_cast<size_t>(rows * cols), 1);
  policy.actions.assign(static_cast<size_t>(rows * cols), -1);
  policy.reaches.assign(static_cast<size_t>(rows * cols), -1);
  policy.num_regions = 0;
  return policy;
}

inline void AddRegion(policy_t& policy, int row0, int col0, int rows, int cols) {
  policy.region_row0.push_back(row0);
  policy.region_col0.push_back(col0);
  policy.region_rows.push_back(rows);
  policy.region_cols.push_back(cols);
  policy.num_regions = static_cast<int>(policy.region_row0.size());
}

}  // namespace dynapath::view::testing
