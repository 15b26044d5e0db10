#include "coordinator/distributed_trainer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <stdexcept>

#include "lcmtypes/protocol/channels.h"
#include "lcmtypes/protocol/convert.h"

namespace dynapath::coordinator {
namespace {

using Ms = std::chrono::milliseconds;

}  // namespace

// One job of the batch in hand.
struct DistributedTrainer::JobState {
  TrainingJob job;
  // Split jobs: the shared table and start statistics after `round` rounds.
  std::unique_ptr<RegionModel> model;
  std::unique_ptr<FederatedAverager> averager;
  QTable shared;
  StartStatistics stats;
  int64_t rounds = 0;
  std::vector<std::optional<LearnerShard>> shards;  // of the round being collected
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
  std::vector<int> agents;           // of the current epoch
  job_batch_t message{};             // the current epoch's batch
  std::optional<average_t> average;  // the last average published (split)
  int64_t round = 0;                 // split: the round being collected
  int64_t start_round = 0;           // split: first round of this epoch
  // Who owes what in this epoch: agent -> (job, learner) items (-1: whole).
  std::map<int, std::vector<std::pair<int, int>>> items;
  std::map<int, bool> agent_round_done;  // split: shards of `round` arrived
  int64_t last_send_ms = 0;
  int64_t last_progress_ms = 0;
  int64_t steps = 0;
};

DistributedTrainer::DistributedTrainer(protocol::Bus& bus, protocol::Inbox& inbox,
                                       const AgentRegistry& agents,
                                       DistributedTrainerOptions options)
    : bus_(bus), inbox_(inbox), agents_(agents), options_(options) {
  namespace ch = protocol::channel;
  bus_.Subscribe<shards_t>(ch::kShards, [this](shards_t& message) {
    const int64_t bytes = message.getEncodedSize();
    inbox_.Post([this, message = std::move(message), bytes] { OnShards(message, bytes); });
  });
  bus_.Subscribe<job_result_t>(ch::kResults, [this](job_result_t& message) {
    const int64_t bytes = message.getEncodedSize();
    inbox_.Post([this, message = std::move(message), bytes] { OnResult(message, bytes); });
  });
}

DistributedTrainer::~DistributedTrainer() = default;

std::vector<int> DistributedTrainer::WaitForAgents() {
  const int64_t start = AgentRegistry::NowMs();
  bool warned = false;
  while (true) {
    std::vector<int> ids;
    for (const AgentInfo& info : agents_.Live()) ids.push_back(info.id);
    if (!ids.empty()) return ids;
    const int64_t waited = AgentRegistry::NowMs() - start;
    if (static_cast<double>(waited) > options_.agent_wait_seconds * 1000) {
      throw std::runtime_error("no agent process alive for " +
                               std::to_string(static_cast<int>(options_.agent_wait_seconds)) +
                               " s; cannot train");
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
  batch.split = config.kind == LearnerKind::kFedAsynQ && nodes.size() < agents.size();
  if (batch.split) {
    for (JobState& state : batch.jobs) {
      state.model = std::make_unique<RegionModel>(state.job);
      state.shared = StartingTable(state.job);
      state.stats = StartStatistics(state.model->start_cells());
      state.rounds = FederatedRounds(state.job.region, state.job.federated);
      state.averager = std::make_unique<FederatedAverager>(
          static_cast<int>(state.shared.values().size()), state.job.federated.averaging);
    }
  }
  StartEpoch(std::move(agents));
  while (!Done()) {
    inbox_.RunFor(Ms(20));
    CheckAgents();
  }

  TrainingStats stats;
  for (JobState& state : batch.jobs) {
    root.Commit(state.job.region, batch.split ? state.shared : *state.result);
    ++stats.jobs;
    stats.steps += state.steps;
  }
  batch_.reset();
  return stats;
}

bool DistributedTrainer::Done() const {
  for (const JobState& state : batch_->jobs) {
    if (batch_->split ? batch_->round < state.rounds : !state.result) return false;
  }
  return true;
}

void DistributedTrainer::StartEpoch(std::vector<int> agents) {
  Batch& batch = *batch_;
  ++batch.epoch;
  if (batch.epoch > 0) ++traffic_.epochs;
  batch.agents = std::move(agents);
  batch.items.clear();
  batch.agent_round_done.clear();
  batch.average.reset();
  batch.start_round = batch.round;

  job_batch_t& message = batch.message;
  message = job_batch_t();
  message.run_id = bus_.run_id();
  message.batch_id = batch.id;
  message.epoch = batch.epoch;
  protocol::SetBatchOptions(batch.config, message);
  for (const JobState& state : batch.jobs) {
    protocol::JobProgress progress;
    if (batch.split) {
      progress.round = batch.round;
      if (batch.round > 0) {
        progress.table = state.shared;
        progress.attempts = state.stats.attempts();
        progress.successes = state.stats.successes();
      }
    }
    protocol::AddJob(state.job, progress, message);
  }
  const int agent_count = static_cast<int>(batch.agents.size());
  auto add_item = [&](int job, int learner, int agent) {
    message.item_job.push_back(job);
    message.item_learner.push_back(learner);
    message.item_agent.push_back(agent);
    batch.items[agent].emplace_back(job, learner);
  };
  if (batch.split) {
    // Contiguous blocks of learners per agent.
    for (size_t j = 0; j < batch.jobs.size(); ++j) {
      JobState& state = batch.jobs[j];
      if (batch.round >= state.rounds) continue;
      const int learners = state.job.federated.learners;
      state.shards.assign(static_cast<size_t>(learners), std::nullopt);
      for (int k = 0; k < learners; ++k) {
        add_item(static_cast<int>(j), k,
                 batch.agents[static_cast<size_t>(k * agent_count / learners)]);
      }
    }
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
  for (const auto& [agent, owed] : batch.items) batch.agent_round_done[agent] = false;
  batch.last_progress_ms = AgentRegistry::NowMs();
  PublishBatch();
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
  if (message.batch_id != batch.id || message.epoch != batch.epoch ||
      message.round != batch.round) {
    return;  // stale or repeated
  }
  auto owed = batch.items.find(message.agent);
  if (owed == batch.items.end() || batch.agent_round_done[message.agent]) return;
  // The message must hold exactly the agent's items of the jobs still running.
  std::vector<std::pair<int, int>> expected;
  for (const auto& [job, learner] : owed->second) {
    if (batch.round < batch.jobs[static_cast<size_t>(job)].rounds)
      expected.emplace_back(job, learner);
  }
  std::vector<std::pair<int, int>> got;
  for (const learner_shard_t& shard : message.shards) got.emplace_back(shard.job, shard.learner);
  std::sort(expected.begin(), expected.end());
  std::sort(got.begin(), got.end());
  if (got != expected) {
    spdlog::warn("dropped shards of agent {}: they do not match its assignment", message.agent);
    return;
  }
  std::vector<LearnerShard> shards;
  for (const learner_shard_t& m : message.shards) {
    const JobState& state = batch.jobs[static_cast<size_t>(m.job)];
    const int64_t entries = static_cast<int64_t>(state.shared.values().size());
    const bool fits =
        (m.entries.empty() || m.entries.back() < entries) &&
        (m.start_cell < 0 || state.stats.SlotOf(m.start_cell) >= 0) &&
        (m.num_visits > 0) == (state.job.federated.averaging == Averaging::kImportance);
    if (!fits) {
      spdlog::warn("dropped shards of agent {}: a shard does not fit job {}", message.agent, m.job);
      return;
    }
    shards.push_back(protocol::ShardFromMessage(m, message.round));
  }
  for (size_t i = 0; i < shards.size(); ++i) {
    JobState& state = batch.jobs[static_cast<size_t>(message.shards[i].job)];
    state.shards[static_cast<size_t>(shards[i].learner)] = std::move(shards[i]);
  }
  batch.agent_round_done[message.agent] = true;
  ++traffic_.messages_in;
  traffic_.bytes_in += bytes;
  batch.last_progress_ms = AgentRegistry::NowMs();
  TryCombine();
}

void DistributedTrainer::TryCombine() {
  Batch& batch = *batch_;
  for (const auto& [agent, done] : batch.agent_round_done) {
    if (!done) return;
  }
  average_t average{};
  average.run_id = bus_.run_id();
  average.batch_id = batch.id;
  average.epoch = batch.epoch;
  average.round = batch.round;
  std::vector<LearnerShard> shards;
  for (size_t j = 0; j < batch.jobs.size(); ++j) {
    JobState& state = batch.jobs[j];
    if (batch.round >= state.rounds) continue;
    shards.clear();
    for (auto& shard : state.shards) {
      shards.push_back(std::move(*shard));
      shard.reset();
    }
    job_average_t job_average{};
    job_average.job = static_cast<int32_t>(j);
    std::vector<uint32_t> entries;
    state.averager->Combine(shards, state.shared, state.stats, entries, job_average.values);
    job_average.entries.assign(entries.begin(), entries.end());
    job_average.num_entries = static_cast<int32_t>(entries.size());
    for (const LearnerShard& shard : shards) {
      job_average.start_cells.push_back(shard.start_cell);
      job_average.reached.push_back(shard.reached_station);
      state.steps += shard.steps;
    }
    job_average.num_learners = static_cast<int32_t>(shards.size());
    average.jobs.push_back(std::move(job_average));
  }
  average.num_jobs = static_cast<int32_t>(average.jobs.size());
  ++batch.round;
  ++traffic_.rounds;
  for (auto& [agent, done] : batch.agent_round_done) done = false;
  if (Done()) return;  // the last round's average is not needed by anyone
  bus_.Publish(protocol::channel::kAverages, average);
  ++traffic_.messages_out;
  traffic_.bytes_out += average.getEncodedSize();
  batch.last_send_ms = AgentRegistry::NowMs();
  batch.average = std::move(average);
}

void DistributedTrainer::OnResult(const job_result_t& message, int64_t bytes) {
  if (!batch_ || batch_->split) return;
  Batch& batch = *batch_;
  if (message.batch_id != batch.id || message.job >= static_cast<int>(batch.jobs.size())) return;
  JobState& state = batch.jobs[static_cast<size_t>(message.job)];
  if (state.result) return;  // repeated
  // A result of an older epoch is as good as any: jobs are pure functions.
  if (message.num_values != state.job.region.cells() * kNumActions) {
    spdlog::warn("dropped a result of agent {}: its table does not fit job {}", message.agent,
                 message.job);
    return;
  }
  QTable table(state.job.region.cells());
  table.values() = message.values;
  state.result = std::move(table);
  state.steps = message.steps;
  ++traffic_.messages_in;
  traffic_.bytes_in += bytes;
  batch.last_progress_ms = AgentRegistry::NowMs();
}

void DistributedTrainer::CheckAgents() {
  if (Done()) return;
  Batch& batch = *batch_;
  const int64_t now = AgentRegistry::NowMs();
  // Which agents still owe something, and are they alive?
  bool lost = false;
  bool resend = false;
  for (const auto& [agent, owed] : batch.items) {
    bool owes = false;
    int64_t results_received = 0;
    if (batch.split) {
      owes = !batch.agent_round_done[agent];
    } else {
      for (const auto& [job, learner] : owed) {
        if (batch.jobs[static_cast<size_t>(job)].result) {
          ++results_received;
        } else {
          owes = true;
        }
      }
    }
    if (!owes) continue;
    AgentInfo info;
    if (!agents_.IsLive(agent) || !agents_.Get(agent, info)) {
      spdlog::warn("agent {} is silent; reassigning its work (batch {}, epoch {})", agent, batch.id,
                   batch.epoch + 1);
      lost = true;
      break;
    }
    // Its heartbeat shows it lacks the batch, or sent what did not arrive;
    // or (split) a round, which takes milliseconds, is overdue: our average
    // or its shards were lost.
    if (info.batch_id != batch.id || info.epoch != batch.epoch) {
      resend = true;
    } else if (batch.split ? static_cast<double>(now - batch.last_progress_ms) >
                                 options_.resend_seconds * 1000
                           : info.round > results_received) {
      resend = true;
    }
  }
  if (lost) {
    std::vector<int> live;
    for (const AgentInfo& info : agents_.Live()) live.push_back(info.id);
    if (live.empty()) live = WaitForAgents();
    StartEpoch(std::move(live));
    return;
  }
  const bool stalled = now - batch.last_progress_ms > 10000 && now - batch.last_send_ms > 10000;
  if ((resend || stalled) &&
      static_cast<double>(now - batch.last_send_ms) > options_.resend_seconds * 1000) {
    ++traffic_.resends;
    if (batch.split && batch.average) {
      bus_.Publish(protocol::channel::kAverages, *batch.average);
      ++traffic_.messages_out;
      traffic_.bytes_out += batch.average->getEncodedSize();
      batch.last_send_ms = now;
    } else {
      PublishBatch();
    }
  }
}

}  // namespace dynapath::coordinator
