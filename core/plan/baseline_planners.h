#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/planner.h"
#endif
// The classical baselines of SPEC section 8.

#include "dynapath/astar_paths.h"
#include "dynapath/planner.h"

namespace dynapath {

// A* Static: paths planned once at time step 0, never updated.
class AStarStaticPlanner : public Planner {
 public:
  StepDetails Initialize(const Grid& grid) override;
  StepDetails Adapt(const Grid&, const std::vector<int>&) override { return {}; }
  bool Adapts() const override { return false; }
  PolicyScore Evaluate(const Grid& grid) override;

 private:
  AStarPlanner astar_;
  StationPaths paths_;
};

// A* Oracle: the report's per-start A*, rerun on every step.
class AStarOraclePlanner : public Planner {
 public:
  explicit AStarOraclePlanner(StopToken stop = nullptr) : stop_(stop) {}
  StepDetails Initialize(const Grid& grid) override;
  StepDetails Adapt(const Grid& grid, const std::vector<int>&) override { return Initialize(grid); }
  PolicyScore Evaluate(const Grid& grid) override;

 private:
  AStarPlanner astar_;
  StationPaths paths_;
  StopToken stop_;
};

// BFS Oracle: one multi-source breadth-first search per step.
class BfsOraclePlanner : public Planner {
 public:
  StepDetails Initialize(const Grid& grid) override;
  StepDetails Adapt(const Grid& grid, const std::vector<int>&) override { return Initialize(grid); }
  PolicyScore Evaluate(const Grid& grid) override;

 private:
  std::vector<int32_t> distance_;
  std::vector<int32_t> queue_;
};

}  // namespace dynapath
