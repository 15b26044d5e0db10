#include "agent/agent.h"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <mutex>

#include "core/single_agent_learner.h"
#include "lcmtypes/protocol/channels.h"

namespace dynapath::agent {

// A split job: the learners of it this agent hosts, each with its own table,
// and a replica of the job's start statistics (kept equal to the
// coordinator's by recording every average's start outcomes).
struct Agent::HostedJob {
  int index = 0;  // in the batch
  protocol::ReceivedJob received;
  std::unique_ptr<RegionModel> model;
  std::vector<std::unique_ptr<FedAsynQLearner>> learners;
  StartStatistics stats;
  int64_t rounds = 0;
};

Agent::Agent(protocol::Bus& bus, AgentOptions options)
    : bus_(bus),
      options_(options),
      coordinator_(bus, &inbox_),
      pool_(std::max(1, options.threads)) {
  namespace ch = protocol::channel;
  bus_.Subscribe<job_batch_t>(ch::kJobs, [this](job_batch_t& batch) {
    inbox_.Post([this, batch = std::move(batch)] { OnBatch(batch); });
  });
  bus_.Subscribe<average_t>(ch::kAverages, [this](average_t& average) {
    inbox_.Post([this, average = std::move(average)] { OnAverage(average); });
  });
}

Agent::~Agent() = default;

AgentExit Agent::Run(const std::atomic<bool>& stop) {
  using Verdict = protocol::CoordinatorWatch::Verdict;
  heartbeat_t base{};
  base.role = heartbeat_t::ROLE_AGENT;
  base.sender = options_.id;
  base.state = heartbeat_t::STATE_RUNNING;
  base.threads = pool_.threads();
  const auto fill = [this](heartbeat_t& beat) {
    beat.batch_id = reported_batch_;
    beat.epoch = reported_epoch_;
    beat.round = reported_round_;
  };
  // Watchdog on the heartbeat thread: the agent thread may be deep in a long
  // job and cannot notice that the coordinator is gone.
  const auto watchdog = [this] {
    if (!options_.exit_process_when_orphaned) return;
    if (coordinator_.Check(options_.startup_timeout_seconds,
                           options_.coordinator_timeout_seconds + 0.5) == Verdict::kGone) {
      spdlog::error("agent {}: the coordinator is gone; exiting", options_.id);
      std::fflush(nullptr);
      _exit(3);
    }
  };
  protocol::HeartbeatSender heartbeat(bus_, base, options_.heartbeat_seconds, fill, watchdog);
  spdlog::info("agent {}: {} threads, waiting for the coordinator of run {}", options_.id,
               pool_.threads(), bus_.run_id());
  while (!stop) {
    inbox_.RunFor(std::chrono::milliseconds(50));
    switch (coordinator_.Check(options_.startup_timeout_seconds,
                               options_.coordinator_timeout_seconds)) {
      case Verdict::kFinished:
        return AgentExit::kCoordinatorFinished;
      case Verdict::kFailed:
        return AgentExit::kCoordinatorFailed;
      case Verdict::kNeverCame:
        spdlog::error("agent {}: no coordinator of run {} appeared within {:.0f} s", options_.id,
                      bus_.run_id(), options_.startup_timeout_seconds);
        return AgentExit::kCoordinatorGone;
      case Verdict::kGone:
        spdlog::error("agent {}: the coordinator of run {} is gone", options_.id, bus_.run_id());
        return AgentExit::kCoordinatorGone;
      default:
        break;
    }
  }
  return AgentExit::kStopped;
}

void Agent::OnBatch(const job_batch_t& batch) {
  if (batch.batch_id < batch_id_ || (batch.batch_id == batch_id_ && batch.epoch < epoch_)) return;
  if (batch.batch_id == batch_id_ && batch.epoch == epoch_) {
    Resend();  // the coordinator is missing something we sent
    return;
  }
  // A new batch, or a new epoch of this one: start over from its contents.
  batch_id_ = batch.batch_id;
  epoch_ = batch.epoch;
  importance_ = batch.averaging == 1;
  sync_period_ = batch.sync_period;
  split_jobs_.clear();
  results_.clear();
  last_shards_.reset();
  round_ = -1;
  reported_batch_ = batch_id_;
  reported_epoch_ = epoch_;
  reported_round_ = -1;

  std::vector<int> whole;
  std::vector<std::vector<int>> split_learners(static_cast<size_t>(batch.num_jobs));
  for (int i = 0; i < batch.num_items; ++i) {
    if (batch.item_agent[i] != options_.id) continue;
    if (batch.item_learner[i] < 0) {
      whole.push_back(batch.item_job[i]);
    } else {
      split_learners[static_cast<size_t>(batch.item_job[i])].push_back(batch.item_learner[i]);
    }
  }
  int64_t start_round = -1;
  for (int j = 0; j < batch.num_jobs; ++j) {
    if (split_learners[j].empty()) continue;
    Result<protocol::ReceivedJob> received = protocol::JobFromBatch(batch, j);
    if (!received) {
      spdlog::error("agent {}: dropped batch {}: {}", options_.id, batch.batch_id,
                    received.error().message);
      return;
    }
    auto hosted = std::make_unique<HostedJob>();
    hosted->index = j;
    hosted->received = std::move(*received);
    try {
      hosted->model = std::make_unique<RegionModel>(hosted->received.job);
    } catch (const std::exception& e) {
      spdlog::error("agent {}: dropped batch {}: {}", options_.id, batch.batch_id, e.what());
      return;
    }
    const TrainingJob& job = hosted->received.job;
    hosted->rounds = FederatedRounds(job.region, job.federated);
    if (hosted->received.attempts.empty()) {
      hosted->stats = StartStatistics(hosted->model->start_cells());
    } else {
      hosted->stats = StartStatistics(hosted->model->start_cells(), hosted->received.attempts,
                                      hosted->received.successes);
    }
    for (int learner : split_learners[j]) {
      hosted->learners.push_back(std::make_unique<FedAsynQLearner>(*hosted->model, learner));
      hosted->learners.back()->Reset(job.warm_start);
    }
    start_round = std::max(start_round, hosted->received.start_round);
    split_jobs_.push_back(std::move(hosted));
  }
  if (!whole.empty()) RunWholeJobs(batch, whole);
  if (!split_jobs_.empty()) {
    round_ = start_round;
    RunSplitRound();
  }
}

void Agent::RunWholeJobs(const job_batch_t& batch, const std::vector<int>& jobs) {
  std::vector<protocol::ReceivedJob> received;
  for (int j : jobs) {
    Result<protocol::ReceivedJob> job = protocol::JobFromBatch(batch, j);
    if (!job) {
      spdlog::error("agent {}: dropped batch {}: {}", options_.id, batch.batch_id,
                    job.error().message);
      return;
    }
    received.push_back(std::move(*job));
  }
  std::mutex mutex;
  // Jobs run one per thread; each result is sent as soon as it is ready.
  pool_.ParallelFor(static_cast<int>(jobs.size()), [&](int i) {
    const TrainingJob& job = received[i].job;
    TrainingResult result;
    try {
      result = job.kind == LearnerKind::kFedAsynQ ? TrainFedAsynQ(job) : TrainSingleAgent(job);
    } catch (const std::exception& e) {
      spdlog::error("agent {}: job {} of batch {} failed: {}", options_.id, jobs[i], batch.batch_id,
                    e.what());
      return;
    }
    job_result_t message{};
    message.run_id = bus_.run_id();
    message.batch_id = batch.batch_id;
    message.epoch = batch.epoch;
    message.agent = options_.id;
    message.job = jobs[i];
    message.episodes_or_rounds = result.episodes_or_rounds;
    message.steps = result.steps;
    message.values = std::move(result.table.values());
    message.num_values = static_cast<int32_t>(message.values.size());
    bus_.Publish(protocol::channel::kResults, message);
    std::lock_guard lock(mutex);
    results_.push_back(std::move(message));
    reported_round_ = static_cast<int64_t>(results_.size());
  });
}

void Agent::RunSplitRound() {
  // (job, learner) pairs of the jobs still running at round_.
  std::vector<std::pair<HostedJob*, int>> items;
  for (auto& job : split_jobs_) {
    if (round_ >= job->rounds) continue;
    for (size_t k = 0; k < job->learners.size(); ++k)
      items.emplace_back(job.get(), static_cast<int>(k));
  }
  if (items.empty()) return;  // every hosted job is finished
  std::vector<LearnerShard> shards(items.size());
  pool_.ParallelFor(static_cast<int>(items.size()), [&](int i) {
    HostedJob& job = *items[i].first;
    shards[i] = job.learners[items[i].second]->RunRound(job.stats, job.received.job.seed, round_,
                                                        sync_period_);
  });
  shards_t message{};
  message.run_id = bus_.run_id();
  message.batch_id = batch_id_;
  message.epoch = epoch_;
  message.round = round_;
  message.agent = options_.id;
  for (size_t i = 0; i < items.size(); ++i) {
    message.shards.push_back(
        protocol::ShardToMessage(shards[i], items[i].first->index, importance_));
  }
  message.num_shards = static_cast<int32_t>(message.shards.size());
  bus_.Publish(protocol::channel::kShards, message);
  last_shards_ = std::move(message);
  reported_round_ = round_;
}

void Agent::OnAverage(const average_t& average) {
  if (average.batch_id != batch_id_ || average.epoch != epoch_ || split_jobs_.empty()) return;
  if (average.round < round_) {
    Resend();  // our shards of round_ were lost
    return;
  }
  if (average.round > round_) return;  // cannot happen without our shards; ignore
  // Check everything before changing anything.
  std::vector<const job_average_t*> by_job(split_jobs_.size(), nullptr);
  for (const job_average_t& job_average : average.jobs) {
    for (size_t i = 0; i < split_jobs_.size(); ++i) {
      HostedJob& job = *split_jobs_[i];
      if (job.index != job_average.job) continue;
      const int64_t entries = static_cast<int64_t>(job.model->cells()) * kNumActions;
      bool ok = job_average.num_learners == job.received.job.federated.learners &&
                (job_average.entries.empty() || job_average.entries.back() < entries);
      for (int32_t cell : job_average.start_cells)
        ok = ok && (cell < 0 || job.stats.SlotOf(cell) >= 0);
      if (!ok) {
        spdlog::warn("agent {}: dropped an average that does not fit job {}", options_.id,
                     job.index);
        return;
      }
      by_job[i] = &job_average;
    }
  }
  for (size_t i = 0; i < split_jobs_.size(); ++i) {
    HostedJob& job = *split_jobs_[i];
    if (round_ >= job.rounds) continue;
    if (by_job[i] == nullptr) {
      spdlog::warn("agent {}: an average lacks job {}; dropped", options_.id, job.index);
      return;
    }
  }
  for (size_t i = 0; i < split_jobs_.size(); ++i) {
    HostedJob& job = *split_jobs_[i];
    if (by_job[i] == nullptr) continue;
    const job_average_t& a = *by_job[i];
    const std::vector<uint32_t> entries(a.entries.begin(), a.entries.end());
    for (auto& learner : job.learners) learner->ApplyAverage(entries, a.values);
    for (int k = 0; k < a.num_learners; ++k) {
      if (a.start_cells[k] >= 0) job.stats.Record(job.stats.SlotOf(a.start_cells[k]), a.reached[k]);
    }
  }
  ++round_;
  RunSplitRound();
}

void Agent::Resend() {
  if (last_shards_) bus_.Publish(protocol::channel::kShards, *last_shards_);
  for (const job_result_t& result : results_) bus_.Publish(protocol::channel::kResults, result);
}

}  // namespace dynapath::agent
