#pragma once
#ifndef DYNAPATH_CORE_PRIVATE  // defined for dynapath_core and the tests of its insides
#error "private to dynapath_core: include its face, dynapath/federated_job.h"
#endif
// Federated asynchronous Q-learning (FedAsynQ) of SPEC section 7, split into
// the pieces a distributed run needs (private to core: other layers use
// them through dynapath/federated_job.h):
//
//   * FedAsynQLearner: one of the K learners. A round is a pure function of
//     (the round's starting table, the shared start statistics, job seed,
//     learner index, round index): the learner draws its start, takes tau
//     random in-region steps updating its own table, and reports what it
//     changed as a sparse LearnerShard (dynapath/federated_job.h).
//   * FederatedAverager: combines the K shards of a round, in learner order,
//     into the new shared table (EqAvg or ImAvg, log-space weights) and merges
//     the learners' start outcomes into the shared statistics.
//   * dynapath/federated_job.h runs rounds of these learners and averager, in
//     this process (TrainFedAsynQ, LocalTrainer) or on agents.
//
// Sparse shards: all learners start a round from the same table, so the
// average differs from it only where some learner made an update. A shard
// lists those entries (index, value, visits), at most tau of them, which
// keeps averaging and messages proportional to tau, not to the region size.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/learn/region_model.h"
#include "dynapath/federated_job.h"
#include "dynapath/q_table.h"
#include "dynapath/rng.h"
#include "dynapath/start_statistics.h"
#include "dynapath/training_job.h"

namespace dynapath {

// A set of table entries kept as a bitmap with one summary bit per 64-bit
// word: marking is O(1), and listing the marked entries in ascending order
// costs one step per 64 x 64 entries of the table plus one per marked word,
// against some 20 ns per entry for std::sort or a scan of every word (125,000
// words per round at a 1000x1000 root, where a round marks a few thousand
// entries). Memory: 1 bit per entry, and a rank (4 bytes) per word.
class SortedMarks {
 public:
  explicit SortedMarks(size_t entries = 0);

  void Mark(uint32_t entry) {
    uint64_t& word = bits_[entry >> 6];
    if (word == 0) summary_[entry >> 12] |= uint64_t{1} << ((entry >> 6) & 63);
    word |= uint64_t{1} << (entry & 63);
  }
  // Replaces `list` by the marked entries in ascending order; they stay
  // marked, and Position works, until Clear.
  void List(std::vector<uint32_t>& list);
  // Index in the last List of a marked entry.
  uint32_t Position(uint32_t entry) const {
    const uint64_t below = (uint64_t{1} << (entry & 63)) - 1;
    return rank_[entry >> 6] + PopCount(bits_[entry >> 6] & below);
  }
  // Bits set in `x`. std::popcount is a library call on the baseline
  // x86-64 target (no POPCNT instruction); this is a few inline operations.
  static uint32_t PopCount(uint64_t x) {
    x = x - ((x >> 1) & 0x5555555555555555ull);
    x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
    x = (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0Full;
    return static_cast<uint32_t>((x * 0x0101010101010101ull) >> 56);
  }
  // Unmarks the entries of the last List (which must be `list`).
  void Clear(const std::vector<uint32_t>& list);

 private:
  std::vector<uint64_t> bits_;     // bit per entry
  std::vector<uint64_t> summary_;  // bit per word of bits_: the word is not zero
  std::vector<uint32_t> rank_;     // per marked word: marked entries before it
};

// The seed of learner `learner` in round `round` of a job.
uint64_t LearnerRoundSeed(uint64_t job_seed, int learner, int64_t round);

class FedAsynQLearner {
 public:
  // `model` must outlive the learner. `table`: the round's starting table
  // (the job's warm start, then every average) is loaded by Reset/Apply.
  FedAsynQLearner(const RegionModel& model, int learner_index);

  // Sets the learner's table (start of a job, or recovery after a fault).
  void Reset(const QTable& table);

  // Runs one round of `sync_period` steps and returns its shard. The table
  // must equal the shared table of the round's start.
  LearnerShard RunRound(const StartStatistics& stats, uint64_t job_seed, int64_t round,
                        int sync_period);

  // Runs round `round` of learner `learner` (any index, not only this
  // object's: the shard is the one RunRound of that learner gives), then
  // restores the table to the round's start. One object can so play several
  // learners in turn on one table (TrainFedAsynQ; an agent's learners of a
  // job on one thread) with one ApplyAverage per round instead of one per
  // learner, which matters once the tables outgrow the caches.
  LearnerShard RunRoundAndRevert(int learner, const StartStatistics& stats, uint64_t job_seed,
                                 int64_t round, int sync_period);

  // Brings the learner's table to the new shared table: `entries`/`values`
  // are the averaged entries (the union of all shards' entries); every other
  // entry is unchanged since the round started. V: the table's value type.
  template <typename V>
  void ApplyAverage(const std::vector<uint32_t>& entries, const std::vector<V>& values);

  // Plays learners learners[0..count) of round `round` in turn, writing
  // shards[i] = RunRoundAndRevert(learners[i], ...).
  void RunRoundsAndRevert(const int* learners, int count, const StartStatistics& stats,
                          uint64_t job_seed, int64_t round, int sync_period, LearnerShard* shards);

  const QTable& table() const { return table_; }

  // Whether rounds count visits N_k(s, a) (default). Equal averaging does
  // not use them: without counting, a round is cheaper and its shard's
  // visits are all 1, what an absent count decodes to on the wire.
  void set_count_visits(bool count) { count_visits_ = count; }

  // One slot of the visit counts' hash table (fedasynq.cc).
  struct Slot {
    uint32_t key = 0;  // entry + 1, 0 = empty
    uint32_t visits = 0;
  };

 private:
  const RegionModel& model_;
  int learner_index_;
  bool count_visits_ = true;
  QTable table_;
  // Scratch of a round (no allocation per step), proportional to the round,
  // not to the region: the entries touched in order of first touch (one
  // spare) and their values before the round, and an open-addressing hash
  // table of (entry, visits) with at least twice as many slots as the round
  // can touch entries (a dense per-entry array would add 4 bytes per table
  // entry per learner and a cache miss per new entry). When the slots
  // outnumber the table's entries, slot = entry: no hashing, no collisions
  // (a leaf's table).
  std::vector<uint32_t> touched_;
  std::vector<float> originals_;        // float tables
  std::vector<double> wide_originals_;  // double tables
  // A second copy of the table, equal to table_ between rounds while
  // twin_in_sync_, so that two learners' rounds can be walked interleaved
  // (RunTwoAndRevert), with its own round scratch.
  QTable twin_;
  bool twin_in_sync_ = false;
  std::vector<uint32_t> twin_touched_;
  std::vector<float> twin_originals_;
  std::vector<double> twin_wide_originals_;
  std::vector<Slot> slots_;
  SortedMarks marks_;  // sorts the shard's entries

  void Run(int learner, const StartStatistics& stats, uint64_t job_seed, int64_t round,
           int sync_period, bool revert, LearnerShard& shard);
  template <typename V>
  void RunIn(int learner, const StartStatistics& stats, uint64_t job_seed, int64_t round,
             int sync_period, bool revert, LearnerShard& shard);
  // Equal averaging: two learners' rounds at once (one on the twin table).
  template <typename V>
  void RunTwoAndRevert(int learner_a, int learner_b, const StartStatistics& stats,
                       uint64_t job_seed, int64_t round, int sync_period, LearnerShard& shard_a,
                       LearnerShard& shard_b);
  // The end of an uncounted round: the shard's sorted entries and values
  // from the round's list (repeats included), then the revert.
  template <typename V>
  void FinishUncounted(V* q, const uint32_t* touched, const V* originals, size_t listed,
                       bool revert, LearnerShard& shard);
  template <typename V>
  std::vector<V>& Originals() {
    return OfValueType<V>(originals_, wide_originals_);
  }
  template <typename V>
  std::vector<V>& TwinOriginals() {
    return OfValueType<V>(twin_originals_, twin_wide_originals_);
  }
};

// Combines one round's shards into the shared table.
class FederatedAverager {
 public:
  FederatedAverager(int table_entries, Averaging averaging);

  // `shared`: the round's starting table, updated in place to the average.
  // `shards`: exactly one per learner, in learner order (shards[k].learner == k),
  // with values in the table's precision V.
  // Writes the averaged entries (ascending) to `entries`/`values` and records
  // every shard's start outcome in `stats` in learner order. Error, with
  // nothing changed, when a shard is malformed (wrong learner order or sizes,
  // an entry outside the table or not finite, a start that is no start cell)
  // or the table is not of value type V.
  template <typename V>
  Status Combine(const std::vector<LearnerShard>& shards, QTable& shared, StartStatistics& stats,
                 std::vector<uint32_t>& entries, std::vector<V>& values);

 private:
  Averaging averaging_;
  int table_entries_;
  // Scratch reused between rounds (no allocation once warmed up), about one
  // bit per table entry plus what a round touches:
  SortedMarks marks_;  // the union of the shards' entries
  // Small tables (a leaf's): entry -> position in the union, one load where
  // SortedMarks::Position costs a rank and a software popcount. Empty for
  // tables above kDensePositionsLimit entries, which use the marks' ranks.
  static constexpr int kDensePositionsLimit = 1 << 16;
  std::vector<uint32_t> positions_;
  std::vector<float> learner_values_;  // |U| x K: Q_k(e), the shared value if untouched
  std::vector<double> learner_wide_values_;  // the same for double tables
  std::vector<uint32_t> learner_visits_;  // |U| x K: N_k(e)
  std::vector<double> decay_;             // decay_[d] = (1 - eta)^d = exp(-d * -log(1 - eta))
};

}  // namespace dynapath
