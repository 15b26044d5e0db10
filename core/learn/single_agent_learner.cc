#include "core/learn/single_agent_learner.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/learn/rng_skip.h"
#include "core/learn/settled_updates.h"
#include "dynapath/rng.h"
#include "dynapath/start_statistics.h"

namespace dynapath {

namespace {

// Largest absolute difference between two tables of the same size.
template <typename V>
double MaxAbsChange(const QTable& a, const QTable& b) {
  const std::vector<V>& x = a.Values<V>();
  const std::vector<V>& y = b.Values<V>();
  V largest = 0;
  for (size_t i = 0; i < x.size(); ++i) largest = std::max(largest, std::fabs(x[i] - y[i]));
  return largest;
}

// Bit pattern of a value, for the exact "did not change" test.
template <typename V>
auto Bits(V value) {
  if constexpr (sizeof(V) == 4) {
    return std::bit_cast<uint32_t>(value);
  } else {
    return std::bit_cast<uint64_t>(value);
  }
}

// The learner on a table of value type V (float, or the report code's double).
template <typename V>
void Train(const TrainingJob& job, const SingleAgentRules& rules, const RegionModel& model,
           StopToken stop, std::atomic<int64_t>* work, int64_t& counted, TrainingResult& result) {
  const SingleAgentOptions& options = job.single_agent;

  StartStatistics stats(model.start_cells());
  if (stats.start_cells().empty()) return;

  V* q = result.table.Values<V>().data();
  // Settled updates (no-ops, see settled_updates.h) are skipped: the table
  // and the random stream are exactly those of applying every update.
  SettledUpdates settled(model);
  // One Q-learning update of table entry s * 8 + a.
  const auto update = [&model, q, &settled](uint32_t entry) {
    if (settled.settled(entry)) return;
    const int s = static_cast<int>(entry / kNumActions), a = static_cast<int>(entry % kNumActions);
    const int next = model.target(s, a);
    const V best_next = model.BootstrapMax(next, q + static_cast<size_t>(next) * kNumActions);
    const V value = q[entry];
    const V updated = value + kLearningRateOf<V> * (static_cast<V>(model.reward(s, a)) +
                                                     kDiscountOf<V> * best_next - value);
    if (Bits(updated) == Bits(value)) {
      settled.MarkSettled(entry);
    } else {
      q[entry] = updated;
      settled.RowChanged(s);
    }
  };

  Rng rng(job.seed);
  const RngSkip& skip = RngSkip::For(std::max(0, options.replay_batch));
  // Everything the episode loop needs is allocated here, before it.
  const int max_steps = job.region.rows() + job.region.cols() - (rules.one_step_fewer ? 1 : 0);
  // The environment is deterministic, so (s, a) determines r and s': the
  // buffer stores the table index s * 8 + a of each transition.
  std::vector<uint32_t> replay(static_cast<size_t>(std::max(1, options.replay_capacity)));
  size_t replay_size = 0, replay_next = 0;
  QTable snapshot(model.cells(), result.table.precision());
  bool has_snapshot = false;
  if (rules.first_check_against_start) {
    // The first check compares with the table the training started from.
    std::copy(result.table.Values<V>().begin(), result.table.Values<V>().end(),
              snapshot.Values<V>().begin());
    has_snapshot = true;
  }
  int quiet_checks = 0;
  double epsilon = options.epsilon_start;
  int64_t episodes = 0, steps = 0;

  for (int e = 0; e < options.max_episodes; ++e) {
    if (e % 64 == 0) {
      // Episodes done so far, counted where the stop flag is checked (not
      // one atomic per episode).
      if (work != nullptr && e > 0) {
        work->fetch_add(e - counted, std::memory_order_relaxed);
        counted = e;
      }
      if (StopRequested(stop)) break;
    }
    if (e >= options.convergence_start_episode &&
        (e - options.convergence_start_episode) % std::max(1, options.convergence_interval) == 0) {
      if (has_snapshot) {
        quiet_checks = MaxAbsChange<V>(result.table, snapshot) < options.convergence_threshold
                           ? quiet_checks + 1
                           : 0;
        if (quiet_checks >= options.convergence_checks) break;
      }
      std::copy(result.table.Values<V>().begin(), result.table.Values<V>().end(),
                snapshot.Values<V>().begin());
      has_snapshot = true;
    }

    const int start = stats.Draw(rng);
    // The steps use a local copy of the generator (put back after the
    // episode), which the compiler can keep in registers.
    Rng step_rng = rng;
    const bool replaying = e >= options.replay_start_episode;
    int s = start;
    // A start on a station is an immediate success with no step (ours), or
    // an ordinary start (the report's rule).
    bool success = !rules.station_starts_step && model.is_station(s);
    for (int t = 0; !success && t < max_steps; ++t) {
      const int count = model.action_count(s);
      if (count == 0) break;  // a 1x1 region: nowhere to go
      const uint8_t* actions = model.actions(s);
      int a;
      if (step_rng.Uniform() < epsilon) {
        a = actions[step_rng.Below(static_cast<uint32_t>(count))];
      } else {
        // Greedy; strict ">" over increasing actions: ties go to the lowest.
        const V* row = q + static_cast<size_t>(s) * kNumActions;
        a = actions[0];
        for (int i = 1; i < count; ++i) {
          if (row[actions[i]] > row[a]) a = actions[i];
        }
      }
      const uint32_t entry = static_cast<uint32_t>(s * kNumActions + a);
      update(entry);
      const int next = model.target(s, a);
      ++steps;
      if (replay_size == replay.size()) settled.Removed(replay[replay_next]);
      replay[replay_next] = entry;
      settled.Added(entry);
      replay_next = replay_next + 1 == replay.size() ? 0 : replay_next + 1;
      replay_size = std::min(replay_size + 1, replay.size());
      if (replaying) {
        if (settled.BufferSettled()) {
          // Every draw would pick a settled entry: only the draws remain.
          skip.Apply(step_rng);
        } else {
          const uint32_t size = static_cast<uint32_t>(replay_size);
          for (int i = 0; i < options.replay_batch; ++i) update(replay[step_rng.Below(size)]);
        }
      }
      s = next;
      success = model.is_station(s);
    }
    rng = step_rng;
    // The report's code never writes its start statistics: its starts stay
    // uniform (StartStatistics draws uniformly until 10 are recorded).
    if (!rules.uniform_starts) stats.Record(stats.SlotOf(start), success);
    epsilon = std::max(epsilon * options.epsilon_decay, options.epsilon_min);
    episodes = e + 1;
  }

  result.episodes_or_rounds = episodes;
  result.steps = steps;
}

}  // namespace

SingleAgentRules ReportSingleAgentRules() {
  SingleAgentRules rules;
  rules.station_starts_step = true;
  rules.uniform_starts = true;
  rules.one_step_fewer = true;
  rules.first_check_against_start = true;
  return rules;
}

SingleAgentRules SingleAgentRulesOf(const TrainingJob& job) {
  // Only --semantics report selects Bootstrap::kAllStored (run_driver.cc
  // rejects --bootstrap with it), so agents learn the rules from the job's
  // bootstrap field with no message change.
  return job.bootstrap == Bootstrap::kAllStored ? ReportSingleAgentRules() : SingleAgentRules{};
}

TrainingResult TrainSingleAgent(const TrainingJob& job, StopToken stop,
                                std::atomic<int64_t>* work) {
  return TrainSingleAgent(job, SingleAgentRulesOf(job), stop, work);
}

TrainingResult TrainSingleAgent(const TrainingJob& job, const SingleAgentRules& rules,
                                StopToken stop, std::atomic<int64_t>* work) {
  TrainingResult result;
  result.node = job.node;
  result.table = StartingTable(job);  // validates the job first
  const RegionModel model(job);
  int64_t counted = 0;
  WithValueType(result.table.precision(),
                [&]<typename V>(V*) { Train<V>(job, rules, model, stop, work, counted, result); });
  // Ended (converged, stopped, or nothing to learn): the unused budget
  // counts as done, so the batch's count ends at its total.
  const int64_t budget = SingleAgentBudget(job);
  if (work != nullptr && budget > counted) {
    work->fetch_add(budget - counted, std::memory_order_relaxed);
  }
  return result;
}

int64_t SingleAgentBudget(const TrainingJob& job) {
  return std::max(0, job.single_agent.max_episodes);
}

}  // namespace dynapath
