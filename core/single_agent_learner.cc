#include "core/single_agent_learner.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/rng.h"
#include "core/start_statistics.h"

namespace dynapath {

namespace {

// Largest absolute difference between two tables of the same size.
double MaxAbsChange(const QTable& a, const QTable& b) {
  const std::vector<float>& x = a.values();
  const std::vector<float>& y = b.values();
  float largest = 0.0f;
  for (size_t i = 0; i < x.size(); ++i) largest = std::max(largest, std::fabs(x[i] - y[i]));
  return largest;
}

}  // namespace

TrainingResult TrainSingleAgent(const TrainingJob& job) {
  TrainingResult result;
  result.node = job.node;
  result.table = StartingTable(job);  // validates the job first
  const RegionModel model(job);
  const SingleAgentOptions& options = job.single_agent;

  StartStatistics stats(model.start_cells());
  if (stats.start_cells().empty()) return result;

  float* q = result.table.values().data();
  // One Q-learning update of (s, a); returns s'.
  const auto update = [&model, q](int s, int a) {
    const int next = model.target(s, a);
    const float best_next = model.BootstrapMax(next, q + static_cast<size_t>(next) * kNumActions);
    float& value = q[static_cast<size_t>(s) * kNumActions + a];
    value += kLearningRate * (model.reward(s, a) + kDiscount * best_next - value);
    return next;
  };

  Rng rng(job.seed);
  // Everything the episode loop needs is allocated here, before it.
  const int max_steps = job.region.rows() + job.region.cols();
  // The environment is deterministic, so (s, a) determines r and s': the
  // buffer stores the table index s * 8 + a of each transition.
  std::vector<uint32_t> replay(static_cast<size_t>(std::max(1, options.replay_capacity)));
  size_t replay_size = 0, replay_next = 0;
  QTable snapshot(model.cells());
  bool has_snapshot = false;
  int quiet_checks = 0;
  double epsilon = options.epsilon_start;
  int64_t episodes = 0, steps = 0;

  for (int e = 0; e < options.max_episodes; ++e) {
    if (e >= options.convergence_start_episode &&
        (e - options.convergence_start_episode) % std::max(1, options.convergence_interval) == 0) {
      if (has_snapshot) {
        quiet_checks = MaxAbsChange(result.table, snapshot) < options.convergence_threshold
                           ? quiet_checks + 1
                           : 0;
        if (quiet_checks >= options.convergence_checks) break;
      }
      std::copy(result.table.values().begin(), result.table.values().end(),
                snapshot.values().begin());
      has_snapshot = true;
    }

    const int start = stats.Draw(rng);
    const bool replaying = e >= options.replay_start_episode;
    int s = start;
    // A start on a station is an immediate success with no step.
    bool success = model.is_station(s);
    for (int t = 0; !success && t < max_steps; ++t) {
      const int count = model.action_count(s);
      if (count == 0) break;  // a 1x1 region: nowhere to go
      const uint8_t* actions = model.actions(s);
      int a;
      if (rng.Uniform() < epsilon) {
        a = actions[rng.Below(static_cast<uint32_t>(count))];
      } else {
        // Greedy; strict ">" over increasing actions: ties go to the lowest.
        const float* row = q + static_cast<size_t>(s) * kNumActions;
        a = actions[0];
        for (int i = 1; i < count; ++i) {
          if (row[actions[i]] > row[a]) a = actions[i];
        }
      }
      const int next = update(s, a);
      ++steps;
      replay[replay_next] = static_cast<uint32_t>(s * kNumActions + a);
      replay_next = replay_next + 1 == replay.size() ? 0 : replay_next + 1;
      replay_size = std::min(replay_size + 1, replay.size());
      if (replaying) {
        for (int i = 0; i < options.replay_batch; ++i) {
          const uint32_t entry = replay[rng.Below(static_cast<uint32_t>(replay_size))];
          update(static_cast<int>(entry / kNumActions), static_cast<int>(entry % kNumActions));
        }
      }
      s = next;
      success = model.is_station(s);
    }
    stats.Record(stats.SlotOf(start), success);
    epsilon = std::max(epsilon * options.epsilon_decay, options.epsilon_min);
    episodes = e + 1;
  }

  result.episodes_or_rounds = episodes;
  result.steps = steps;
  return result;
}

}  // namespace dynapath
