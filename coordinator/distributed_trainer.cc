#include "coordinator/distributed_trainer.h"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "dynapath/learners.h"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "protocol/resend_gate.h"
#include "protocol/round_combiner.h"

namespace dynapath::coordinator {
namespace {

using Ms = std::chrono::milliseconds;
// Restarts of a split batch at one round before it runs its jobs whole.
constexpr int kMaxRestartsAtRound = 3;

}  // namespace

// One job of the batch in hand.
struct DistributedTrainer::JobState {
  TrainingJob job;
  // Whole jobs: the final table once received.
  std::optional<QTable> result;
  int64_t steps = 0;
};

struct DistributedTrainer::Batch {
  int64_t id = 0;
  int32_t epoch = 0;
  bool split = false;
  LearnerConfig config;
  std::vector<JobState> jobs;
  std::vector<int> agents;  // of the current epoch
  job_batch_t message{};    // the current epoch's batch
  // Split: the shared tables and start statistics, round by round.
  std::unique_ptr<protocol::RoundCombiner> combiner;
  // Who owes what in this epoch: agent -> (job, learner) items (-1: whole).
  std::map<int, std::vector<std::pair<int, int>>> items;
  int64_t last_send_ms = 0;
  int64_t last_progress_ms = 0;
  // Since when the batch has been waiting for something its agents sent or
  // lack (0: not waiting), and how many reassignments that caused in a row.
  int64_t stuck_since_ms = 0;
  int stalls = 0;
  // Repeats of this epoch's batch since its last progress: each doubles the
  // wait before the next (RepeatIntervalMs), so agents that are merely busy
  // are not flooded with copies they must decode.
  int repeats_since_progress = 0;
  // A shard or result arrived: the batch is no longer stuck, and its stall
  // and repeat counts start over.
  void Progressed() {
    last_progress_ms = AgentRegistry::NowMs();
    stuck_since_ms = 0;
    stalls = 0;
    repeats_since_progress = 0;
  }
  // Split: when the round being collected began (the last combine, or the
  // epoch's start).
  int64_t round_started_ms = 0;
  // Split: restarts for lost shards in a row at the same combined round.
  int64_t restart_round = -1;
  // Split: the round last asked of the agents (RequestRound) and when.
  int64_t requested_round = -1;
  int64_t requested_ms = 0;
  int restarts_at_round = 0;
  // Round-trip samples: when this epoch's batch first went out, whether it
  // was repeated (then acknowledgements are ambiguous), who acknowledged.
  int64_t epoch_sent_ms = 0;
  bool repeated = false;
  std::vector<int> acknowledged;
  int64_t steps = 0;
};

DistributedTrainerOptions MakeTrainerOptions(double agent_wait_seconds, double give_up_seconds,
                                             runtime::Placement placement) {
  DistributedTrainerOptions trainer;
  trainer.agent_wait_seconds = agent_wait_seconds;
  trainer.placement = placement;
  trainer.max_stalls =
      std::max(1, static_cast<int>(std::ceil(give_up_seconds / trainer.stall_seconds)) - 1);
  return trainer;
}

Result<std::string> WaitForAgents(const AgentRegistry& agents, protocol::Inbox& inbox,
                                  int min_agents, double wait_seconds,
                                  const std::atomic<bool>* stop) {
  const int64_t start = protocol::SteadyMs();
  while (static_cast<int>(agents.Live().size()) < min_agents) {
    if (stop != nullptr && stop->load()) return Error::Cancelled();
    if (static_cast<double>(protocol::SteadyMs() - start) > wait_seconds * 1000) {
      return Error::Unavailable("only " + std::to_string(agents.Live().size()) + " of " +
                                std::to_string(min_agents) + " agents appeared within " +
                                std::to_string(static_cast<int>(wait_seconds)) + " s");
    }
    inbox.RunFor(std::chrono::milliseconds(50));
  }
  std::string ids;
  for (const AgentInfo& info : agents.Live()) ids += " " + std::to_string(info.id);
  return ids;
}

double EstimatedRoundUs(const std::vector<Region>& regions, const FedAsynQOptions& options) {
  double us = 0.0;
  for (const Region& region : regions) {
    const double ns_per_step = region.cells() <= 64 * 64 ? 25.0 : 90.0;
    us += static_cast<double>(options.learners) * options.sync_period * ns_per_step / 1000.0;
  }
  return us;
}

bool DistributedTrainer::ShouldSplit(const Batch& batch, size_t agents) const {
  if (!TrainsInRounds(batch.config.kind) || batch.jobs.empty() || batch.jobs.size() >= agents) {
    return false;
  }
  switch (options_.placement) {
    case runtime::Placement::kWhole:
      return false;
    case runtime::Placement::kAuto:
      if (split_disabled_) return false;
      break;
    case runtime::Placement::kSplit:
      return true;
  }
  // Every split round costs a network round trip: split only when a round's
  // work is longer than both the fixed cost of its messages and the measured
  // round trip (none yet: this batch runs whole and measures it).
  if (round_trip_ms_ < 0) return false;
  return RoundUs(batch) >= std::max(options_.split_min_round_us, round_trip_ms_ * 1000);
}

double DistributedTrainer::RoundUs(const Batch& batch) {
  std::vector<Region> regions;
  for (const JobState& state : batch.jobs) regions.push_back(state.job.region);
  return EstimatedRoundUs(regions, batch.jobs.front().job.federated);
}

DistributedTrainer::DistributedTrainer(protocol::Bus& bus, protocol::Inbox& inbox,
                                       const AgentRegistry& agents,
                                       DistributedTrainerOptions options)
    : bus_(bus), inbox_(inbox), agents_(agents), options_(options) {
  namespace ch = protocol::channel;
  bus_.Subscribe<shards_t>(ch::kShards, [this](shards_t& message) {
    const int64_t bytes = message.getEncodedSize();
    inbox_.Post([this, message = std::move(message), bytes] { OnShards(message, bytes); }, bytes);
  });
  bus_.Subscribe<job_result_t>(ch::kResults, [this](job_result_t& message) {
    const int64_t bytes = message.getEncodedSize();
    inbox_.Post([this, message = std::move(message), bytes] { OnResult(message, bytes); }, bytes);
  });
}

DistributedTrainer::~DistributedTrainer() = default;

bool DistributedTrainer::Going() {
  if (status_ && options_.stop != nullptr && options_.stop->load()) status_ = Error::Cancelled();
  return status_.ok();
}

std::vector<int> DistributedTrainer::LiveAgents() const {
  const int64_t now = AgentRegistry::NowMs();
  std::vector<int> all, preferred;
  for (const AgentInfo& info : agents_.Live()) {
    all.push_back(info.id);
    const auto avoided = avoid_until_ms_.find(info.id);
    if (avoided == avoid_until_ms_.end() || avoided->second <= now) preferred.push_back(info.id);
  }
  return preferred.empty() ? all : preferred;
}

std::vector<int> DistributedTrainer::WaitForAgents() {
  const int64_t start = AgentRegistry::NowMs();
  bool warned = false;
  while (true) {
    if (!Going()) return {};
    std::vector<int> ids = LiveAgents();
    if (!ids.empty()) return ids;
    const int64_t waited = AgentRegistry::NowMs() - start;
    if (static_cast<double>(waited) > options_.agent_wait_seconds * 1000) {
      status_ = Error::Unavailable("no agent process alive for " +
                                   std::to_string(static_cast<int>(options_.agent_wait_seconds)) +
                                   " s; cannot train");
      return {};
    }
    if (!warned && waited > 1000) {
      spdlog::warn("no live agent; waiting up to {:.0f} s for one", options_.agent_wait_seconds);
      warned = true;
    }
    inbox_.RunFor(Ms(50));
  }
}

TrainingStats DistributedTrainer::Train(const std::vector<NodeId>& nodes,
                                        const std::vector<uint64_t>& seeds,
                                        const LearnerConfig& config, const QuadTree& tree,
                                        const Grid& grid, RootQTable& root) {
  if (!status_) return {};  // failed or stopped before: the run is ending
  batch_ = std::make_unique<Batch>();
  Batch& batch = *batch_;
  batch.id = next_batch_id_++;
  batch.epoch = -1;
  batch.config = config;
  batch.jobs.resize(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    JobState& state = batch.jobs[i];
    state.job = MakeTrainingJob(nodes[i], seeds[i], config, tree, grid, root);
  }
  ++traffic_.batches;
  std::vector<int> agents = WaitForAgents();
  if (!agents.empty()) {
    batch.split = ShouldSplit(batch, agents.size());
    StartEpoch(std::move(agents));
  }
  const int64_t batch_start = AgentRegistry::NowMs();
  constexpr int64_t kProgressIntervalMs = 5000;
  int64_t next_progress = batch_start + kProgressIntervalMs;
  while (status_ && !Done() && Going()) {
    inbox_.RunFor(Ms(20));
    CheckAgents();
    if (const int64_t now = AgentRegistry::NowMs(); now >= next_progress && batch_) {
      LogProgress(now - batch_start);
      next_progress = now + kProgressIntervalMs;
    }
  }
  if (!status_) {  // nothing is committed: the run ends with status()
    batch_.reset();
    return {};
  }

  TrainingStats stats;
  for (size_t j = 0; j < batch.jobs.size(); ++j) {
    JobState& state = batch.jobs[j];
    root.Commit(state.job.region,
                batch.split ? batch.combiner->job(static_cast<int>(j)).shared : *state.result);
    ++stats.jobs;
    stats.steps += state.steps;
  }
  batch_.reset();
  return stats;
}

void DistributedTrainer::LogProgress(int64_t elapsed_ms) const {
  const Batch& batch = *batch_;
  const double elapsed = static_cast<double>(elapsed_ms) / 1000;
  if (batch.split && batch.combiner) {
    int64_t rounds = 0;
    for (const protocol::RoundCombiner::Job& job : batch.combiner->jobs()) {
      rounds = std::max(rounds, job.rounds);
    }
    const int64_t round = batch.combiner->round();
    std::string left = "time left unknown yet";
    if (rounds > 0 && round * 100 >= rounds) {
      left = fmt::format("about {:.0f} s left",
                         elapsed * static_cast<double>(rounds - round) / static_cast<double>(round));
    }
    spdlog::info("coordinator: training on agents: {} job(s) split, round {} of {}, {:.0f} s so "
                 "far; {}",
                 batch.jobs.size(), round, rounds, elapsed, left);
    return;
  }
  size_t done = 0;
  for (const JobState& state : batch.jobs) done += state.result ? 1 : 0;
  spdlog::info("coordinator: training on agents: {} of {} jobs done, {:.0f} s so far", done,
               batch.jobs.size(), elapsed);
}

bool DistributedTrainer::Done() const {
  if (batch_->split) return batch_->combiner->Finished();
  for (const JobState& state : batch_->jobs) {
    if (!state.result) return false;
  }
  return true;
}

void DistributedTrainer::StartEpoch(std::vector<int> agents) {
  Batch& batch = *batch_;
  ++batch.epoch;
  if (batch.epoch > 0) ++traffic_.epochs;
  batch.repeats_since_progress = 0;
  batch.agents = std::move(agents);
  batch.items.clear();

  // Split jobs restart from the last round the combiner completed.
  std::vector<protocol::RoundCombiner::Job> combined;
  int64_t round = 0;
  if (batch.split) {
    if (batch.combiner) {
      combined = batch.combiner->jobs();
      round = batch.combiner->round();
    } else {
      for (size_t j = 0; j < batch.jobs.size(); ++j) {
        combined.push_back(
            protocol::RoundCombiner::Job::From(static_cast<int>(j), batch.jobs[j].job));
      }
    }
  }

  job_batch_t& message = batch.message;
  message = job_batch_t();
  message.run_id = bus_.run_id();
  message.batch_id = batch.id;
  message.epoch = batch.epoch;
  protocol::SetBatchOptions(batch.config, message);
  for (size_t j = 0; j < batch.jobs.size(); ++j) {
    protocol::JobProgress progress;
    if (batch.split && round > 0) {
      progress.round = round;
      progress.table = combined[j].shared;
      progress.attempts = combined[j].stats.attempts();
      progress.successes = combined[j].stats.successes();
    }
    protocol::AddJob(batch.jobs[j].job, progress, message);
  }
  const int agent_count = static_cast<int>(batch.agents.size());
  auto add_item = [&](int job, int learner, int agent) {
    message.item_job.push_back(job);
    message.item_learner.push_back(learner);
    message.item_agent.push_back(agent);
    batch.items[agent].emplace_back(job, learner);
  };
  if (batch.split) {
    // Contiguous blocks of every job's learners per agent.
    for (size_t j = 0; j < batch.jobs.size(); ++j) {
      const int learners = combined[j].learners;
      for (int k = 0; k < learners; ++k) {
        add_item(static_cast<int>(j), k,
                 batch.agents[static_cast<size_t>(k * agent_count / learners)]);
      }
    }
    // We only listen: keep the rounds the agents run past one we lack, so
    // that they re-send that round alone (they keep kAgentKeptRounds).
    batch.combiner = std::make_unique<protocol::RoundCombiner>(
        std::move(combined), batch.items, round, protocol::kAgentKeptRounds - 1);
  } else {
    // Largest job first, each to the least loaded agent (by cells).
    std::vector<int> order;
    for (size_t j = 0; j < batch.jobs.size(); ++j) {
      if (!batch.jobs[j].result) order.push_back(static_cast<int>(j));
    }
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return batch.jobs[a].job.region.cells() > batch.jobs[b].job.region.cells();
    });
    std::vector<int64_t> load(static_cast<size_t>(agent_count), 0);
    for (int j : order) {
      const size_t least =
          static_cast<size_t>(std::min_element(load.begin(), load.end()) - load.begin());
      load[least] += batch.jobs[j].job.region.cells();
      add_item(j, -1, batch.agents[least]);
    }
  }
  message.num_items = static_cast<int32_t>(message.item_job.size());
  batch.last_progress_ms = AgentRegistry::NowMs();
  batch.round_started_ms = batch.last_progress_ms;
  batch.repeated = false;
  batch.acknowledged.clear();
  PublishBatch();
  batch.epoch_sent_ms = batch.last_send_ms;
}

void DistributedTrainer::PublishBatch() {
  Batch& batch = *batch_;
  bus_.Publish(protocol::channel::kJobs, batch.message);
  ++traffic_.messages_out;
  traffic_.bytes_out += batch.message.getEncodedSize();
  batch.last_send_ms = AgentRegistry::NowMs();
}

void DistributedTrainer::OnShards(const shards_t& message, int64_t bytes) {
  if (!batch_ || !batch_->split) return;
  Batch& batch = *batch_;
  if (message.batch_id != batch.id || message.epoch != batch.epoch) return;  // stale
  if (message.num_shards == 0) return;  // our own request (RequestRound)
  std::string why;
  const protocol::RoundCombiner::Added added = batch.combiner->Add(message, &why);
  // An agent is past the round we collect: all agents had that round's
  // shards, so the ones we lack were lost on their way to us. Ask at once,
  // while the agents still keep them.
  if (message.round > batch.combiner->round() && !batch.combiner->RoundComplete()) {
    RequestRound();
  }
  switch (added) {
    case protocol::RoundCombiner::Added::kInvalid:
      spdlog::warn("dropped shards of agent {}: {}", message.agent, why);
      return;
    case protocol::RoundCombiner::Added::kStored:
      break;
    default:
      return;  // repeated, or a round we cannot use
  }
  ++traffic_.messages_in;
  traffic_.bytes_in += bytes;
  batch.Progressed();
  while (batch.combiner->RoundComplete()) {
    for (const protocol::RoundCombiner::JobRound& job_round : batch.combiner->Combine()) {
      batch.jobs[static_cast<size_t>(job_round.index)].steps += job_round.steps;
    }
    ++traffic_.rounds;
    const int64_t now = AgentRegistry::NowMs();
    slow_round_ms_ = SlowRoundMs(slow_round_ms_, now - batch.round_started_ms);
    batch.round_started_ms = now;
  }
}

void DistributedTrainer::RequestRound() {
  Batch& batch = *batch_;
  const int64_t now = AgentRegistry::NowMs();
  const int64_t round = batch.combiner->round();
  // Once per round, and again after two round trips (the request or its
  // answer was lost: agents run on meanwhile, past what they keep).
  const int64_t retry = protocol::RepeatIntervalMs(round_trip_ms_, 200);
  if (round == batch.requested_round && now - batch.requested_ms < retry) return;
  batch.requested_round = round;
  batch.requested_ms = now;
  shards_t request{};
  request.run_id = bus_.run_id();
  request.batch_id = batch.id;
  request.epoch = batch.epoch;
  request.round = round;
  request.needs_round = round;
  request.num_shards = 0;  // a request: agents re-send their shards of needs_round
  bus_.Publish(protocol::channel::kShards, request);
  ++traffic_.round_requests;
}

void DistributedTrainer::OnResult(const job_result_t& message, int64_t bytes) {
  if (!batch_ || batch_->split) return;
  Batch& batch = *batch_;
  if (message.batch_id != batch.id || message.job >= static_cast<int>(batch.jobs.size())) return;
  JobState& state = batch.jobs[static_cast<size_t>(message.job)];
  if (state.result) return;  // repeated
  // A result of an older epoch is as good as any: jobs are pure functions.
  std::optional<QTable> table =
      protocol::GetTable(message, state.job.region.cells(), state.job.precision);
  if (!table) {
    spdlog::warn("dropped a result of agent {}: its table does not fit job {}", message.agent,
                 message.job);
    return;
  }
  state.result = std::move(*table);
  state.steps = message.steps;
  ++traffic_.messages_in;
  traffic_.bytes_in += bytes;
  batch.Progressed();
}

void DistributedTrainer::CheckAgents() {
  if (Done()) return;
  Batch& batch = *batch_;
  const int64_t now = AgentRegistry::NowMs();
  // Called every 20 ms while a batch lasts (a longer gap: this process did
  // not run, and what it did not hear meanwhile says nothing about agents).
  const int64_t silence_counted_from = resume_clock_.CountedFrom(now);
  // Which agents still owe something, and are they alive?
  std::vector<int> owing;
  if (batch.split) {
    owing = batch.combiner->Missing();
  } else {
    for (const auto& [agent, owed] : batch.items) {
      for (const auto& [job, learner] : owed) {
        if (!batch.jobs[static_cast<size_t>(job)].result) {
          owing.push_back(agent);
          break;
        }
      }
    }
  }
  bool resend = false;
  bool restart = false;
  for (int agent : owing) {
    AgentInfo info;
    if (agents_.Get(agent, info)) SampleRoundTrip(info);
    if (!agents_.IsLive(agent, silence_counted_from) || !agents_.Get(agent, info)) {
      spdlog::warn("agent {} is silent; reassigning its work (batch {}, epoch {})", agent, batch.id,
                   batch.epoch + 1);
      restart = true;
      break;
    }
    if (info.batch_id != batch.id || info.epoch != batch.epoch) {
      resend = true;  // it lacks the batch
    } else if (!batch.split) {
      int64_t received = 0;  // results of it that arrived
      for (const auto& [job, learner] : batch.items[agent]) {
        received += batch.jobs[static_cast<size_t>(job)].result ? 1 : 0;
      }
      resend = resend || info.round > received;  // it sent what did not arrive
    } else if (info.round < batch.combiner->round() &&
               now - batch.last_progress_ms < ComputingPatienceMs()) {
      // It has not sent the round we collect: it is still computing it (a
      // slow or loaded machine, a sanitizer build). A loss shows as an agent
      // at our round or past it; counting a slow round as one would reassign
      // work that is being done, and the new epoch would wait for that round
      // to end before it is even read.
    } else if (now - batch.last_progress_ms >
               std::min(static_cast<int64_t>(options_.resend_seconds * 1000),
                        ResendIntervalMs() + static_cast<int64_t>(RoundUs(batch) / 1000))) {
      // Agents keep their shards of their last two rounds only: one further
      // ahead cannot fill our gap, so the batch restarts from our round.
      if (info.round > batch.combiner->round() + protocol::kAgentKeptRounds - 1) {
        spdlog::warn("shards of agent {} for round {} were lost; restarting the round (batch {})",
                     agent, batch.combiner->round(), batch.id);
        if (batch.combiner->round() == batch.restart_round) {
          ++batch.restarts_at_round;
        } else {
          batch.restart_round = batch.combiner->round();
          batch.restarts_at_round = 1;
        }
        restart = true;
        break;
      }
      RequestRound();
      resend = true;
    }
  }
  if (restart && batch.split && batch.restarts_at_round >= kMaxRestartsAtRound) {
    // The same round lost again and again (measured at 20 ms of delay: the
    // coordinator keeps missing one round's shards and the agents run past
    // it): stop splitting. Whole jobs give the same results (a job is a pure
    // function of its inputs) and need one round trip, not one per round.
    spdlog::warn(
        "batch {}: round {} restarted {} times; running its jobs whole on the agents instead of "
        "splitting their rounds{}",
        batch.id, batch.restart_round, batch.restarts_at_round,
        options_.placement == runtime::Placement::kAuto ? " (and no more splitting in this run)"
                                                        : "");
    if (options_.placement == runtime::Placement::kAuto) split_disabled_ = true;
    ++traffic_.split_fallbacks;
    batch.split = false;
    batch.combiner.reset();
    for (JobState& state : batch.jobs) state.steps = 0;
  }
  if (restart) {
    std::vector<int> live = LiveAgents();
    if (live.empty()) live = WaitForAgents();
    if (live.empty()) return;  // status_ says why
    batch.stuck_since_ms = 0;
    StartEpoch(std::move(live));
    return;
  }
  // Live agents that owe what keeps being lost: bounded (OnStall).
  if (resend) {
    if (batch.stuck_since_ms == 0) {
      batch.stuck_since_ms = now;
    } else if (static_cast<double>(now - batch.stuck_since_ms) > options_.stall_seconds * 1000) {
      OnStall(owing);
      return;
    }
  } else {
    batch.stuck_since_ms = 0;
  }
  const bool stalled = now - batch.last_progress_ms > 10000 && now - batch.last_send_ms > 10000;
  // Whole jobs: repeat once the gap has lasted a few round trips (agents
  // send a heartbeat right after each result, so a gap seen that long is a
  // loss, not a result still in flight). Split rounds keep resend_seconds:
  // their gaps are detected by the lack of progress itself.
  // Split rounds: a gap is a round without progress beyond a round's work
  // plus the repeat interval of whole jobs (reordering is not loss).
  const int64_t first_interval =
      batch.split ? std::min(static_cast<int64_t>(options_.resend_seconds * 1000),
                             ResendIntervalMs() + static_cast<int64_t>(RoundUs(batch) / 1000))
                  : ResendIntervalMs();
  const int64_t interval = RepeatIntervalMs(first_interval, batch.repeats_since_progress);
  if ((resend && now - batch.stuck_since_ms >= first_interval &&
       now - batch.last_send_ms > interval) ||
      (stalled && now - batch.last_send_ms > interval)) {
    ++traffic_.resends;
    ++batch.repeats_since_progress;
    batch.repeated = true;
    PublishBatch();  // agents answer a repeat by re-sending what they sent
  }
}

void DistributedTrainer::SampleRoundTrip(const AgentInfo& info) {
  Batch& batch = *batch_;
  // Karn's rule: only acknowledgements of a batch sent once are timed.
  if (batch.repeated || info.batch_id != batch.id || info.epoch != batch.epoch) return;
  if (std::find(batch.acknowledged.begin(), batch.acknowledged.end(), info.id) !=
      batch.acknowledged.end()) {
    return;
  }
  batch.acknowledged.push_back(info.id);
  const double sample =
      static_cast<double>(std::max<int64_t>(0, info.last_seen_ms - batch.epoch_sent_ms));
  round_trip_ms_ = round_trip_ms_ < 0 ? sample : 0.875 * round_trip_ms_ + 0.125 * sample;
  traffic_.round_trip_ms = round_trip_ms_;
}

int64_t DistributedTrainer::ResendIntervalMs() const {
  const double cap = options_.resend_seconds * 1000;
  if (round_trip_ms_ < 0) return static_cast<int64_t>(cap);
  return static_cast<int64_t>(std::clamp(2 * round_trip_ms_ + 20.0, 30.0, cap));
}

int64_t RepeatIntervalMs(int64_t first_interval_ms, int repeats_since_progress) {
  // Exponential backoff, as TCP's retransmission timer: a batch repeated
  // without progress is more likely late (its agents busy, a slow host, a
  // sanitizer build) than lost again. Measured under ASan with learners
  // split: repeats every 30 ms kept busy agents decoding 64 KB copies,
  // 7,214 repeats in one run, until the batch stalled and was reassigned.
  // Capped at kMaxRepeatIntervalMs so that a real loss is still repaired
  // well before the stall bound (stall_seconds, 5 s by default).
  const int doublings = std::min(repeats_since_progress, 6);
  const int64_t grown = first_interval_ms << doublings;
  return std::max(first_interval_ms, std::min(grown, kMaxRepeatIntervalMs));
}

int64_t SlowRoundMs(int64_t previous_ms, int64_t round_ms) {
  return std::max(round_ms, previous_ms - previous_ms / 8);
}

int64_t DistributedTrainer::ComputingPatienceMs() const {
  const int64_t give_up_ms =
      static_cast<int64_t>(options_.stall_seconds * 1000) * std::max(1, options_.max_stalls);
  return std::min(give_up_ms, 3 * slow_round_ms_);
}

void DistributedTrainer::OnStall(const std::vector<int>& owing) {
  Batch& batch = *batch_;
  const int64_t now = AgentRegistry::NowMs();
  ++batch.stalls;
  ++traffic_.stalls;
  std::string who;
  for (int agent : owing) {
    AgentInfo info;
    agents_.Get(agent, info);
    who += (who.empty() ? "agent " : ", agent ") + std::to_string(agent);
    if (info.batch_id != batch.id || info.epoch != batch.epoch) {
      who += " has not received the batch";
    } else if (batch.split) {
      who += " is at round " + std::to_string(info.round) + ", the coordinator at " +
             std::to_string(batch.combiner->round());
    } else {
      who += " sent results that did not arrive";
    }
  }
  const double waited = static_cast<double>(now - batch.stuck_since_ms) / 1000.0;
  if (batch.stalls > options_.max_stalls) {
    status_ = Error::Unavailable(
        "training batch " + std::to_string(batch.id) + " made no progress for " +
        std::to_string(static_cast<int>(batch.stalls * options_.stall_seconds)) + " s in " +
        std::to_string(batch.stalls) + " attempts although its agents are alive (" + who +
        "): their messages are being lost");
    return;
  }
  for (int agent : owing) {
    avoid_until_ms_[agent] = now + static_cast<int64_t>(options_.avoid_seconds * 1000);
  }
  std::vector<int> live = LiveAgents();
  if (live.empty()) live = WaitForAgents();
  if (live.empty()) return;  // status_ says why
  std::string to;
  for (int agent : live) to += (to.empty() ? "" : ",") + std::to_string(agent);
  spdlog::warn(
      "batch {} made no progress for {:.1f} s ({}; {} resends so far); reassigning its work to "
      "agent(s) {} (epoch {}, attempt {} of {})",
      batch.id, waited, who, traffic_.resends, to, batch.epoch + 1, batch.stalls,
      options_.max_stalls);
  batch.stuck_since_ms = 0;
  StartEpoch(std::move(live));
}

}  // namespace dynapath::coordinator
