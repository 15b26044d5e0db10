#pragma once
// The rounds of a training batch's split jobs (jobs whose learners are spread
// over several agents). Every agent publishes one shards_t per round with the
// shards of the learners it hosts; the combiner collects the round's messages
// of all agents and, once all are there, combines each job's shards in
// learner order (RoundAverager, exactly as in-process training) into the
// job's shared table and start statistics (dynapath/federated_job.h).
//
// The coordinator and every agent hosting learners of the batch run the same
// combiner on the same messages, so all hold identical tables after every
// round without an average being sent back: a round costs one message per
// agent and a single network hop. The coordinator's copy is the authoritative
// one (final tables, and the restart point when an agent is lost).
//
// Messages of the round being collected and of the next one are kept (a fast
// agent may be one round ahead); older ones are reported as kPast so the
// caller can tell a lagging sender, newer ones are dropped.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dynapath/federated_job.h"
#include "dynapath/result.h"
#include "dynapath/shards_t.hpp"
#include "dynapath/training_job.h"

namespace dynapath::protocol {

class RoundCombiner {
 public:
  // A split job of the batch: where it stands, and its index in the batch
  // (the shards' job field).
  struct Job : FederatedState {
    int index = 0;
    Job() = default;
    Job(int batch_index, FederatedState state)
        : FederatedState(std::move(state)), index(batch_index) {}
    // Job `index` of a batch before its first round.
    static Job From(int index, const TrainingJob& job);
  };
  // (job index, learner) pairs an agent hosts.
  using Items = std::map<int, std::vector<std::pair<int, int>>>;

  // Error unless every item names a learner of the jobs and every learner of
  // every job is hosted exactly once (received items are checked with it).
  static Status CheckItems(const std::vector<Job>& jobs, const Items& items);
  // `items` must pass CheckItems. `rounds_ahead`: how many rounds past
  // round() are kept for later (at most `ahead_bytes` of them). An agent
  // cannot run more than one round ahead of the slowest agent (each round
  // starts from everyone's last one), so 1 suffices for agents; the
  // coordinator, which only listens, may fall further behind when shards
  // are lost on their way to it, and keeps what the agents sent meanwhile
  // so that it asks again for the lost round alone.
  RoundCombiner(std::vector<Job> jobs, Items items, int64_t start_round, int rounds_ahead = 1,
                int64_t ahead_bytes = int64_t{64} << 20);

  // The round being collected.
  int64_t round() const { return round_; }
  // Every job has all its rounds combined.
  bool Finished() const;

  enum class Added { kStored, kDuplicate, kPast, kFuture, kInvalid };
  // Keeps `message` (batch and epoch are the caller's to check). kInvalid
  // (with `why`) when it does not match the sender's items or the jobs'
  // tables and statistics.
  Added Add(const shards_t& message, std::string* why = nullptr);
  // All shards of round() are there.
  bool RoundComplete() const;
  // Agents whose shards of round() are missing.
  std::vector<int> Missing() const;

  // What a round changed in job `index` (RoundAverager::Combine's average).
  struct JobRound : RoundAverage {
    int index = 0;
  };
  // Combines round() (RoundComplete() must hold) and moves to the next one.
  std::vector<JobRound> Combine();

  // The job of batch index `index` (must be one of the combiner's jobs).
  const Job& job(int index) const;
  const std::vector<Job>& jobs() const { return jobs_; }
  const Items& items() const { return items_; }

 private:
  bool Running(int job_index, int64_t round) const;
  // The agent's items of the jobs still running in `round`, sorted.
  std::vector<std::pair<int, int>> Expected(int agent, int64_t round) const;
  std::string Mismatch(const shards_t& message) const;

  std::vector<Job> jobs_;
  std::map<int, size_t> position_;  // batch index -> position in jobs_
  std::vector<RoundAverager> averagers_;
  Items items_;
  int64_t round_ = 0;
  int rounds_ahead_;
  int64_t ahead_bytes_;
  // round -> agent -> its message (rounds round_ .. round_ + rounds_ahead_),
  // and their encoded bytes past round_.
  std::map<int64_t, std::map<int, shards_t>> pending_;
  int64_t pending_ahead_bytes_ = 0;
};

}  // namespace dynapath::protocol
