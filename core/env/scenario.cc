#include "dynapath/scenario.h"

#include <array>

#include "dynapath/c_random.h"
#include "dynapath/mdp.h"

namespace dynapath {
namespace {

// Cumulative bounds of the report's skewed distribution of moves per step:
// u = rand() % 1000 < 900 gives 1 move, < 950 gives 2, ..., else 10.
constexpr std::array<int, 9> kMoveBounds = {900, 950, 970, 980, 987, 992, 995, 997, 999};

}  // namespace

int DrawMoveCount(CRandom& random) {
  const int u = random.Next() % 1000;
  int moves = 1;
  for (int bound : kMoveBounds) {
    if (u < bound) return moves;
    ++moves;
  }
  return moves;
}

Grid GenerateMaze(int rows, int cols, const CellProbabilities& probabilities, CRandom& random) {
  Grid grid(rows, cols);
  bool has_station = false;
  for (int i = 0; i < grid.size(); ++i) {
    const double v = static_cast<double>(random.Next()) / CRandom::kMax;
    if (v < probabilities.free) {
      grid.set(i, Cell::kFree);
    } else if (v < probabilities.free + probabilities.obstacle) {
      grid.set(i, Cell::kObstacle);
    } else {
      grid.set(i, Cell::kStation);
      has_station = true;
    }
  }
  if (!has_station) {
    const int row = random.Next() % rows;
    const int col = random.Next() % cols;
    grid.set(row, col, Cell::kStation);
  }
  return grid;
}

void MoveOneObstacle(Grid& grid, std::vector<int>& candidates, CRandom& random, ChangeStep& step) {
  const size_t chosen = static_cast<size_t>(random.Next()) % candidates.size();
  const int from = candidates[chosen];
  const int row = grid.RowOf(from), col = grid.ColOf(from);
  std::array<int, kNumActions> free_neighbours{};
  int count = 0;
  for (int a = 0; a < kNumActions; ++a) {
    const int r = row + kActionRowOffset[a], c = col + kActionColOffset[a];
    if (grid.InBounds(r, c) && grid.at(r, c) == Cell::kFree)
      free_neighbours[count++] = grid.Index(r, c);
  }
  if (count == 0) return;
  const int to = free_neighbours[static_cast<size_t>(random.Next() % count)];
  grid.set(from, Cell::kFree);
  grid.set(to, Cell::kObstacle);
  candidates[chosen] = to;
  step.changes.push_back({from, Cell::kFree});
  step.changes.push_back({to, Cell::kObstacle});
}

ChangeSequence GenerateChanges(const Grid& initial, int steps, CRandom& random) {
  Grid grid = initial;
  ChangeSequence sequence;
  sequence.steps.resize(static_cast<size_t>(steps));
  std::vector<int> obstacles;
  for (ChangeStep& step : sequence.steps) {
    step.requested_moves = DrawMoveCount(random);
    // Built once per step in row-major order, then updated in place.
    obstacles.clear();
    for (int i = 0; i < grid.size(); ++i) {
      if (grid.at(i) == Cell::kObstacle) obstacles.push_back(i);
    }
    for (int move = 0; move < step.requested_moves && !obstacles.empty(); ++move) {
      MoveOneObstacle(grid, obstacles, random, step);
    }
  }
  return sequence;
}

Scenario GenerateScenario(int rows, int cols, Difficulty difficulty, unsigned seed, int steps) {
  CRandom random(seed);
  Scenario scenario;
  scenario.grid = GenerateMaze(rows, cols, ProbabilitiesOf(difficulty), random);
  scenario.changes =
      GenerateChanges(scenario.grid, steps < 0 ? ReportTimeSteps(rows) : steps, random);
  return scenario;
}

}  // namespace dynapath
