// dynapath train-model: trains convQ's model (dynapath/convq_training.h)
// from a seed and writes the model file (docs/reference/MODEL_FORMAT.md).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/model_training.h"
#include "dynapath/convq_training.h"
#include "protocol/dispatcher.h"
#include "runtime/model_file.h"
#include "runtime/option_group.h"
#include "runtime/process_options.h"
#include "runtime/test_hold.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {

int TrainModelCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Trains convQ's model by reinforcement learning (fitted Q-iteration on TD\n"
      "targets of the report's MDP, over freshly generated mazes of every\n"
      "difficulty whose seeds are 2^31 and above, disjoint from every evaluation\n"
      "seed) and writes it to FILE. The file is a function of the seed and the\n"
      "training sizes: the same at any --threads. Ctrl-C stops it (exit 130)\n"
      "without writing FILE. With --learners K the training is federated: K\n"
      "learners fit their share of each round's mazes and their fits are\n"
      "averaged; they can be hosted on agents, with the same file:\n"
      "  --agents N    on N dynapath-agent processes over LCM, in a private network\n"
      "                namespace (or on --lcm-url's network, where agents started\n"
      "                elsewhere with the same --run-id and --secret-file join too)\n"
      "  --embedded    on agents as threads of this process over memq:// (N from\n"
      "                --agents, else 1)",
      "dynapath train-model");
  const ConvQTrainingOptions defaults;
  long long seed = static_cast<long long>(defaults.seed);
  long long threads = 1, rounds = defaults.rounds, mazes = defaults.mazes_per_round;
  long long samples = defaults.samples_per_maze;
  std::optional<long long> learners, agents;
  std::optional<std::string> average;
  bool embedded = false;
  runtime::ProcessOptions process;
  std::string out;
  runtime::OptionGroup group(app);
  group.Option("--seed", seed, "S", "the training seed (0 to 2^53 - 1)");
  group.Option("--threads", threads, "N", "threads sharing out each round's mazes (1 to 64)");
  group.Option("--rounds", rounds, "N", "fitting rounds (1 to 10000)");
  group.Option("--mazes", mazes, "N", "mazes per round (1 to 4096)");
  group.Option("--samples", samples, "N", "sampled transitions per maze (1 to 1000000)");
  group.Option("--learners", learners, "K",
               "federated: K learners (1 to 256, at most --mazes), learner k fitting mazes "
               "k, k + K, ... of every round; their fits averaged by --average",
               "not federated");
  group.Option("--average", average, "equal|importance",
               "federated: the plain mean of the learners' weights, or each weighted by the "
               "transitions it was fitted on",
               "equal");
  group.Option("--agents", agents, "N",
               "federated: host the learners on N dynapath-agent processes over LCM, in a "
               "private network namespace or on --lcm-url's network (1 to 256); the same file "
               "as in this process",
               "in this process");
  group.Flag("--embedded", embedded,
             "federated: host the learners on agents as threads of this process over memq:// "
             "(N from --agents, else 1); the same file as in this process");
  runtime::DeclareRunNetworkOptions(group, process, false);
  app.add_option("--out", out, "the model file to write")->type_name("FILE")->required();

  if (int code = runtime::ParseCommandLine(app, args, "dynapath train-model"); code >= 0) {
    return code;
  }
  const auto usage_error = [](const std::string& message) {
    std::fprintf(stderr, "dynapath train-model: %s\n", message.c_str());
    return kExitUsage;
  };
  ConvQTrainingOptions options;
  const struct {
    const char* name;
    long long value, min, max;
    int* target;
  } ranges[] = {{"threads", threads, 1, 64, &options.threads},
                {"rounds", rounds, 1, 10000, &options.rounds},
                {"mazes", mazes, 1, 4096, &options.mazes_per_round},
                {"samples", samples, 1, 1000000, &options.samples_per_maze}};
  for (const auto& range : ranges) {
    Result<long long> checked = runtime::InRange(range.name, range.value, 0, range.min, range.max);
    if (!checked) return usage_error(checked.error().message);
    *range.target = static_cast<int>(*checked);
  }
  Result<long long> checked_seed = runtime::InRange("seed", seed, 0, 0, (1LL << 53) - 1);
  if (!checked_seed) return usage_error(checked_seed.error().message);
  options.seed = static_cast<uint64_t>(*checked_seed);
  if (!learners && (average || agents || embedded)) {
    return usage_error(std::string("option --") +
                       (average  ? "average"
                        : agents ? "agents"
                                 : "embedded") +
                       " needs --learners K (a federated training)");
  }
  if (!agents && !embedded) {
    const std::pair<const char*, bool> network_options[] = {
        {"run-id", process.run_id.has_value()},
        {"lcm-url", !process.lcm_url.empty()},
        {"secret-file", process.secret_file.has_value()},
        {"insecure", process.insecure}};
    for (const auto& [option, given] : network_options) {
      if (given) {
        return usage_error(std::string("--") + option + " needs --agents N or --embedded");
      }
    }
  }
  if (learners) {
    const long long most = std::min<long long>(kMaxConvQLearners, options.mazes_per_round);
    Result<long long> k = runtime::InRange("learners", learners, 0, 1, most);
    if (!k) {
      return usage_error(
          k.error().message +
          (*learners > options.mazes_per_round
               ? " (every learner fits at least one maze of a round: at most --mazes)"
               : ""));
    }
    options.learners = static_cast<int>(*k);
  }
  if (average) {
    if (*average == "equal") {
      options.averaging = ConvQAveraging::kEqual;
    } else if (*average == "importance") {
      options.averaging = ConvQAveraging::kImportance;
    } else {
      return usage_error("option --average must be equal or importance, got '" + *average + "'");
    }
  }
  std::optional<app::ModelTrainingAgents> on_agents;
  if (agents || embedded) {
    app::ModelTrainingAgentOptions agent_options;
    Result<long long> n = runtime::InRange("agents", agents, 1, 1, runtime::kMaxAgents);
    if (!n) return usage_error(n.error().message);
    agent_options.agents = static_cast<int>(*n);
    agent_options.embedded = embedded;
    agent_options.process = process;
    Result<app::ModelTrainingAgents> plan = app::PlanModelTrainingAgents(agent_options);
    if (!plan) return usage_error(plan.error().message);
    on_agents = std::move(*plan);
  }
  const std::filesystem::path parent = std::filesystem::path(out).parent_path();
  std::error_code error;
  if (out.empty() || std::filesystem::is_directory(out, error) ||
      (!parent.empty() && !std::filesystem::is_directory(parent, error))) {
    return usage_error("option --out must name a file in an existing directory, got '" + out + "'");
  }

  // Still single-threaded: a private network needs that.
  if (on_agents) app::EnterModelTrainingNetwork(*on_agents);
  const std::atomic<bool>& stop =
      protocol::StopOnSignals("\ndynapath train-model: stopping (Ctrl-C again: at once)\n",
                              "\ndynapath train-model: stopped at once\n");
  spdlog::info(
      "training convQ: seed {}, {} rounds of {} mazes ({} to {} cells a side), {} "
      "transitions each, {} threads",
      options.seed, options.rounds, options.mazes_per_round, options.min_side, options.max_side,
      options.samples_per_maze, options.threads);
  if (options.learners > 0) {
    spdlog::info("federated: {} learners, {} averaging, {}", options.learners,
                 options.averaging == ConvQAveraging::kEqual ? "equal" : "importance",
                 !on_agents            ? std::string("in this process")
                 : on_agents->embedded ? fmt::format("on {} agent threads", on_agents->agents)
                                       : fmt::format("on {} agent processes", on_agents->agents));
  }
  const auto start = std::chrono::steady_clock::now();
  // A test hook (runtime/test_hold.h): stop after this round.
  const int hold_after = runtime::TestHoldStep("train-model");
  const auto report = [&](const ConvQTrainingRound& round) {
    const ConvQModel& m = round.model;
    spdlog::info(
        "round {}/{}: TD error {:.3g} (rms over {} transitions); rewards {:.6g} station, "
        "{:.6g} free, {:.6g} blocked; discounts {:.6g} move, {:.6g} bump",
        round.round, options.rounds, round.td_rms, round.samples, m.station_reward, m.free_reward,
        m.blocked_reward, m.move_discount, m.bump_discount);
    if (round.round == hold_after) runtime::HoldForTest("train-model", round.round);
  };
  Result<ConvQModel> model = on_agents ? app::TrainModelOnAgents(options, *on_agents, stop, report)
                                       : TrainConvQModel(options, &stop, report);
  if (!model) {
    if (model.error().IsCancelled()) {
      spdlog::warn("interrupted: no model written");
      return kExitInterrupted;
    }
    spdlog::error("{}", model.error().message);
    return kExitFailure;
  }
  runtime::ModelFile file{*model, options};
  if (Status written = runtime::WriteModelFile(out, file); !written) {
    spdlog::error("{}: {}", out, written.error().message);
    return kExitFailure;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::string weights;
  for (double weight : ConvQWeights(*model)) weights += fmt::format(" {:a}", weight);
  spdlog::info("wrote {} in {:.1f} s; weights (exact):{}", out, seconds, weights);
  return 0;
}

}  // namespace dynapath::cli
