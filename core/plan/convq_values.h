#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/convq_model.h"
#endif
// The settled values of convQ's recurrent convolution (dynapath/convq_model.h)
// on a grid, kept up to date as cells change.
//
// Values are held shifted by the constant c = free_reward / (1 -
// move_discount), the value of a free cell that never reaches a station:
// U = V - c. Then a move to a free cell is worth exactly move_discount * U
// of the target (the step reward cancels), a move into a station
// station_reward - c, and a blocked move's self-loop settles at
// (blocked_reward - c + bump_discount * c) / (1 - bump_discount). The
// shift changes no decision (it is the same constant for every action)
// but keeps the values relative to 0 instead of to c, so that a station
// thousands of cells away still differs from none in a double.
//
// Settling the iteration is solved in one pass, largest value first (the
// operator is monotone and move_discount < 1, so a value is final when it
// is the largest left): the fixed point the plain iteration approaches,
// which IterateConvQ computes for tests. A repair resets only the changed
// cells, their neighbours and the cells whose value was derived through
// them, and settles from there: the same fixed point as a full solve, bit
// for bit.

#include <cstdint>
#include <queue>
#include <vector>

#include "dynapath/convq_model.h"
#include "dynapath/grid.h"
#include "dynapath/mdp.h"

namespace dynapath {

class ConvQValues {
 public:
  explicit ConvQValues(const ConvQModel& model);

  // Settles the values on `grid` from scratch.
  void Solve(const Grid& grid);
  // `grid` holds changes at `changed` since the last Solve or Repair.
  void Repair(const Grid& grid, const std::vector<int>& changed);
  // Cells whose value may have changed in the last Solve/Repair (a
  // superset; every cell after Solve).
  const std::vector<int>& touched() const { return touched_; }

  // The value on SPEC's scale (V): 0 for stations, 0 for obstacles (unused).
  double Value(const Grid& grid, int cell) const;
  // The shifted value U = V - c of a free cell.
  double Shifted(int cell) const { return shifted_[static_cast<size_t>(cell)]; }
  double shift() const { return shift_; }
  // The 8 action values of `cell`, shifted by c like the values (the same
  // order of actions as SPEC's): what the policy evaluation ranks. Out-of-
  // grid actions get the blocked value. Zeros for obstacles and stations.
  void ActionValues(const Grid& grid, int cell, double* q) const;

 private:
  // The value of a free cell from its own neighbourhood alone: the best of
  // entering a neighbouring station, the blocked move's settled self-loop
  // and 0 when a free neighbour exists (the value of wandering).
  double Initial(const Grid& grid, int cell) const;
  void Push(int cell);
  // Settles from the queued cells, largest first.
  void Propagate(const Grid& grid);

  ConvQModel model_;
  double shift_ = 0;          // c
  double station_ = 0;        // station_reward - c
  double blocked_base_ = 0;   // blocked_reward - c + bump_discount * c
  double blocked_fixed_ = 0;  // blocked_base_ / (1 - bump_discount)
  double move_ = 0;           // move_discount
  std::vector<double> shifted_;
  std::vector<int32_t> source_;  // the neighbour a value came from, -1 own
  std::vector<uint8_t> marked_;
  std::vector<int> touched_;
  std::vector<int> reset_;
  // Max-heap by value, ties to the larger cell index (deterministic).
  std::priority_queue<std::pair<double, int>> queue_;
};

// The plain synchronous iteration of the convolution on SPEC's scale, from
// V = 0, `iterations` times (the definition the solver settles; tests).
std::vector<double> IterateConvQ(const ConvQModel& model, const Grid& grid, int iterations);

}  // namespace dynapath
