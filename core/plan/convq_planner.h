#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/planner.h"
#endif
// convQ: a learned recurrent convolution (dynapath/convq_model.h) settled on
// the grid. No training on the maze: Initialize settles the values of the
// whole grid, Adapt re-settles around the changed cells only
// (ConvQValues::Repair). The action values are kept in a table scored by
// the same policy evaluation as the learning approaches' tables (SPEC
// section 4).

#include <memory>

#include "core/eval/incremental_policy_evaluation.h"
#include "core/plan/convq_values.h"
#include "dynapath/planner.h"

namespace dynapath {

class ConvQPlanner : public Planner {
 public:
  ConvQPlanner(const ConvQModel& model, int leaf_limit);

  StepDetails Initialize(const Grid& grid) override;
  StepDetails Adapt(const Grid& grid, const std::vector<int>& changed_cells) override;
  PolicyScore Evaluate(const Grid& grid) override;
  bool Picture(const Grid& grid, PolicyPicture& picture) override;

  const ConvQValues& values() const { return values_; }
  const QTable& table() const { return table_; }

 private:
  // Recomputes the table rows of `touched` cells and their neighbours.
  void UpdateRows(const Grid& grid, const std::vector<int>& cells, bool all);

  int leaf_limit_;
  ConvQValues values_;
  std::unique_ptr<QuadTree> tree_;  // only for the evaluation's regions
  QTable table_;
  std::vector<uint8_t> marked_;
  std::vector<int> rows_;
  IncrementalPolicyEvaluation evaluation_;
};

}  // namespace dynapath
