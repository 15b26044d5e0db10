#include "dynapath/convq_training.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <thread>
#include <vector>

#include "core/plan/convq_values.h"
#include "dynapath/mdp.h"
#include "dynapath/rng.h"
#include "dynapath/scenario.h"

namespace dynapath {
namespace convq_train {

constexpr size_t kN = kConvQWeightCount;
// The TD target's discount: SPEC's gamma, in double.
constexpr double kGamma = 0.9;

// Least-squares sums of one maze's samples.
struct Sums {
  std::array<double, kN * kN> a{};
  std::array<double, kN> b{};
  double squared_error = 0;
  int samples = 0;
};

// A maze of the report's kinds: side, difficulty and the point of its
// change sequence drawn from the maze's own stream.
Grid TrainingMaze(const ConvQTrainingOptions& options, int round, int index) {
  Rng rng(DeriveSeed({options.seed, static_cast<uint64_t>(round), static_cast<uint64_t>(index)}));
  const int span = options.max_side - options.min_side + 1;
  const int side = options.min_side + static_cast<int>(rng.Next() % static_cast<uint64_t>(span));
  const Difficulty difficulty = kAllDifficulties[index % 3];
  const int steps = static_cast<int>(rng.Next() % static_cast<uint64_t>(2 * side + 1));
  Scenario scenario = GenerateScenario(side, side, difficulty,
                                       ConvQTrainingMazeSeed(options.seed, round, index), steps);
  for (const ChangeStep& step : scenario.changes.steps) ApplyChanges(step, scenario.grid);
  return std::move(scenario.grid);
}

// Features of (s, a) under the round's values: the target's kind (station,
// free, blocked), then the discounted terms' values V(t) (t free) and
// V(s) (blocked). Q(s, a) = weights . features.
Sums MazeSums(const ConvQTrainingOptions& options, const ConvQModel& model, int round, int index) {
  const Grid grid = TrainingMaze(options, round, index);
  ConvQValues values(model);
  values.Solve(grid);
  std::vector<int> starts;
  for (int cell = 0; cell < grid.size(); ++cell) {
    if (grid.at(cell) == Cell::kFree) starts.push_back(cell);
  }
  Sums sums;
  if (starts.empty()) return sums;
  Rng rng(DeriveSeed(
      {options.seed, static_cast<uint64_t>(round), static_cast<uint64_t>(index), 0x5a3d1e5ull}));
  for (int k = 0; k < options.samples_per_maze; ++k) {
    const int s = starts[static_cast<size_t>(rng.Next() % starts.size())];
    const int a = static_cast<int>(rng.Next() % kNumActions);
    const int r = grid.RowOf(s) + kActionRowOffset[a], c = grid.ColOf(s) + kActionColOffset[a];
    // SPEC section 2's transition and reward.
    const bool blocked = !grid.InBounds(r, c) || grid.at(r, c) == Cell::kObstacle;
    const int next = blocked ? s : grid.Index(r, c);
    const bool station = grid.at(next) == Cell::kStation;
    const double reward = station ? 100.0 : blocked ? -10.0 : -1.0;
    const double target = reward + (station ? 0.0 : kGamma * values.Value(grid, next));
    std::array<double, kN> x{};
    x[0] = station ? 1.0 : 0.0;
    x[1] = !station && !blocked ? 1.0 : 0.0;
    x[2] = blocked ? 1.0 : 0.0;
    x[3] = !station && !blocked ? values.Value(grid, next) : 0.0;
    x[4] = blocked ? values.Value(grid, s) : 0.0;
    const std::array<double, kN> w = ConvQWeights(model);
    double q = 0;
    for (size_t i = 0; i < kN; ++i) q += w[i] * x[i];
    sums.squared_error += (target - q) * (target - q);
    for (size_t i = 0; i < kN; ++i) {
      sums.b[i] += x[i] * target;
      for (size_t j = 0; j < kN; ++j) sums.a[i * kN + j] += x[i] * x[j];
    }
    ++sums.samples;
  }
  return sums;
}

// Solves (A + ridge I) w = b by Gaussian elimination with partial pivoting.
std::array<double, kN> Solve(std::array<double, kN * kN> a, std::array<double, kN> b) {
  double trace = 0;
  for (size_t i = 0; i < kN; ++i) trace += a[i * kN + i];
  const double ridge = 1e-12 * (trace / kN) + 1e-12;
  for (size_t i = 0; i < kN; ++i) a[i * kN + i] += ridge;
  for (size_t col = 0; col < kN; ++col) {
    size_t pivot = col;
    for (size_t row = col + 1; row < kN; ++row) {
      if (std::fabs(a[row * kN + col]) > std::fabs(a[pivot * kN + col])) pivot = row;
    }
    if (pivot != col) {
      for (size_t j = 0; j < kN; ++j) std::swap(a[col * kN + j], a[pivot * kN + j]);
      std::swap(b[col], b[pivot]);
    }
    for (size_t row = col + 1; row < kN; ++row) {
      const double f = a[row * kN + col] / a[col * kN + col];
      for (size_t j = col; j < kN; ++j) a[row * kN + j] -= f * a[col * kN + j];
      b[row] -= f * b[col];
    }
  }
  std::array<double, kN> w{};
  for (size_t i = kN; i-- > 0;) {
    double sum = b[i];
    for (size_t j = i + 1; j < kN; ++j) sum -= a[i * kN + j] * w[j];
    w[i] = sum / a[i * kN + i];
  }
  return w;
}

// Adds `sums` into `total`.
void Accumulate(const Sums& sums, Sums& total) {
  for (size_t i = 0; i < kN * kN; ++i) total.a[i] += sums.a[i];
  for (size_t i = 0; i < kN; ++i) total.b[i] += sums.b[i];
  total.squared_error += sums.squared_error;
  total.samples += sums.samples;
}

// Keeps a fitted model inside the bounds (the iteration must contract).
ConvQModel Bounded(const std::array<double, kN>& w) {
  std::array<double, kN> out = w;
  for (size_t i = 0; i < kN; ++i) {
    if (!std::isfinite(out[i])) out[i] = 0.0;
    out[i] = i >= 3 ? std::clamp(out[i], 0.0, 0.99) : std::clamp(out[i], -1e5, 1e5);
  }
  return ConvQModelFromWeights(out);
}

}  // namespace convq_train

using namespace convq_train;

unsigned ConvQTrainingMazeSeed(uint64_t seed, int round, int index) {
  const uint64_t mixed =
      DeriveSeed({seed, static_cast<uint64_t>(round), static_cast<uint64_t>(index), 0x6d617a65ull});
  return static_cast<unsigned>(kConvQTrainingSeedBase | (mixed & 0x7fffffffull));
}

Result<ConvQModel> TrainConvQModel(const ConvQTrainingOptions& options, StopToken stop,
                                   const std::function<void(const ConvQTrainingRound&)>& progress) {
  if (options.learners > 0) {
    return TrainConvQFederated(options, LocalConvQShards(options, stop), progress);
  }
  ConvQModel model = InitialConvQModel();
  const int threads = std::max(1, options.threads);
  std::vector<Sums> per_maze(static_cast<size_t>(options.mazes_per_round));
  for (int round = 1; round <= options.rounds; ++round) {
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) {
      workers.emplace_back([&, t] {
        for (int i = t; i < options.mazes_per_round; i += threads) {
          if (StopRequested(stop)) return;
          per_maze[static_cast<size_t>(i)] = MazeSums(options, model, round, i);
        }
      });
    }
    for (int i = 0; i < options.mazes_per_round; i += threads) {
      if (StopRequested(stop)) break;
      per_maze[static_cast<size_t>(i)] = MazeSums(options, model, round, i);
    }
    for (std::thread& worker : workers) worker.join();
    if (StopRequested(stop)) return Error::Cancelled();
    Sums total;
    for (const Sums& sums : per_maze) Accumulate(sums, total);
    model = Bounded(Solve(total.a, total.b));
    if (progress) {
      ConvQTrainingRound report;
      report.round = round;
      report.samples = total.samples;
      report.td_rms = total.samples == 0 ? 0.0 : std::sqrt(total.squared_error / total.samples);
      report.model = model;
      progress(report);
    }
  }
  return model;
}

ConvQModel InitialConvQModel() { return ConvQModel{0.0, 0.0, 0.0, 0.5, 0.5}; }

ConvQShard TrainConvQLearner(const ConvQTrainingOptions& options, const ConvQModel& model,
                             int round, int learner) {
  ConvQShard shard;
  shard.learner = learner;
  shard.model = model;
  const int learners = std::max(1, options.learners);
  Sums total;
  for (int i = learner; i < options.mazes_per_round; i += learners) {
    Accumulate(MazeSums(options, model, round, i), total);
  }
  shard.samples = total.samples;
  shard.squared_error = total.squared_error;
  if (total.samples > 0) shard.model = Bounded(Solve(total.a, total.b));
  return shard;
}

ConvQModel AverageConvQShards(const std::vector<ConvQShard>& shards, ConvQAveraging averaging,
                              const ConvQModel& round_model) {
  std::array<double, kN> sum{};
  double total_weight = 0;
  for (const ConvQShard& shard : shards) {
    const double weight =
        averaging == ConvQAveraging::kEqual ? 1.0 : static_cast<double>(shard.samples);
    const std::array<double, kN> w = ConvQWeights(shard.model);
    for (size_t i = 0; i < kN; ++i) sum[i] += weight * w[i];
    total_weight += weight;
  }
  if (total_weight <= 0) return round_model;
  for (double& value : sum) value /= total_weight;
  return Bounded(sum);
}

ConvQShardSource LocalConvQShards(const ConvQTrainingOptions& options, StopToken stop) {
  return [options, stop](int round, const ConvQModel& model) -> Result<std::vector<ConvQShard>> {
    const int learners = options.learners;
    const int threads = std::clamp(options.threads, 1, std::max(1, learners));
    std::vector<ConvQShard> shards(static_cast<size_t>(learners));
    const auto work = [&](int first) {
      for (int k = first; k < learners; k += threads) {
        if (StopRequested(stop)) return;
        shards[static_cast<size_t>(k)] = TrainConvQLearner(options, model, round, k);
      }
    };
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) workers.emplace_back(work, t);
    work(0);
    for (std::thread& worker : workers) worker.join();
    if (StopRequested(stop)) return Error::Cancelled();
    return shards;
  };
}

Result<ConvQModel> TrainConvQFederated(
    const ConvQTrainingOptions& options, const ConvQShardSource& source,
    const std::function<void(const ConvQTrainingRound&)>& progress) {
  ConvQModel model = InitialConvQModel();
  for (int round = 1; round <= options.rounds; ++round) {
    Result<std::vector<ConvQShard>> shards = source(round, model);
    if (!shards) return shards.error();
    if (static_cast<int>(shards->size()) != options.learners) {
      return Error::Internal("round " + std::to_string(round) + " has " +
                             std::to_string(shards->size()) + " shards, expected " +
                             std::to_string(options.learners));
    }
    int samples = 0;
    double squared_error = 0;
    for (size_t k = 0; k < shards->size(); ++k) {
      if ((*shards)[k].learner != static_cast<int>(k)) {
        return Error::Internal("round " + std::to_string(round) + ": shard " + std::to_string(k) +
                               " is learner " + std::to_string((*shards)[k].learner) + "'s");
      }
      samples += (*shards)[k].samples;
      squared_error += (*shards)[k].squared_error;
    }
    model = AverageConvQShards(*shards, options.averaging, model);
    if (progress) {
      ConvQTrainingRound report;
      report.round = round;
      report.samples = samples;
      report.td_rms = samples == 0 ? 0.0 : std::sqrt(squared_error / samples);
      report.model = model;
      progress(report);
    }
  }
  return model;
}

}  // namespace dynapath
