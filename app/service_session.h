#pragma once
// `dynapath serve` below its command line: the options it was given, typed
// (ServiceOptions), the service they describe, checked once (ServicePlan),
// and the session that runs it (ServiceSession): the service's LCM and bus,
// the path service and its bus glue (ServiceOnBus), and for training on
// agents the coordinator's part and the agents (threads or processes).

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "dynapath/approach.h"
#include "protocol/dispatcher.h"
#include "runtime/goal_service.h"
#include "runtime/output_lock.h"
#include "runtime/path_service.h"
#include "runtime/policy_options.h"
#include "runtime/process_options.h"
#include "runtime/run_driver.h"
#include "runtime/scenario_options.h"
#include "runtime/service_bus.h"

namespace dynapath::app {

// What serve was given (the command line fills it).
struct ServiceOptions {
  ServiceOptions() { run.approach = ApproachName(Approach::kFedAsynQEqAvg); }
  runtime::ModeOptions mode;
  runtime::ScenarioOptions scenario;
  runtime::RunOptions run;
  runtime::ProcessOptions process;
  runtime::ThreadOptions threads;
  runtime::GoalOptions goals;
  runtime::LogOptions log;
  std::string answer = "learned-else-exact";
  long long max_starts = 64;
  double occupied_thresh = 0.65, free_thresh = 0.196;
  double policy_every = 5, policy_gap = 1;
  // Options only told apart by being given at all.
  bool save_at_given = false;
  bool placement_given = false;
  bool out_given = false;
};

// The answer modes by name (--answer's words).
const char* AnswerModeWords();
std::string AnswerModeName(AnswerMode mode);

// A service, checked: what ServiceSession starts.
struct ServicePlan {
  runtime::RunMode mode;
  int threads = 1;
  runtime::ProcessSetup process;
  runtime::ScenarioSetup setup;
  runtime::RunPlan run;
  // The service's configuration but its trainer and loaded policy (the
  // session sets both from the plan).
  runtime::ServiceConfig config;
  runtime::ServiceBusOptions bus;
  // Goal requests (--goals, --goal-cache-mb, the map frame).
  runtime::GoalServiceConfig goals;
  std::string log_level;
  bool write_results = false;  // --out given
};

// Checks `options` once, before any work: an error names the option it is
// about (Error::subject) and says what is wrong, as serve prints it.
Result<ServicePlan> PlanService(const ServiceOptions& options);

// The path service and its bus glue, each needing the other: the service's
// commits are published on the bus, the bus's requests answered by the
// service; and the goal service, which follows the commits and answers goal
// requests. Construct before the bus is dispatched; destruction stops the
// service first.
class ServiceOnBus {
 public:
  ServiceOnBus(protocol::Bus& bus, const Grid& maze, runtime::ServiceConfig config,
               runtime::ServiceBusOptions options, runtime::GoalServiceConfig goals);
  ~ServiceOnBus();
  ServiceOnBus(const ServiceOnBus&) = delete;
  ServiceOnBus& operator=(const ServiceOnBus&) = delete;

  runtime::PathService& service() { return service_; }
  const runtime::ServiceBus& glue() const { return *glue_; }
  const runtime::GoalService& goals() const { return goals_; }

 private:
  std::atomic<runtime::ServiceBus*> published_to_{nullptr};
  runtime::GoalService goals_;  // before the service, whose commits it follows
  runtime::PathService service_;
  std::optional<runtime::ServiceBus> glue_;
};

class ServiceSession {
 public:
  explicit ServiceSession(ServicePlan plan);
  ~ServiceSession();
  ServiceSession(const ServiceSession&) = delete;
  ServiceSession& operator=(const ServiceSession&) = delete;

  // Enters the service's network (a private one without --lcm-url; the
  // process must still be single-threaded), opens its LCM and buses and
  // builds the service, not started yet; locks --out first. An error of
  // the options (--out taken, the network cannot be made, agent processes
  // on memq://) is kInvalidArgument.
  Status Open();
  // After Open: whether another service of the run could answer here (not
  // in a private network nor on memq://): the caller probes for one before
  // Serve, as the client named probe_client(), which this one ignores.
  bool may_have_company() const;
  const std::string& probe_client() const { return plan_.bus.own_probe_client; }
  uint64_t maze_fingerprint() const;
  // Starts training (on the agents too) and answers until `stop` is set or
  // the training ends; then stops everything. Fails when the agents could
  // not be started (an empty message: logged already) or training failed.
  Status Serve(const std::atomic<bool>& stop);
  // After Serve: what was served (several lines; none when the service
  // never started).
  std::string Summary() const;
  // After Serve succeeded: the result files written (with --out); Cancelled
  // when it was stopped before its first policy (nothing written).
  Status Finish();

  const ServicePlan& plan() const { return plan_; }
  // After Open: the path service (tests; any thread).
  runtime::PathService* service() { return served_ ? &served_->service() : nullptr; }

 private:
  struct Training;
  ServicePlan plan_;
  std::optional<runtime::OutputLock> out_lock_;
  bool private_network_ = false;
  bool started_ = false;
  std::unique_ptr<lcm::LCM> lcm_;
  std::optional<protocol::Bus> bus_;
  std::unique_ptr<Training> training_;
  std::unique_ptr<ServiceOnBus> served_;
  std::optional<protocol::Dispatcher> dispatcher_;  // after the subscribers, destroyed first
  Result<ApproachRun> run_ = ApproachRun{};
};

}  // namespace dynapath::app
