#include "app/run_session.h"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <thread>

#include "app/repeats.h"
#include "app/resources.h"
#include "dynapath/text_file.h"
#include "launch/launcher.h"
#include "runtime/checkpoint_file.h"
#include "runtime/output_check.h"
#include "runtime/policy_saver.h"

namespace dynapath::app {
namespace {

// A launcher's outcome as the run's (its messages were logged: none here).
Status Quiet(const Status& outcome) {
  if (outcome) return Ok{};
  if (outcome.error().IsCancelled()) return Error("", Error::Code::kCancelled);
  if (outcome.error().IsInvalidArgument()) return Error("", Error::Code::kInvalidArgument);
  return Error("", Error::Code::kInternal);
}

}  // namespace

Result<RunPlan> PlanRun(RunOptions options) {
  RunPlan plan;
  Result<runtime::RunMode> run_mode = runtime::ResolveMode(options.mode, runtime::kMaxAgents);
  if (!run_mode) return run_mode.error();
  plan.mode = *run_mode;
  const bool distributed = plan.distributed();
  Result<int> threads = runtime::ResolveThreads(options.threads);
  if (!threads) return threads.error();
  plan.threads = *threads;
  Result<runtime::RunPlan> run = runtime::ResolveRunOptions(options.run);
  if (!run) return run.error();
  plan.run = std::move(*run);
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(options.process, false);
  if (!process) return process.error();
  plan.process = std::move(*process);
  const bool checkpointing = plan.checkpointing();
  Result<long long> restart_limit =
      runtime::InRange("restart-coordinator", options.restarts, checkpointing ? 3 : 0, 0, 100);
  if (!restart_limit) return restart_limit.error();
  plan.coordinator_restarts = static_cast<int>(*restart_limit);
  if (*restart_limit > 0 && !checkpointing) {
    return OptionError("--restart-coordinator restarts from checkpoints: give --checkpoint DIR",
                       "restart-coordinator");
  }
  if (options.force && (!checkpointing || options.run.resume_checkpoint)) {
    return OptionError(
        "--force starts a new run over the checkpoint in --checkpoint DIR: give --checkpoint "
        "DIR, and not with --resume",
        "force");
  }
  if (options.restarts && plan.mode.kind != runtime::RunMode::kAgents) {
    return OptionError(
        "--restart-coordinator restarts coordinator processes: use it with --agents N",
        "restart-coordinator");
  }
  if (!distributed) {
    const std::pair<const char*, bool> network_options[] = {
        {"lcm-url", !options.process.lcm_url.empty()},
        {"log", options.log_file.has_value()},
        {"run-id", options.process.run_id.has_value()},
        {"fault-drop", options.fault_drop_given},
        {"fault-dup", options.fault_dup_given},
        {"secret-file", options.process.secret_file.has_value()},
        {"insecure", options.process.insecure}};
    for (const auto& [option, given] : network_options) {
      if (given)
        return OptionError(std::string("--") + option + " needs --agents N or --embedded", option);
    }
  }
  if (plan.mode.kind == runtime::RunMode::kEmbedded && !options.process.lcm_url.empty()) {
    // Embedded runs are threads over memq://; silently ignoring the URL
    // would leave agents started elsewhere waiting for a run they never see.
    return OptionError("--lcm-url needs processes on a network: use --agents N, not --embedded",
                       "lcm-url");
  }
  if (options.log_file && plan.mode.kind != runtime::RunMode::kAgents) {
    return OptionError("--log records a multi-process run: use it with --agents N", "log");
  }
  // The maze options here, so a bad one is one error line, not one per process.
  Result<runtime::ScenarioSetup> setup = runtime::ResolveScenario(options.scenario);
  if (!setup) return setup.error();
  plan.setup = std::move(*setup);
  const int steps = static_cast<int>(plan.setup.scenario.changes.steps.size());
  if (Status policy = runtime::CheckPolicyPlan(plan.run.policy, plan.run.approaches,
                                               plan.run.options, plan.setup.scenario.grid, steps,
                                               plan.run.RunSeed(plan.setup.seed));
      !policy) {
    return policy.error();
  }
  // Every output checked before any work.
  if (options.log_file) {
    if (Status status = runtime::CheckOutputFile(*options.log_file, "log"); !status) {
      return status.error();
    }
  }
  if (!plan.run.policy.save_path.empty()) {
    if (Status status = runtime::CheckOutputFile(plan.run.policy.save_path, "save-policy");
        !status) {
      return status.error();
    }
    // A file there is kept (its other sections) or, resuming, must be the
    // one the checkpoint recorded: checked here too, before any process starts.
    Result<runtime::PolicySaver> saver = runtime::PolicySaver::Open(
        plan.run.policy, plan.run.approaches, steps, plan.run.checkpoint.resume.get());
    if (!saver) return saver.error();
  }
  Result<long long> repeat_count = runtime::InRange("repeats", options.repeats, 1, 1, kMaxRepeats);
  if (!repeat_count) return repeat_count.error();
  plan.repeats = static_cast<int>(*repeat_count);
  if (plan.repeats > 1) {
    if (distributed) {
      return OptionError(
          "--repeats needs --local (for agents: dynapath experiment --repeats N --agents M)",
          "repeats");
    }
    if (!plan.run.policy.save_path.empty() || !plan.run.policy.load_path.empty()) {
      return OptionError("--repeats runs without --save-policy and --load-policy", "repeats");
    }
    if (checkpointing) {
      return OptionError(
          "--repeats runs without --checkpoint (dynapath experiment --repeats N checkpoints each "
          "repeat)",
          "repeats");
    }
    const long long last = static_cast<long long>(plan.run.RunSeed(plan.setup.seed)) +
                           (plan.repeats - 1) * static_cast<long long>(kRepeatSeedStride);
    if (last > runtime::kMaxLearnerSeed) {
      return OptionError("option --learner-seed: the last repeat's learner seed " +
                             std::to_string(last) + " would exceed " +
                             std::to_string(runtime::kMaxLearnerSeed),
                         "learner-seed");
    }
  }
  plan.options = std::move(options);
  return plan;
}

void DeclareRecordedOptions(runtime::OptionGroup& group, RunOptions& options) {
  runtime::DeclareModeOptions(group, options.mode);
  runtime::DeclareScenarioOptions(group, options.scenario);
  runtime::DeclareRunOptions(group, options.run);
  runtime::DeclareThreadOptions(group, options.threads);
}

RunSession::RunSession(RunPlan plan) : plan_(std::move(plan)) {}

Status RunSession::RecordOptions() {
  runtime::ConfigWriter recorded;
  runtime::OptionGroup record(recorded);
  DeclareRecordedOptions(record, plan_.options);
  Status written = recorded.status();
  if (written) {
    written = WriteFileDurably(plan_.run.checkpoint.dir + "/" + runtime::kCheckpointOptionsName,
                               recorded.Text());
  }
  if (!written) return OptionError("option --checkpoint: " + written.error().message, "checkpoint");
  return Ok{};
}

Status RunSession::Prepare() {
  const runtime::RunPlan& run = plan_.run;
  Result<runtime::OutputLock> out_lock = runtime::LockResultDirectory(run.out_dir);
  if (!out_lock) return OptionError(out_lock.error().message, "out");
  out_lock_.emplace(std::move(*out_lock));
  if (plan_.checkpointing()) {
    std::error_code ignored;
    if (std::filesystem::weakly_canonical(run.checkpoint.dir, ignored) !=
        std::filesystem::weakly_canonical(run.out_dir, ignored)) {  // else locked as --out
      Result<runtime::OutputLock> locked =
          runtime::OutputLock::Acquire(run.checkpoint.dir, "checkpoint");
      if (!locked) return OptionError(locked.error().message, "checkpoint");
      checkpoint_lock_.emplace(std::move(*locked));
    }
    if (!plan_.options.run.resume_checkpoint) {
      if (!plan_.options.force) {
        if (Status free = runtime::CheckCheckpointFree(run.checkpoint.dir); !free) {
          return OptionError(free.error().message, "checkpoint");
        }
      }
      // A new run: the checkpoint before it (of a finished run, or given up
      // with --force) must not be taken up by a --resume of this one.
      std::error_code removed;
      std::filesystem::remove(run.checkpoint.dir + "/" + runtime::kCheckpointFileName, removed);
      if (removed) return OptionError("option --checkpoint: " + removed.message(), "checkpoint");
      if (Status recorded = RecordOptions(); !recorded) return recorded;
    } else if (run.checkpoint.resume) {
      const runtime::RunCheckpoint& from = *run.checkpoint.resume;
      spdlog::info("resuming from {}/{}: {} of {} approaches finished{}", run.checkpoint.dir,
                   runtime::kCheckpointFileName, from.pass, run.approaches.size(),
                   from.policy
                       ? fmt::format(", {} after step {}", ApproachName(from.runs.back().approach),
                                     from.policy->step)
                       : std::string());
    } else {
      spdlog::info("{} holds no checkpoint yet: the run starts from the beginning",
                   run.checkpoint.dir);
    }
  }
  if (!plan_.distributed()) return Ok{};
  embedded_ = plan_.mode.kind == runtime::RunMode::kEmbedded;
  if (!embedded_) {
    embedded_ = launch::EnterRunNetwork(plan_.process.lcm_url, plan_.process.run_id) ==
                launch::ProcessNetwork::kNone;
  }
  if (embedded_ && plan_.options.log_file) {
    return OptionError("--log needs a network; not with --embedded", "log");
  }
  return Ok{};
}

Status RunSession::Run(const std::atomic<bool>& stop) {
  const runtime::ScenarioSetup& setup = plan_.setup;
  if (plan_.distributed()) {
    launch::DistributedRun run;
    run.process = plan_.process;
    run.process.bus.max_grid_cells = GridCap(setup.scenario.grid);
    run.agents = plan_.mode.agents;
    run.threads_per_agent = ThreadsPerAgent(plan_.threads, plan_.mode.agents);
    run.scenario = plan_.options.scenario;
    run.run = plan_.options.run;
    run.log_level = plan_.options.log.log_level;
    run.log_file = plan_.options.log_file.value_or("");
    run.out_lock_fd = out_lock_->fd();
    run.coordinator_restarts = plan_.coordinator_restarts;
    if (embedded_) {
      spdlog::info("run {}: envsim, coordinator and {} agents as threads over memq://",
                   plan_.process.run_id, run.agents);
      return Quiet(launch::RunEmbedded(run, plan_.run, setup));
    }
    spdlog::info("run {}: envsim, coordinator and {} agent processes", plan_.process.run_id,
                 run.agents);
    if (!plan_.process.lcm_url.empty() && !plan_.options.process.secret_file &&
        !plan_.options.process.insecure) {
      // The secret the launcher made is known to its children only.
      spdlog::info(
          "processes started elsewhere cannot join this run: its secret is the launcher's own "
          "(to share one, make it with `dynapath secret PATH` and pass --secret-file PATH here "
          "and to them)");
    }
    return Quiet(launch::LaunchProcesses(run));
  }
  spdlog::info("maze {} {} ({}), {} time steps, {} approaches, {} threads", setup.labels.size_label,
               setup.labels.difficulty_label, setup.source, setup.scenario.changes.steps.size(),
               plan_.run.approaches.size(), plan_.threads);
  if (plan_.repeats > 1) return RunRepeats(stop);
  Result<std::vector<ApproachRun>> runs =
      runtime::RunLocal(plan_.run, setup, plan_.threads, {}, &stop);
  if (!runs) {
    // A checkpoint or loaded policy that does not fit the run is an error
    // of the options (kInvalidArgument); the others fail the run.
    if (runs.error().IsCancelled() || runs.error().IsInvalidArgument()) return runs.error();
    return Error(runs.error().message, Error::Code::kInternal);
  }
  return Ok{};
}

// run --repeats N (N > 1, --local): `threads` repeats at once, one thread
// each; repeat 1 in the output directory, repeat k in DIR/r<k>.
Status RunSession::RunRepeats(const std::atomic<bool>& stop) {
  const runtime::ScenarioSetup& setup = plan_.setup;
  const int repeats = plan_.repeats;
  std::vector<runtime::RunPlan> plans;
  repeats_.clear();
  for (int k = 1; k <= repeats; ++k) {
    runtime::RunPlan repeat = plan_.run;
    repeat.learner_seed = RepeatLearnerSeed(plan_.options.run.learner_seed, setup.seed, k);
    if (k > 1) repeat.out_dir = plan_.run.out_dir + "/r" + std::to_string(k);
    repeats_.push_back(RepeatDone{repeat.out_dir, k, setup.seed, repeat.RunSeed(setup.seed)});
    plans.push_back(std::move(repeat));
  }
  const int workers = std::max(1, std::min(plan_.threads, repeats));
  const int threads_each = std::max(1, plan_.threads / workers);
  spdlog::info("{} repeats, {} at once with {} thread{} each", repeats, workers, threads_each,
               threads_each == 1 ? "" : "s");
  std::mutex mutex;
  int next = 0;
  std::vector<std::string> errors(static_cast<size_t>(repeats));
  bool cancelled = false;
  auto work = [&] {
    for (;;) {
      int k = 0;
      {
        std::lock_guard lock(mutex);
        if (next == repeats || stop) return;
        k = next++;
      }
      Result<std::vector<ApproachRun>> runs =
          runtime::RunLocal(plans[static_cast<size_t>(k)], setup, threads_each, {}, &stop);
      std::lock_guard lock(mutex);
      if (!runs) {
        errors[static_cast<size_t>(k)] = runs.error().message;
        cancelled = cancelled || runs.error().IsCancelled();
      } else {
        spdlog::info("repeat {} of {} done (learner seed {})", k + 1, repeats,
                     repeats_[static_cast<size_t>(k)].learner_seed);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int w = 0; w < workers; ++w) pool.emplace_back(work);
  for (std::thread& thread : pool) thread.join();
  if (cancelled || stop) return Error("", Error::Code::kCancelled);
  for (int k = 0; k < repeats; ++k) {
    if (!errors[static_cast<size_t>(k)].empty()) {
      return Error("repeat " + std::to_string(k + 1) + ": " + errors[static_cast<size_t>(k)],
                   Error::Code::kInternal);
    }
  }
  return Ok{};
}

}  // namespace dynapath::app
