#include "coordinator/convq_trainer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <string>

#include "coordinator/distributed_trainer.h"
#include "protocol/channels.h"
#include "protocol/convert.h"

namespace dynapath::coordinator {

ConvQTrainer::ConvQTrainer(protocol::Bus& bus, ConvQTrainerOptions options)
    : bus_(bus), options_(options), agents_(options.agent_timeout_seconds) {
  bus_.Subscribe<heartbeat_t>(protocol::channel::kHeartbeat, [this](heartbeat_t& beat) {
    if (agents_.OnHeartbeat(beat)) inbox_.Wake();
  });
  bus_.Subscribe<model_shards_t>(protocol::channel::kModelShards, [this](model_shards_t& shards) {
    const int64_t bytes = shards.getEncodedSize();
    inbox_.Post([this, shards = std::move(shards)] { OnShards(shards); }, bytes);
  });
}

ConvQTrainer::~ConvQTrainer() { Finish(); }

void ConvQTrainer::Start() { heartbeat_.Start(); }

void ConvQTrainer::Finish() { heartbeat_.Finish(status_); }

void ConvQTrainer::AgentExited(int id, const std::string& how) {
  inbox_.Post([this, id, how] {
    agents_.MarkGone(id);
    exited_[id] = how;
    spdlog::warn("agent {} {}", id, how);
  });
}

void ConvQTrainer::NoAgentProcessLeft() {
  inbox_.Post([this] { processes_gone_ = true; });
}

std::string ConvQTrainer::ExitedAgents() const {
  std::string text;
  for (const auto& [id, how] : exited_) {
    text += (text.empty() ? "agent " : ", agent ") + std::to_string(id) + " " + how;
  }
  return text;
}

std::vector<int> ConvQTrainer::LiveAgents(int min) {
  const int64_t start = AgentRegistry::NowMs();
  while (true) {
    const std::vector<AgentInfo> live = agents_.Live();
    // Agents known to have exited are not waited for.
    const int needed = std::max(1, min - static_cast<int>(exited_.size()));
    if (static_cast<int>(live.size()) >= needed) {
      std::vector<int> ids;
      for (const AgentInfo& info : live) ids.push_back(info.id);
      return ids;
    }
    if (Stopped()) {
      status_ = Error::Cancelled();
      return {};
    }
    if (NoneLeft()) {
      status_ =
          Error::Unavailable("training convQ's model on agents: every agent process has exited (" +
                             ExitedAgents() + ") and no other agent is live");
      return {};
    }
    if (static_cast<double>(AgentRegistry::NowMs() - start) > options_.agent_wait_seconds * 1000) {
      status_ = Error::Unavailable(
          "training convQ's model on agents: only " + std::to_string(live.size()) + " of " +
          std::to_string(needed) + " agents appeared within " +
          std::to_string(static_cast<int>(options_.agent_wait_seconds)) + " s");
      return {};
    }
    inbox_.RunFor(std::chrono::milliseconds(50));
  }
}

void ConvQTrainer::Publish(const std::vector<int>& live) {
  ++epoch_;
  std::vector<int> missing;
  for (size_t k = 0; k < shards_.size(); ++k) {
    if (!shards_[k]) missing.push_back(static_cast<int>(k));
  }
  owed_.clear();
  message_.epoch = epoch_;
  message_.item_learner.clear();
  message_.item_agent.clear();
  // Contiguous blocks of learners per agent.
  for (size_t i = 0; i < missing.size(); ++i) {
    const int agent = live[i * live.size() / missing.size()];
    message_.item_learner.push_back(missing[i]);
    message_.item_agent.push_back(agent);
    owed_[agent].push_back(missing[i]);
  }
  message_.num_items = static_cast<int32_t>(message_.item_learner.size());
  bus_.Publish(protocol::channel::kModelRound, message_);
  last_send_ms_ = AgentRegistry::NowMs();
  repeats_ = 0;
}

void ConvQTrainer::OnShards(const model_shards_t& message) {
  // Any epoch of the round in hand will do: a shard is a function of the
  // round alone.
  if (message.round != round_ || shards_.empty()) {
    ++stats_.shards_ignored;
    return;
  }
  for (const ConvQShard& shard : protocol::ConvQShardsFromMessage(message)) {
    if (shard.learner >= static_cast<int>(shards_.size())) {
      ++stats_.shards_refused;
      spdlog::warn("dropped a shard of agent {}: learner {} of a training of {} learners",
                   message.agent, shard.learner, shards_.size());
      continue;
    }
    std::optional<ConvQShard>& slot = shards_[static_cast<size_t>(shard.learner)];
    if (slot) {
      ++stats_.shards_ignored;
      continue;
    }
    slot = shard;
    ++stats_.shards;
    ++stats_.shards_by_agent[message.agent];
    last_progress_ms_ = AgentRegistry::NowMs();
  }
}

Result<std::vector<ConvQShard>> ConvQTrainer::Round(const ConvQTrainingOptions& options, int round,
                                                    const ConvQModel& model) {
  if (!status_) return status_.error();
  if (!waited_) {
    waited_ = true;
    if (LiveAgents(options_.min_agents).empty()) return status_.error();
    std::string ids;
    for (const AgentInfo& info : agents_.Live()) ids += " " + std::to_string(info.id);
    spdlog::info("training convQ's model on agents{}", ids);
  }
  round_ = round;
  shards_.assign(static_cast<size_t>(options.learners), std::nullopt);
  message_ = protocol::ModelRoundToMessage(options, round, model);
  message_.run_id = bus_.run_id();
  last_progress_ms_ = AgentRegistry::NowMs();
  std::vector<int> live = LiveAgents(1);
  if (live.empty()) return status_.error();
  Publish(live);
  const auto complete = [&] {
    return std::all_of(shards_.begin(), shards_.end(),
                       [](const std::optional<ConvQShard>& s) { return s.has_value(); });
  };
  protocol::ResumeClock resume_clock(std::max<int64_t>(agents_.timeout_ms() / 2, 1000));
  while (!complete()) {
    if (Stopped()) {
      status_ = Error::Cancelled();
      return status_.error();
    }
    inbox_.RunFor(std::chrono::milliseconds(20));
    if (complete()) break;
    const int64_t now = AgentRegistry::NowMs();
    const int64_t counted_from = resume_clock.CountedFrom(now);
    // An agent that owes shards and fell silent: its learners go to the
    // live agents.
    std::vector<int> lost;
    for (const auto& [agent, learners] : owed_) {
      const bool owes = std::any_of(learners.begin(), learners.end(), [&](int k) {
        return !shards_[static_cast<size_t>(k)].has_value();
      });
      if (owes && !agents_.IsLive(agent, counted_from)) lost.push_back(agent);
    }
    if (!lost.empty()) {
      std::string who;
      for (int agent : lost) {
        who += (who.empty() ? "agent " : ", agent ") + std::to_string(agent) +
               (exited_.count(agent) != 0 ? " exited" : " silent");
      }
      spdlog::warn("{}; reassigning their learners of round {} (epoch {})", who, round, epoch_ + 1);
      live = LiveAgents(1);
      if (live.empty()) return status_.error();
      ++stats_.epochs;
      last_progress_ms_ = now;
      Publish(live);
      continue;
    }
    if (static_cast<double>(now - last_progress_ms_) > options_.give_up_seconds * 1000) {
      std::string who;
      for (const auto& [agent, learners] : owed_) {
        AgentInfo info;
        if (!agents_.Get(agent, info)) continue;
        who += (who.empty() ? "agent " : ", agent ") + std::to_string(agent) +
               (info.batch_id != round || info.epoch != epoch_ ? " has not received the round"
                : info.round == round                          ? " sent shards that did not arrive"
                                                               : " is still computing");
      }
      status_ = Error::Unavailable("training convQ's model on agents: round " +
                                   std::to_string(round) + " got no shard for " +
                                   std::to_string(static_cast<int>(options_.give_up_seconds)) +
                                   " s although its agents are alive (" + who + ")");
      return status_.error();
    }
    // Still owed: repeat the round, backing off (agents re-send what they
    // sent, and compute what they lacked).
    const int64_t first = static_cast<int64_t>(options_.resend_seconds * 1000);
    if (now - last_send_ms_ > RepeatIntervalMs(first, repeats_)) {
      bus_.Publish(protocol::channel::kModelRound, message_);
      last_send_ms_ = now;
      ++repeats_;
      ++stats_.resends;
    }
  }
  ++stats_.rounds;
  std::vector<ConvQShard> shards;
  shards.reserve(shards_.size());
  for (std::optional<ConvQShard>& shard : shards_) shards.push_back(std::move(*shard));
  shards_.clear();
  return shards;
}

}  // namespace dynapath::coordinator
