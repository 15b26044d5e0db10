#include "agent/agent.h"

#include <spdlog/spdlog.h>
#include <sys/random.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <random>

#include "dynapath/convq_training.h"
#include "dynapath/learners.h"
#include "protocol/channels.h"

namespace dynapath::agent {

// A split job: the learners of it this agent hosts (FederatedLearners: at
// most one worker per thread). The job's shared table and start statistics
// live in the combiner.
struct Agent::HostedJob {
  int index = 0;  // in the batch
  protocol::ReceivedJob received;
  std::unique_ptr<FederatedLearners> learners;
  int64_t rounds = 0;
};

namespace {
using Ms = std::chrono::milliseconds;
// Re-send our shards when a round waited this long for others' (doubling
// while it waits on, up to the cap), or twice our own compute time if longer.
constexpr int64_t kNudgeMs = 10;
constexpr int64_t kNudgeCapMs = 250;
// The longest a round's re-send answers later requests for it.
constexpr int64_t kResendCapMs = 20;
// Rounds of our own shards kept for re-sending (at most kKeptBytes of them,
// at least two): the coordinator asks for a round it lacks as soon as it
// sees a later one, by which time the agents may be a few rounds further
// (protocol::kAgentKeptRounds; DistributedTrainer restarts beyond).
constexpr size_t kKeptBytes = size_t{16} << 20;

uint64_t KernelRandom64() {
  uint64_t value = 0;
  if (getrandom(&value, sizeof value, 0) == static_cast<ssize_t>(sizeof value)) return value;
  // No getrandom (very old kernel): std::random_device, still not pid-based.
  std::random_device device;
  return (static_cast<uint64_t>(device()) << 32) ^ device();
}

std::string InstanceText(uint64_t instance) {
  char text[32];
  std::snprintf(text, sizeof text, "instance %016llx", static_cast<unsigned long long>(instance));
  return text;
}

uint64_t ParseInstance(const std::string& message) {
  if (message.rfind("instance ", 0) != 0) return 0;
  return std::strtoull(message.c_str() + 9, nullptr, 16);
}
}  // namespace

int RandomAgentId() { return static_cast<int>(KernelRandom64() % 2147483647ULL) + 1; }

uint64_t RandomInstance() {
  uint64_t value = 0;
  while (value == 0) value = KernelRandom64();
  return value;
}

Agent::Agent(protocol::Bus& bus, AgentOptions options)
    : bus_(bus),
      options_(options),
      coordinator_(bus, &inbox_),
      pool_(std::max(1, options.threads)) {
  namespace ch = protocol::channel;
  bus_.Subscribe<job_batch_t>(ch::kJobs, [this](job_batch_t& batch) {
    const int64_t bytes = batch.getEncodedSize();
    inbox_.Post([this, batch = std::move(batch)] { OnBatch(batch); }, bytes);
  });
  bus_.Subscribe<shards_t>(ch::kShards, [this](shards_t& shards) {
    if (shards.agent == options_.id) return;  // our own, looped back
    const int64_t bytes = shards.getEncodedSize();
    inbox_.Post([this, shards = std::move(shards)] { OnShards(shards); }, bytes);
  });
  bus_.Subscribe<model_round_t>(ch::kModelRound, [this](model_round_t& round) {
    const int64_t bytes = round.getEncodedSize();
    inbox_.Post([this, round = std::move(round)] { OnModelRound(round); }, bytes);
  });
  if (options_.instance == 0) options_.instance = RandomInstance();
  bus_.Subscribe<heartbeat_t>(ch::kHeartbeat, [this](heartbeat_t& beat) {
    if (beat.role != heartbeat_t::ROLE_AGENT || beat.sender != options_.id) return;
    const uint64_t other = ParseInstance(beat.message);
    if (other != options_.instance) {
      collided_with_ = other == 0 ? 1 : other;  // 0: an agent without an instance
      inbox_.Wake();
    }
  });
}

Agent::~Agent() = default;

AgentExit Agent::Run(const std::atomic<bool>& stop) {
  stop_ = &stop;
  using Verdict = protocol::CoordinatorWatch::Verdict;
  heartbeat_t base{};
  base.role = heartbeat_t::ROLE_AGENT;
  base.sender = options_.id;
  base.state = heartbeat_t::STATE_RUNNING;
  base.threads = pool_.threads();
  base.message = InstanceText(options_.instance);
  const auto fill = [this](heartbeat_t& beat) {
    beat.batch_id = reported_batch_;
    beat.epoch = reported_epoch_;
    beat.round = reported_round_;
  };
  // Watchdog on the heartbeat thread: the agent thread may be deep in a long
  // job and cannot notice that the coordinator is gone.
  const auto watchdog = [this] {
    if (!options_.exit_process_when_orphaned) return;
    const Verdict verdict = coordinator_.Check(options_.startup_timeout_seconds,
                                               options_.coordinator_timeout_seconds + 0.5);
    // Said here too: the agent thread may be inside a long job.
    if (const double silent = coordinator_.SilenceToReport(); silent > 0) {
      spdlog::warn("agent {}: the coordinator has been silent for {:.0f} s (waiting up to {:.0f} s)",
                   options_.id, silent, options_.coordinator_timeout_seconds);
    }
    if (verdict == Verdict::kGone) {
      spdlog::error("agent {}: the coordinator is gone; exiting", options_.id);
      std::fflush(nullptr);
      _exit(3);
    }
  };
  protocol::HeartbeatSender heartbeat(bus_, base, options_.heartbeat_seconds, fill, watchdog);
  heartbeat_ = &heartbeat;
  struct Clear {
    std::atomic<protocol::HeartbeatSender*>& pointer;
    ~Clear() { pointer = nullptr; }
  } clear{heartbeat_};
  spdlog::info("agent {}: {} threads, waiting for the coordinator of run {}", options_.id,
               pool_.threads(), bus_.run_id());
  bool announced = false;
  while (!stop) {
    // While a split round waits for others, wake in time to nudge them.
    int64_t wait_ms = 50;
    if (combiner_ && computed_round_ == combiner_->round()) {
      wait_ms = std::clamp<int64_t>(next_nudge_ms_ - protocol::SteadyMs(), 1, 50);
    }
    inbox_.RunFor(Ms(wait_ms));
    NudgeIfStalled();
    // Two agents with one id: the one with the larger instance leaves (its
    // work is reassigned), so exactly one goes on.
    if (const uint64_t other = collided_with_; other != 0 && other < options_.instance) {
      spdlog::error(
          "agent {}: another agent of run {} uses id {}; exiting (give each agent its own "
          "--id, or none for a random one)",
          options_.id, bus_.run_id(), options_.id);
      return AgentExit::kIdCollision;
    }
    if (!announced && coordinator_.Seen()) {
      heartbeat.SendNow();  // join at once, not at the next heartbeat
      announced = true;
    }
    // Checked first: a pause of our own resets the coordinator's silence.
    const Verdict verdict = coordinator_.Check(options_.startup_timeout_seconds,
                                               options_.coordinator_timeout_seconds);
    if (const double silent = coordinator_.SilenceToReport(); silent > 0) {
      spdlog::warn("agent {}: the coordinator has been silent for {:.0f} s (waiting up to {:.0f} s)",
                   options_.id, silent, options_.coordinator_timeout_seconds);
    }
    switch (verdict) {
      case Verdict::kFinished:
        spdlog::debug("agent {}: {} round(s) re-sent on request, {} message(s) dropped at the "
                      "inbox's bound",
                      options_.id, shard_resends_, inbox_.dropped());
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
    Beat();
    return;
  }
  // A new batch, or a new epoch of this one: start over from its contents.
  batch_id_ = batch.batch_id;
  epoch_ = batch.epoch;
  importance_ = batch.averaging == 1;
  split_jobs_.clear();
  combiner_.reset();
  results_.clear();
  sent_.clear();
  resend_gate_.Reset();
  computed_round_ = -1;
  reported_batch_ = batch_id_;
  reported_epoch_ = epoch_;
  reported_round_ = -1;
  Beat();  // acknowledges the batch

  std::vector<int> whole;
  protocol::RoundCombiner::Items items;  // every agent's split learners
  std::vector<std::vector<int>> split_learners(static_cast<size_t>(batch.num_jobs));
  for (int i = 0; i < batch.num_items; ++i) {
    if (batch.item_learner[i] >= 0) {
      items[batch.item_agent[i]].emplace_back(batch.item_job[i], batch.item_learner[i]);
    }
    if (batch.item_agent[i] != options_.id) continue;
    if (batch.item_learner[i] < 0) {
      whole.push_back(batch.item_job[i]);
    } else {
      split_learners[static_cast<size_t>(batch.item_job[i])].push_back(batch.item_learner[i]);
    }
  }
  std::vector<protocol::RoundCombiner::Job> combined;
  int64_t start_round = -1;
  for (int j = 0; j < batch.num_jobs; ++j) {
    if (split_learners[j].empty()) continue;
    Result<protocol::ReceivedJob> received = protocol::JobFromBatch(batch, j);
    if (!received) {
      spdlog::error("agent {}: dropped batch {}: {}", options_.id, batch.batch_id,
                    received.error().message);
      return;
    }
    // The learners a split job's workers run, by kind (Validate refuses
    // split items of a learner that does not train in rounds; a new kind
    // does not compile until it is decided here).
    switch (received->job.kind) {
      case LearnerKind::kFedAsynQ:
        break;
      case LearnerKind::kSingleAgent:
        spdlog::error("agent {}: dropped batch {}: split item of a whole-job learner", options_.id,
                      batch.batch_id);
        return;
    }
    auto hosted = std::make_unique<HostedJob>();
    hosted->index = j;
    hosted->received = std::move(*received);
    const TrainingJob& job = hosted->received.job;  // checked by JobFromBatch
    FederatedState state =
        hosted->received.attempts.empty()
            ? FederatedState::Start(job)
            : FederatedState::Resume(job, hosted->received.attempts, hosted->received.successes);
    hosted->rounds = state.rounds;
    hosted->learners =
        std::make_unique<FederatedLearners>(job, split_learners[j], state.shared, pool_.threads());
    combined.emplace_back(j, std::move(state));
    start_round = std::max(start_round, hosted->received.start_round);
    split_jobs_.push_back(std::move(hosted));
  }
  if (!whole.empty()) RunWholeJobs(batch, whole);
  if (split_jobs_.empty()) return;
  // Our combiner sees only the jobs we host: their learners on other agents
  // are the only ones it waits for.
  for (auto& [agent, owned] : items) {
    std::erase_if(owned, [&](const std::pair<int, int>& item) {
      return split_learners[static_cast<size_t>(item.first)].empty();
    });
  }
  std::erase_if(items, [](const auto& entry) { return entry.second.empty(); });
  if (Status checked = protocol::RoundCombiner::CheckItems(combined, items); !checked) {
    spdlog::error("agent {}: dropped batch {}: {}", options_.id, batch.batch_id,
                  checked.error().message);
    split_jobs_.clear();
    return;
  }
  combiner_ =
      std::make_unique<protocol::RoundCombiner>(std::move(combined), std::move(items), start_round);
  computed_round_ = start_round - 1;
  ContinueSplit();
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
      result = TrainJob(job, stop_);
    } catch (const std::exception& e) {
      spdlog::error("agent {}: job {} of batch {} failed: {}", options_.id, jobs[i], batch.batch_id,
                    e.what());
      return;
    }
    if (StopRequested(stop_)) return;  // cut short: a partial table is no result
    job_result_t message{};
    message.run_id = bus_.run_id();
    message.batch_id = batch.batch_id;
    message.epoch = batch.epoch;
    message.agent = options_.id;
    message.job = jobs[i];
    message.episodes_or_rounds = result.episodes_or_rounds;
    message.steps = result.steps;
    protocol::PutTable(result.table, message);
    bus_.Publish(protocol::channel::kResults, message);
    std::lock_guard lock(mutex);
    results_.push_back(std::move(message));
    reported_round_ = static_cast<int64_t>(results_.size());
    Beat();  // tells what was sent: a lost result shows at once
  });
}

void Agent::ContinueSplit() {
  while (combiner_ && !combiner_->Finished()) {
    if (computed_round_ < combiner_->round()) {
      ComputeRound();
      continue;
    }
    if (!combiner_->RoundComplete()) return;  // OnShards or a nudge continues
    for (const protocol::RoundCombiner::JobRound& job_round : combiner_->Combine()) {
      for (auto& job : split_jobs_) {
        if (job->index == job_round.index) job->learners->Apply(job_round);
      }
    }
  }
}

void Agent::ComputeRound() {
  const int64_t round = combiner_->round();
  // (job, worker, index of the job's first shard) of the jobs still
  // running in this round; shards are kept in job then hosted-learner order.
  struct Item {
    HostedJob* job;
    int worker;
    size_t first_shard;
  };
  std::vector<Item> items;
  std::vector<std::pair<HostedJob*, size_t>> active;  // (job, its first shard)
  size_t shard_count = 0;
  for (auto& job : split_jobs_) {
    if (round >= job->rounds) continue;
    active.emplace_back(job.get(), shard_count);
    for (int w = 0; w < job->learners->workers(); ++w) items.push_back({job.get(), w, shard_count});
    shard_count += job->learners->learners().size();
  }
  const int64_t started = protocol::SteadyMs();
  std::vector<LearnerShard> shards(shard_count);
  pool_.ParallelFor(static_cast<int>(items.size()), [&](int i) {
    const Item& item = items[i];
    item.job->learners->RunRound(item.worker, combiner_->job(item.job->index).stats, round,
                                 shards.data() + item.first_shard);
  });
  round_compute_ms_ = protocol::SteadyMs() - started;
  shards_t message{};
  message.run_id = bus_.run_id();
  message.batch_id = batch_id_;
  message.epoch = epoch_;
  message.round = round;
  message.agent = options_.id;
  for (const auto& [job, first_shard] : active) {
    for (size_t p = 0; p < job->learners->learners().size(); ++p) {
      message.shards.push_back(
          protocol::ShardToMessage(shards[first_shard + p], job->index, importance_));
    }
  }
  message.num_shards = static_cast<int32_t>(message.shards.size());
  computed_round_ = round;
  PublishShards(message, round);
  // Ours go through the same path as everyone's, so all combine the same.
  std::string why;
  if (combiner_->Add(message, &why) != protocol::RoundCombiner::Added::kStored) {
    spdlog::error("agent {}: own shards rejected: {}", options_.id, why);
  }
  sent_.push_back(std::move(message));
  size_t kept = 0;
  for (const shards_t& sent : sent_) kept += static_cast<size_t>(sent.getEncodedSize());
  while (sent_.size() > 2 &&
         (sent_.size() > static_cast<size_t>(protocol::kAgentKeptRounds) || kept > kKeptBytes)) {
    kept -= static_cast<size_t>(sent_.front().getEncodedSize());
    sent_.pop_front();
  }
  reported_round_ = round;
  waiting_since_ms_ = protocol::SteadyMs();
  // The first nudge after a round trip or two (measured by the Bus's
  // repairs; kNudgeMs until then), or twice our own compute time.
  const double rtt = bus_.RepairRoundTripMs();
  const int64_t nudge =
      rtt < 0 ? kNudgeMs : std::clamp<int64_t>(static_cast<int64_t>(2 * rtt) + 2, 3, kNudgeMs);
  nudge_interval_ms_ = std::max(nudge, 2 * round_compute_ms_);
  next_nudge_ms_ = waiting_since_ms_ + nudge_interval_ms_;
}

void Agent::PublishShards(const shards_t& shards, int64_t needs_round) {
  if (shards.needs_round == needs_round) {
    bus_.Publish(protocol::channel::kShards, shards);
    return;
  }
  shards_t copy = shards;
  copy.needs_round = needs_round;
  bus_.Publish(protocol::channel::kShards, copy);
}

void Agent::OnShards(const shards_t& shards) {
  if (!combiner_ || shards.batch_id != batch_id_ || shards.epoch != epoch_) return;
  // The sender still lacks shards of an earlier round: ours of it got lost.
  // That round alone: the coordinator keeps the later rounds it got
  // (RoundCombiner's rounds_ahead), and asks again for any other it lacks.
  // Once per repair interval for a round (protocol/resend_gate.h): the
  // re-send is multicast, so it answers every request for that round.
  if (shards.needs_round < combiner_->round()) {
    const int64_t oldest_kept = sent_.empty() ? combiner_->round() : sent_.front().round;
    const int64_t interval = protocol::RepeatIntervalMs(bus_.RepairRoundTripMs(), kResendCapMs);
    for (const shards_t& sent : sent_) {
      if (sent.round == shards.needs_round &&
          resend_gate_.Allow(sent.round, oldest_kept, protocol::SteadyMs(), interval)) {
        PublishShards(sent, combiner_->round());
        ++shard_resends_;
      }
    }
  }
  if (shards.num_shards == 0) return;  // the coordinator's request: nothing to combine
  std::string why;
  if (combiner_->Add(shards, &why) == protocol::RoundCombiner::Added::kInvalid) {
    spdlog::warn("agent {}: dropped shards of agent {}: {}", options_.id, shards.agent, why);
    return;
  }
  ContinueSplit();
}

void Agent::NudgeIfStalled() {
  if (!combiner_ || combiner_->Finished() || computed_round_ != combiner_->round()) return;
  const int64_t now = protocol::SteadyMs();
  if (now < next_nudge_ms_ || sent_.empty()) return;
  PublishShards(sent_.back(), combiner_->round());
  nudge_interval_ms_ = std::min(kNudgeCapMs, nudge_interval_ms_ * 2);
  next_nudge_ms_ = now + nudge_interval_ms_;
}

void Agent::OnModelRound(const model_round_t& m) {
  if (m.round < model_round_ || (m.round == model_round_ && m.epoch < model_epoch_)) return;
  if (m.round == model_round_ && m.epoch == model_epoch_) {
    // A repeat: the trainer lacks what we sent.
    if (model_sent_) bus_.Publish(protocol::channel::kModelShards, *model_sent_);
    Beat();
    return;
  }
  model_round_ = m.round;
  model_epoch_ = m.epoch;
  model_sent_.reset();
  std::vector<int> learners;
  for (int i = 0; i < m.num_items; ++i) {
    if (m.item_agent[static_cast<size_t>(i)] == options_.id) {
      learners.push_back(m.item_learner[static_cast<size_t>(i)]);
    }
  }
  std::sort(learners.begin(), learners.end());
  // The heartbeat tells the trainer where we are: this round and epoch,
  // round -1 while computing it, the round once its shards are sent.
  reported_batch_ = m.round;
  reported_epoch_ = m.epoch;
  reported_round_ = -1;
  Beat();
  if (learners.empty()) return;
  const ConvQTrainingOptions options = protocol::ConvQOptionsFromRound(m);
  const ConvQModel model = protocol::ConvQModelFromRound(m);
  std::vector<ConvQShard> shards(learners.size());
  pool_.ParallelFor(static_cast<int>(learners.size()), [&](int i) {
    shards[static_cast<size_t>(i)] =
        TrainConvQLearner(options, model, m.round, learners[static_cast<size_t>(i)]);
  });
  model_shards_t message = protocol::ConvQShardsToMessage(shards);
  message.run_id = bus_.run_id();
  message.epoch = m.epoch;
  message.round = m.round;
  message.agent = options_.id;
  bus_.Publish(protocol::channel::kModelShards, message);
  model_sent_ = std::move(message);
  reported_round_ = m.round;
  Beat();
}

void Agent::Beat() {
  if (protocol::HeartbeatSender* sender = heartbeat_) sender->SendNow();
}

void Agent::Resend() {
  const int64_t needs = combiner_ ? combiner_->round() : 0;
  for (const shards_t& sent : sent_) PublishShards(sent, needs);
  for (const job_result_t& result : results_) bus_.Publish(protocol::channel::kResults, result);
}

}  // namespace dynapath::agent
