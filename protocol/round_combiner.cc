#include "protocol/round_combiner.h"

#include <algorithm>
#include <cassert>

#include "dynapath/mdp.h"
#include "protocol/convert.h"
#include "protocol/varint.h"

namespace dynapath::protocol {

RoundCombiner::Job RoundCombiner::Job::From(int batch_index, const TrainingJob& job) {
  return Job(batch_index, FederatedState::Start(job));
}

Status RoundCombiner::CheckItems(const std::vector<Job>& jobs, const Items& items) {
  std::map<int, size_t> position;
  std::vector<std::vector<int>> hosts(jobs.size());
  for (size_t i = 0; i < jobs.size(); ++i) {
    position[jobs[i].index] = i;
    hosts[i].assign(static_cast<size_t>(std::max(0, jobs[i].learners)), 0);
  }
  for (const auto& [agent, owned] : items) {
    for (const auto& [job, learner] : owned) {
      auto it = position.find(job);
      if (it == position.end() || learner < 0 || learner >= jobs[it->second].learners) {
        return Error::Corrupt("round combiner: an item names no learner of its jobs");
      }
      ++hosts[it->second][static_cast<size_t>(learner)];
    }
  }
  for (const std::vector<int>& counts : hosts) {
    for (int count : counts) {
      if (count != 1) return Error::Corrupt("round combiner: a learner is not hosted once");
    }
  }
  return Ok{};
}

RoundCombiner::RoundCombiner(std::vector<Job> jobs, Items items, int64_t start_round,
                             int rounds_ahead, int64_t ahead_bytes)
    : jobs_(std::move(jobs)),
      items_(std::move(items)),
      round_(start_round),
      rounds_ahead_(std::max(1, rounds_ahead)),
      ahead_bytes_(ahead_bytes) {
  // The caller checked the items (received ones with CheckItems; the
  // coordinator's are its own plan).
  assert(CheckItems(jobs_, items_).ok());
  for (size_t i = 0; i < jobs_.size(); ++i) {
    position_[jobs_[i].index] = i;
    averagers_.emplace_back(jobs_[i]);
  }
  for (auto& [agent, owned] : items_) std::sort(owned.begin(), owned.end());
}

bool RoundCombiner::Finished() const {
  for (const Job& job : jobs_) {
    if (round_ < job.rounds) return false;
  }
  return true;
}

const RoundCombiner::Job& RoundCombiner::job(int index) const {
  return jobs_.at(position_.at(index));
}

bool RoundCombiner::Running(int job_index, int64_t round) const {
  return round < jobs_[position_.at(job_index)].rounds;
}

std::vector<std::pair<int, int>> RoundCombiner::Expected(int agent, int64_t round) const {
  std::vector<std::pair<int, int>> expected;
  auto it = items_.find(agent);
  if (it == items_.end()) return expected;
  for (const auto& item : it->second) {
    if (Running(item.first, round)) expected.push_back(item);
  }
  return expected;  // sorted: items_ is
}

std::string RoundCombiner::Mismatch(const shards_t& message) const {
  std::vector<std::pair<int, int>> got;
  for (const learner_shard_t& shard : message.shards) got.emplace_back(shard.job, shard.learner);
  std::sort(got.begin(), got.end());
  if (got != Expected(message.agent, message.round)) {
    return "its shards do not match its learners";
  }
  std::vector<uint32_t> entries;
  for (const learner_shard_t& shard : message.shards) {
    const Job& job = this->job(shard.job);
    DecodeAscending(shard.entry_gaps, shard.num_entries, entries);  // validated by the Bus
    if (!entries.empty() && entries.back() >= job.shared.size()) {
      return "a shard's entry lies outside job " + std::to_string(shard.job);
    }
    if (shard.start_cell >= 0 && job.stats.SlotOf(shard.start_cell) < 0) {
      return "a shard's start cell is not a start of job " + std::to_string(shard.job);
    }
    const bool wide = job.shared.precision() == QPrecision::kDouble;
    if ((wide ? shard.num_wide_values : shard.num_values) != shard.num_entries) {
      return "a shard's values are not of the precision of job " + std::to_string(shard.job);
    }
    if ((shard.visit_bytes > 0) !=
        (job.averaging == Averaging::kImportance && shard.num_entries > 0)) {
      return "a shard's visit counts do not fit the averaging of job " + std::to_string(shard.job);
    }
  }
  return {};
}

RoundCombiner::Added RoundCombiner::Add(const shards_t& message, std::string* why) {
  if (message.round < round_) return Added::kPast;
  if (message.round > round_ + rounds_ahead_) return Added::kFuture;
  if (std::string mismatch = Mismatch(message); !mismatch.empty()) {
    if (why != nullptr) *why = std::move(mismatch);
    return Added::kInvalid;
  }
  auto found = pending_.find(message.round);
  if (found != pending_.end() && found->second.count(message.agent) > 0) {
    return Added::kDuplicate;
  }
  if (message.round > round_ + 1) {
    // Further ahead than an agent can be of another: kept within the cap.
    const int64_t bytes = message.getEncodedSize();
    if (pending_ahead_bytes_ + bytes > ahead_bytes_) return Added::kFuture;
    pending_ahead_bytes_ += bytes;
  }
  pending_[message.round].emplace(message.agent, message);
  return Added::kStored;
}

std::vector<int> RoundCombiner::Missing() const {
  std::vector<int> missing;
  auto round = pending_.find(round_);
  for (const auto& [agent, owned] : items_) {
    if (Expected(agent, round_).empty()) continue;
    if (round == pending_.end() || round->second.count(agent) == 0) missing.push_back(agent);
  }
  return missing;
}

bool RoundCombiner::RoundComplete() const { return !Finished() && Missing().empty(); }

std::vector<RoundCombiner::JobRound> RoundCombiner::Combine() {
  assert(RoundComplete());  // callers combine only complete rounds
  const std::map<int, shards_t>& messages = pending_[round_];
  std::vector<JobRound> result;
  std::vector<LearnerShard> shards;
  for (size_t j = 0; j < jobs_.size(); ++j) {
    Job& job = jobs_[j];
    if (round_ >= job.rounds) continue;
    shards.assign(static_cast<size_t>(job.learners), LearnerShard{});
    JobRound job_round;
    job_round.index = job.index;
    for (const auto& [agent, message] : messages) {
      for (const learner_shard_t& shard : message.shards) {
        if (shard.job == job.index) {
          shards[static_cast<size_t>(shard.learner)] = ShardFromMessage(shard, round_);
        }
      }
    }
    // Add() kept only messages whose shards fit the job (Mismatch: learners,
    // entries, start cells; the Bus validated sizes and finiteness), one per
    // learner, so the averager finds nothing malformed.
    [[maybe_unused]] const Status combined = averagers_[j].Combine(shards, job, job_round);
    assert(combined.ok());
    result.push_back(std::move(job_round));
  }
  pending_.erase(round_);
  ++round_;
  // Round round_ + 1 is no longer charged to the cap.
  if (auto next = pending_.find(round_ + 1); next != pending_.end()) {
    for (const auto& [agent, message] : next->second) {
      pending_ahead_bytes_ -= message.getEncodedSize();
    }
  }
  return result;
}

}  // namespace dynapath::protocol
