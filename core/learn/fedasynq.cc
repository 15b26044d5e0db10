#include "core/learn/fedasynq.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <utility>

namespace dynapath {

namespace {

// eta of the importance weights: SPEC section 7 sets eta = alpha = 0.4 (kept
// in double: 0.4f would make the base 0.59999999).
constexpr double kImportanceEta = 0.4;
// (1 - eta)^d underflows to 0 in double beyond d ~ 1458; tabulate a little
// more and compute the rest (all 0) on demand.
constexpr size_t kDecayTableSize = 1536;

// Hash of a table entry for the learners' visit counts (Fibonacci hashing:
// the top bits of entry * 2^32 / golden ratio).
constexpr uint32_t kEntryHashFactor = 0x9E3779B1u;

}  // namespace

SortedMarks::SortedMarks(size_t entries)
    : bits_((entries + 63) / 64, 0),
      summary_((bits_.size() + 63) / 64, 0),
      rank_(bits_.size(), 0) {}

void SortedMarks::List(std::vector<uint32_t>& list) {
  list.clear();
  for (size_t s = 0; s < summary_.size(); ++s) {
    uint64_t words = summary_[s];
    while (words != 0) {
      const size_t w = s * 64 + static_cast<size_t>(std::countr_zero(words));
      words &= words - 1;
      rank_[w] = static_cast<uint32_t>(list.size());
      uint64_t word = bits_[w];
      const uint32_t base = static_cast<uint32_t>(w * 64);
      while (word != 0) {
        list.push_back(base + static_cast<uint32_t>(std::countr_zero(word)));
        word &= word - 1;
      }
    }
  }
}

void SortedMarks::Clear(const std::vector<uint32_t>& list) {
  for (uint32_t entry : list) {
    bits_[entry >> 6] = 0;
    summary_[entry >> 12] = 0;
  }
}

uint64_t LearnerRoundSeed(uint64_t job_seed, int learner, int64_t round) {
  return DeriveSeed({job_seed, static_cast<uint64_t>(learner), static_cast<uint64_t>(round)});
}

FedAsynQLearner::FedAsynQLearner(const RegionModel& model, int learner_index)
    : model_(model),
      learner_index_(learner_index),
      table_(model.cells()),
      marks_(static_cast<size_t>(model.cells()) * kNumActions) {}

void FedAsynQLearner::Reset(const QTable& table) {
  // Tables come from StartingTable of the same checked job, or from a
  // combiner's shared table sized from that job's region.
  assert(table.cells() == model_.cells());
  table_ = table;
  twin_in_sync_ = false;
}

LearnerShard FedAsynQLearner::RunRound(const StartStatistics& stats, uint64_t job_seed,
                                       int64_t round, int sync_period) {
  LearnerShard shard;
  Run(learner_index_, stats, job_seed, round, sync_period, false, shard);
  return shard;
}

LearnerShard FedAsynQLearner::RunRoundAndRevert(int learner, const StartStatistics& stats,
                                                uint64_t job_seed, int64_t round, int sync_period) {
  LearnerShard shard;
  Run(learner, stats, job_seed, round, sync_period, true, shard);
  return shard;
}

namespace {

using Slot = FedAsynQLearner::Slot;

// Where the visit count of `entry` is: slot = entry when kDirect, else the
// top bits of entry * golden ratio, then linear probing.
template <bool kDirect>
uint32_t HomeSlot(uint32_t entry, int shift) {
  if constexpr (kDirect) {
    return entry;
  } else {
    return (entry * kEntryHashFactor) >> shift;
  }
}

template <bool kDirect>
uint32_t FindSlot(const Slot* slots, uint32_t mask, int shift, uint32_t entry) {
  uint32_t slot = HomeSlot<kDirect>(entry, shift);
  if constexpr (!kDirect) {
    while (slots[slot].key != entry + 1) slot = (slot + 1) & mask;
  }
  return slot;
}

// One step of a learner's walk from `s`: the action drawn among the
// in-region ones, its table entry, where it leads, what it pays and the
// bootstrap maximum there.
template <typename V>
struct WalkStep {
  uint32_t entry;
  int next;
  V reward;
  V best_next;
};
template <typename V>
inline WalkStep<V> DrawStep(const RegionModel& model, const V* q, Rng& rng, int s) {
  const uint32_t index = rng.Below(static_cast<uint32_t>(model.in_region_count(s)));
  const int a = model.actions(s)[index];
  const int next = model.step_target(s, static_cast<int>(index));
  return {static_cast<uint32_t>(s * kNumActions + a), next, static_cast<V>(model.reward(s, a)),
          model.BootstrapMax(next, q + static_cast<size_t>(next) * kNumActions)};
}
// The Q-learning update of a step's entry from its `value`.
template <typename V>
inline V Updated(V value, const WalkStep<V>& step) {
  return value + kLearningRateOf<V> * (step.reward + kDiscountOf<V> * step.best_next - value);
}
// An uncounted step (equal averaging, which needs no visit counts): every
// step is listed at `step`, repeats included, so listing is two stores, and
// reverting the list backwards restores each entry's first original.
// Returns the next cell; `station` records a move that ended on a station
// (the reward is +100 exactly then).
template <typename V>
inline int UncountedStep(const RegionModel& model, V* q, Rng& rng, int s, int step,
                         uint32_t* touched, V* originals, bool& station) {
  const WalkStep<V> move = DrawStep(model, q, rng, s);
  const V value = q[move.entry];
  touched[step] = move.entry;
  originals[step] = value;
  q[move.entry] = Updated(value, move);
  station |= move.reward == static_cast<V>(kStationReward);
  return move.next;
}

// The random walk of one learner's round: `steps` Q-learning updates of `q`
// from `s`, counting visits in `slots` and listing new entries (with their
// values before the round) in touched/originals (kCount), or listing every
// step (UncountedStep). Everything lives in locals: stores through the table
// and the lists could otherwise alias members, reloaded at every step.
// Returns the number of entries listed.
template <bool kDirect, bool kCount, typename V>
size_t Walk(const RegionModel& model, V* q, Rng& walk_rng, int s, int steps, bool& reached,
            Slot* slots, uint32_t mask, int shift, uint32_t* touched, V* originals) {
  Rng rng = walk_rng;  // a local copy stays in registers
  size_t listed = 0;
  bool station = false;
  for (int step = 0; step < steps; ++step) {
    if constexpr (!kCount) {
      s = UncountedStep(model, q, rng, s, step, touched, originals, station);
    } else {
      const WalkStep<V> move = DrawStep(model, q, rng, s);
      // Count the visit, without branches on whether the entry is new (which
      // a random walk makes unpredictable): the listing is always written
      // and only counted when the slot was empty.
      const uint32_t key = move.entry + 1;
      uint32_t slot = HomeSlot<kDirect>(move.entry, shift);
      if constexpr (!kDirect) {
        // Another entry's slot (rare: at most half the slots are used).
        while ((slots[slot].key != 0) & (slots[slot].key != key)) slot = (slot + 1) & mask;
      }
      Slot& held = slots[slot];
      const V value = q[move.entry];
      touched[listed] = move.entry;
      originals[listed] = value;
      listed += held.key == 0;
      held.key = key;
      ++held.visits;
      q[move.entry] = Updated(value, move);
      station |= move.reward == static_cast<V>(kStationReward);
      s = move.next;
    }
  }
  reached |= station;
  walk_rng = rng;
  return kCount ? listed : static_cast<size_t>(std::max(0, steps));
}

// Two learners' uncounted walks of one round, interleaved step by step on
// two copies of the same table: each walk is exactly what Walk<true, false>
// gives it alone (they share nothing but the model), and the two chains of
// dependent loads and arithmetic overlap, where one walk alone leaves the
// core waiting.
template <typename V>
void WalkTwo(const RegionModel& model, V* qa, V* qb, Rng& rng_a, Rng& rng_b, int sa, int sb,
             int steps, bool& reached_a, bool& reached_b, uint32_t* touched_a, V* originals_a,
             uint32_t* touched_b, V* originals_b) {
  Rng ra = rng_a, rb = rng_b;
  bool station_a = false, station_b = false;
  for (int step = 0; step < steps; ++step) {
    sa = UncountedStep(model, qa, ra, sa, step, touched_a, originals_a, station_a);
    sb = UncountedStep(model, qb, rb, sb, step, touched_b, originals_b, station_b);
  }
  reached_a |= station_a;
  reached_b |= station_b;
  rng_a = ra;
  rng_b = rb;
}

// A shard refilled in place (its vectors keep their capacity for the next
// round) for `learner`'s round starting at `start`.
void BeginShard(LearnerShard& shard, int learner, int64_t round, int start) {
  shard.entries.clear();
  shard.values.clear();
  shard.wide_values.clear();
  shard.visits.clear();
  shard.reached_station = false;
  shard.steps = 0;
  shard.learner = learner;
  shard.round = round;
  shard.start_cell = start;
}

// Room for a round's list of `steps` entries and their originals (one spare).
template <typename V>
void ReserveList(std::vector<uint32_t>& touched, std::vector<V>& originals, int steps) {
  const size_t wanted = static_cast<size_t>(steps) + 1;
  if (touched.size() < wanted) {
    touched.resize(wanted);
    originals.resize(wanted);
  }
}

}  // namespace

void FedAsynQLearner::Run(int learner, const StartStatistics& stats, uint64_t job_seed,
                          int64_t round, int sync_period, bool revert, LearnerShard& shard) {
  WithValueType(table_.precision(), [&]<typename V>(V*) {
    RunIn<V>(learner, stats, job_seed, round, sync_period, revert, shard);
  });
}

template <typename V>
void FedAsynQLearner::RunIn(int learner, const StartStatistics& stats, uint64_t job_seed,
                            int64_t round, int sync_period, bool revert, LearnerShard& shard) {
  if (!revert) twin_in_sync_ = false;  // table_ keeps this round's updates
  Rng rng(LearnerRoundSeed(job_seed, learner, round));
  const int start = stats.Draw(rng);
  BeginShard(shard, learner, round, start);
  if (start < 0) return;

  V* q = table_.Values<V>().data();
  std::vector<V>& originals = Originals<V>();
  const size_t table_entries = table_.size();
  bool reached = model_.is_station(start);
  // Every cell of a region has an in-region move except in a 1x1 region,
  // which takes no step.
  const int steps = model_.action_count(start) > 0 ? std::max(0, sync_period) : 0;
  if (!count_visits_) {
    ReserveList(touched_, originals, steps);
    const size_t listed = Walk<true, false>(model_, q, rng, start, steps, reached, nullptr, 0, 0,
                                            touched_.data(), originals.data());
    shard.reached_station = reached;
    shard.steps = steps;
    FinishUncounted(q, touched_.data(), originals.data(), listed, revert, shard);
    return;
  }

  // Scratch sized for the round; the slots are all empty between rounds.
  const size_t most_touched =
      static_cast<size_t>(std::clamp<int64_t>(sync_period, 0, static_cast<int64_t>(table_entries)));
  const size_t wanted = std::max<size_t>(16, std::bit_ceil(2 * most_touched));
  if (slots_.size() < wanted) slots_.assign(wanted, Slot{});
  ReserveList(touched_, originals, static_cast<int>(most_touched));
  const bool direct = slots_.size() >= table_entries;
  const uint32_t mask = static_cast<uint32_t>(slots_.size() - 1);
  const int shift = 32 - std::countr_zero(slots_.size());

  const size_t listed =
      direct ? Walk<true, true>(model_, q, rng, start, steps, reached, slots_.data(), mask, shift,
                                touched_.data(), originals.data())
             : Walk<false, true>(model_, q, rng, start, steps, reached, slots_.data(), mask, shift,
                                 touched_.data(), originals.data());
  shard.reached_station = reached;
  shard.steps = steps;

  for (size_t i = 0; i < listed; ++i) marks_.Mark(touched_[i]);
  marks_.List(shard.entries);
  marks_.Clear(shard.entries);
  std::vector<V>& values = ShardValues<V>(shard);
  values.resize(shard.entries.size());
  shard.visits.resize(shard.entries.size());
  Slot* slots = slots_.data();
  for (size_t i = 0; i < shard.entries.size(); ++i) {
    const uint32_t entry = shard.entries[i];
    values[i] = q[entry];
    shard.visits[i] = slots[direct ? FindSlot<true>(slots, mask, shift, entry)
                                   : FindSlot<false>(slots, mask, shift, entry)]
                          .visits;
  }
  for (size_t i = 0; i < listed; ++i) {
    if (revert) q[touched_[i]] = originals[i];
  }
  // Empty the used slots: all of them at once unless few were used.
  if (listed * 4 < slots_.size()) {
    for (size_t i = 0; i < listed; ++i) {
      const uint32_t entry = touched_[i];
      slots[direct ? FindSlot<true>(slots, mask, shift, entry)
                   : FindSlot<false>(slots, mask, shift, entry)] = Slot{};
    }
  } else {
    std::fill(slots_.begin(), slots_.end(), Slot{});
  }
  return;
}

template <typename V>
void FedAsynQLearner::FinishUncounted(V* q, const uint32_t* touched, const V* originals,
                                      size_t listed, bool revert, LearnerShard& shard) {
  for (size_t i = 0; i < listed; ++i) marks_.Mark(touched[i]);
  marks_.List(shard.entries);
  marks_.Clear(shard.entries);
  std::vector<V>& values = ShardValues<V>(shard);
  values.resize(shard.entries.size());
  for (size_t i = 0; i < shard.entries.size(); ++i) values[i] = q[shard.entries[i]];
  // What an absent count decodes to on the wire (protocol::ShardFromMessage).
  shard.visits.assign(shard.entries.size(), 1u);
  if (revert) {
    for (size_t i = listed; i-- > 0;) q[touched[i]] = originals[i];
  }
}

template <typename V>
void FedAsynQLearner::RunTwoAndRevert(int learner_a, int learner_b, const StartStatistics& stats,
                                      uint64_t job_seed, int64_t round, int sync_period,
                                      LearnerShard& shard_a, LearnerShard& shard_b) {
  Rng rng_a(LearnerRoundSeed(job_seed, learner_a, round));
  Rng rng_b(LearnerRoundSeed(job_seed, learner_b, round));
  const int start_a = stats.Draw(rng_a), start_b = stats.Draw(rng_b);
  const int steps = std::max(0, sync_period);
  if (start_a < 0 || start_b < 0 || steps == 0 || model_.action_count(start_a) == 0 ||
      model_.action_count(start_b) == 0) {
    // Nothing to interleave (no start, or a 1x1 region): one at a time.
    Run(learner_a, stats, job_seed, round, sync_period, true, shard_a);
    Run(learner_b, stats, job_seed, round, sync_period, true, shard_b);
    return;
  }
  if (!twin_in_sync_) {  // table_ is the round's starting table here
    twin_ = table_;
    twin_in_sync_ = true;
  }
  std::vector<V>& originals = Originals<V>();
  std::vector<V>& twin_originals = TwinOriginals<V>();
  ReserveList(touched_, originals, steps);
  ReserveList(twin_touched_, twin_originals, steps);
  BeginShard(shard_a, learner_a, round, start_a);
  BeginShard(shard_b, learner_b, round, start_b);
  shard_a.steps = shard_b.steps = steps;
  bool reached_a = model_.is_station(start_a), reached_b = model_.is_station(start_b);
  V* qa = table_.Values<V>().data();
  V* qb = twin_.Values<V>().data();
  WalkTwo(model_, qa, qb, rng_a, rng_b, start_a, start_b, steps, reached_a, reached_b,
          touched_.data(), originals.data(), twin_touched_.data(), twin_originals.data());
  shard_a.reached_station = reached_a;
  shard_b.reached_station = reached_b;
  const size_t listed = static_cast<size_t>(steps);
  FinishUncounted(qa, touched_.data(), originals.data(), listed, true, shard_a);
  FinishUncounted(qb, twin_touched_.data(), twin_originals.data(), listed, true, shard_b);
}

void FedAsynQLearner::RunRoundsAndRevert(const int* learners, int count,
                                         const StartStatistics& stats, uint64_t job_seed,
                                         int64_t round, int sync_period, LearnerShard* shards) {
  int i = 0;
  if (!count_visits_) {
    WithValueType(table_.precision(), [&]<typename V>(V*) {
      for (; i + 1 < count; i += 2) {
        RunTwoAndRevert<V>(learners[i], learners[i + 1], stats, job_seed, round, sync_period,
                           shards[i], shards[i + 1]);
      }
    });
  }
  for (; i < count; ++i) {
    Run(learners[i], stats, job_seed, round, sync_period, true, shards[i]);
  }
}

template <typename V>
void FedAsynQLearner::ApplyAverage(const std::vector<uint32_t>& entries,
                                   const std::vector<V>& values) {
  std::vector<V>& table = table_.Values<V>();
  for (size_t i = 0; i < entries.size(); ++i) table[entries[i]] = values[i];
  if (twin_in_sync_) {
    std::vector<V>& twin = twin_.Values<V>();
    for (size_t i = 0; i < entries.size(); ++i) twin[entries[i]] = values[i];
  }
}
template void FedAsynQLearner::ApplyAverage(const std::vector<uint32_t>&,
                                            const std::vector<float>&);
template void FedAsynQLearner::ApplyAverage(const std::vector<uint32_t>&,
                                            const std::vector<double>&);

FederatedAverager::FederatedAverager(int table_entries, Averaging averaging)
    : averaging_(averaging),
      table_entries_(table_entries),
      marks_(static_cast<size_t>(table_entries)),
      positions_(table_entries <= kDensePositionsLimit ? static_cast<size_t>(table_entries) : 0) {
  // Only the differences l_k - max_j l_j = -(N_max - N_k) * (-log(1 - eta))
  // are ever exponentiated (log-sum-exp), so the weights stay finite for any
  // visit count; they depend only on d = N_max - N_k, tabulated here.
  const double log_base = -std::log(1.0 - kImportanceEta);
  decay_.resize(kDecayTableSize);
  for (size_t d = 0; d < kDecayTableSize; ++d) {
    decay_[d] = std::exp(-static_cast<double>(d) * log_base);
  }
}

template <typename V>
Status FederatedAverager::Combine(const std::vector<LearnerShard>& shards, QTable& shared,
                                  StartStatistics& stats, std::vector<uint32_t>& entries,
                                  std::vector<V>& values) {
  // Validate everything before changing anything.
  if (shared.precision() != kPrecisionOf<V>) {
    return Error::Corrupt("FederatedAverager: table precision mismatch");
  }
  if (static_cast<int64_t>(shared.size()) != table_entries_) {
    return Error::Corrupt("FederatedAverager: table size mismatch");
  }
  for (size_t k = 0; k < shards.size(); ++k) {
    const LearnerShard& shard = shards[k];
    const std::vector<V>& shard_values = ShardValues<V>(shard);
    if (shard.learner != static_cast<int>(k) || shard_values.size() != shard.entries.size() ||
        shard.visits.size() != shard.entries.size()) {
      return Error::Corrupt("FederatedAverager: malformed shard");
    }
    for (size_t j = 0; j < shard.entries.size(); ++j) {
      if (shard.entries[j] >= static_cast<uint32_t>(table_entries_) ||
          !std::isfinite(shard_values[j])) {
        return Error::Corrupt("FederatedAverager: shard entry out of range or not finite");
      }
    }
    if (shard.start_cell >= 0 && stats.SlotOf(shard.start_cell) < 0) {
      return Error::Corrupt("FederatedAverager: shard start is not a start cell");
    }
  }

  // The union U of all shards' entries, ascending.
  for (const LearnerShard& shard : shards) {
    for (uint32_t entry : shard.entries) marks_.Mark(entry);
  }
  marks_.List(entries);

  // Per entry of U and learner k: Q_k(e) and N_k(e); learners that did not
  // touch e hold the shared value with no visits.
  const size_t learners = shards.size();
  std::vector<V>& shared_values = shared.Values<V>();
  std::vector<V>& learner_values = OfValueType<V>(learner_values_, learner_wide_values_);
  learner_values.resize(entries.size() * learners);
  // Equal averaging needs no visit counts.
  const bool weighted = averaging_ != Averaging::kEqual;
  learner_visits_.resize(weighted ? entries.size() * learners : 0);
  for (size_t i = 0; i < entries.size(); ++i) {
    std::fill_n(learner_values.begin() + static_cast<ptrdiff_t>(i * learners), learners,
                shared_values[entries[i]]);
  }
  if (weighted) std::fill(learner_visits_.begin(), learner_visits_.end(), 0u);
  const bool dense = !positions_.empty();
  if (dense) {
    for (size_t i = 0; i < entries.size(); ++i) positions_[entries[i]] = static_cast<uint32_t>(i);
  }
  for (size_t k = 0; k < learners; ++k) {
    const LearnerShard& shard = shards[k];
    const std::vector<V>& shard_values = ShardValues<V>(shard);
    for (size_t j = 0; j < shard.entries.size(); ++j) {
      const uint32_t entry = shard.entries[j];
      const size_t slot = (dense ? positions_[entry] : marks_.Position(entry)) * learners + k;
      learner_values[slot] = shard_values[j];
      if (weighted) learner_visits_[slot] = shard.visits[j];
    }
  }

  // Averages, each summed in double in learner order.
  values.resize(entries.size());
  size_t first_left = 0;
  if (!weighted) {
    // Four entries at a time: each sum still runs in learner order, but four
    // independent chains of additions hide the latency of one (12 dependent
    // additions per entry were most of an equal average's time).
    constexpr size_t kBlock = 4;
    const double scale = static_cast<double>(learners);
    for (; first_left + kBlock <= entries.size(); first_left += kBlock) {
      const V* q = &learner_values[first_left * learners];
      double sums[kBlock] = {0.0, 0.0, 0.0, 0.0};
      for (size_t k = 0; k < learners; ++k) {
        for (size_t b = 0; b < kBlock; ++b) sums[b] += q[b * learners + k];
      }
      for (size_t b = 0; b < kBlock; ++b) {
        const size_t i = first_left + b;
        values[i] = static_cast<V>(sums[b] / scale);
        shared_values[entries[i]] = values[i];
      }
    }
  }
  const double log_base = -std::log(1.0 - kImportanceEta);
  for (size_t i = first_left; i < entries.size(); ++i) {
    const V* q = &learner_values[i * learners];
    double sum = 0.0;
    if (!weighted) {
      for (size_t k = 0; k < learners; ++k) sum += q[k];
      sum /= static_cast<double>(learners);
    } else {
      const uint32_t* n = &learner_visits_[i * learners];
      const uint32_t most = *std::max_element(n, n + learners);
      // exp(l_k - max_j l_j) with l_k = N_k * -log(1 - eta).
      const auto weight = [&](uint32_t visits) {
        const uint32_t d = most - visits;
        return d < decay_.size() ? decay_[d] : std::exp(-static_cast<double>(d) * log_base);
      };
      // sum_k w_k Q_k with w_k = e_k / sum_j e_j, normalised once at the end.
      double total_weight = 0.0;
      for (size_t k = 0; k < learners; ++k) {
        const double e = weight(n[k]);
        total_weight += e;
        sum += e * q[k];
      }
      sum /= total_weight;
    }
    values[i] = static_cast<V>(sum);
    shared_values[entries[i]] = values[i];
  }

  marks_.Clear(entries);

  for (const LearnerShard& shard : shards) {
    if (shard.start_cell >= 0) stats.Record(stats.SlotOf(shard.start_cell), shard.reached_station);
  }
  return Ok{};
}
template Status FederatedAverager::Combine(const std::vector<LearnerShard>&, QTable&,
                                           StartStatistics&, std::vector<uint32_t>&,
                                           std::vector<float>&);
template Status FederatedAverager::Combine(const std::vector<LearnerShard>&, QTable&,
                                           StartStatistics&, std::vector<uint32_t>&,
                                           std::vector<double>&);

}  // namespace dynapath
