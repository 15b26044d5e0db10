// dynapath train-model: trains convQ's model (dynapath/convq_training.h)
// from a seed and writes the model file (docs/reference/MODEL_FORMAT.md).

#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "dynapath/convq_training.h"
#include "protocol/dispatcher.h"
#include "runtime/model_file.h"
#include "runtime/option_group.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {

int TrainModelCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Trains convQ's model by reinforcement learning (fitted Q-iteration on TD\n"
      "targets of the report's MDP, over freshly generated mazes of every\n"
      "difficulty whose seeds are 2^31 and above, disjoint from every evaluation\n"
      "seed) and writes it to FILE. The file is a function of the seed and the\n"
      "training sizes: the same at any --threads. Ctrl-C stops it (exit 130)\n"
      "without writing FILE.",
      "dynapath train-model");
  const ConvQTrainingOptions defaults;
  long long seed = static_cast<long long>(defaults.seed);
  long long threads = 1, rounds = defaults.rounds, mazes = defaults.mazes_per_round;
  long long samples = defaults.samples_per_maze;
  std::string out;
  runtime::OptionGroup group(app);
  group.Option("--seed", seed, "S", "the training seed (0 to 2^53 - 1)");
  group.Option("--threads", threads, "N", "threads sharing out each round's mazes (1 to 64)");
  group.Option("--rounds", rounds, "N", "fitting rounds (1 to 10000)");
  group.Option("--mazes", mazes, "N", "mazes per round (1 to 4096)");
  group.Option("--samples", samples, "N", "sampled transitions per maze (1 to 1000000)");
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
  const std::filesystem::path parent = std::filesystem::path(out).parent_path();
  std::error_code error;
  if (out.empty() || std::filesystem::is_directory(out, error) ||
      (!parent.empty() && !std::filesystem::is_directory(parent, error))) {
    return usage_error("option --out must name a file in an existing directory, got '" + out + "'");
  }

  const std::atomic<bool>& stop =
      protocol::StopOnSignals("\ndynapath train-model: stopping (Ctrl-C again: at once)\n",
                              "\ndynapath train-model: stopped at once\n");
  spdlog::info(
      "training convQ: seed {}, {} rounds of {} mazes ({} to {} cells a side), {} "
      "transitions each, {} threads",
      options.seed, options.rounds, options.mazes_per_round, options.min_side, options.max_side,
      options.samples_per_maze, options.threads);
  const auto start = std::chrono::steady_clock::now();
  Result<ConvQModel> model = TrainConvQModel(options, &stop, [&](const ConvQTrainingRound& round) {
    const ConvQModel& m = round.model;
    spdlog::info(
        "round {}/{}: TD error {:.3g} (rms over {} transitions); rewards {:.6g} station, "
        "{:.6g} free, {:.6g} blocked; discounts {:.6g} move, {:.6g} bump",
        round.round, options.rounds, round.td_rms, round.samples, m.station_reward, m.free_reward,
        m.blocked_reward, m.move_discount, m.bump_discount);
  });
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
