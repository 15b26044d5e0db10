#pragma once
// dynapath serve on the bus: the PathService's messages
// (docs/howto/SERVICE.md). Updates (obstacle_update_t on MAP_UPDATES,
// obstacle_points_t on MAP_POINTS and occupancy_grid_t on MAP_GRID, both
// in metres in the map's frame: the goal service's, else 1 m cells from
// (0, 0); and a recorded run's changes_t on
// ENV_CHANGES replayed by lcm-logplayer) are converted and submitted; requests
// (path_request_t on PATH_REQUEST) are answered on the dispatch thread
// itself from the committed snapshot (a few microseconds of work: no queue
// of ours to grow under a flood, LCM's own bounded one in front); every
// commit is published as runs publish steps (step_report_t on REPORT,
// policy_t on POLICY), so `dynapath view` works on a service. A policy
// message is large (8 bytes a cell) and its fragments are paced, so it goes
// out on a thread of its own, built from the commit's immutable snapshot,
// at most once every policy_gap_seconds: the training thread is back for
// the next update at once, the clients on the group are not flooded, and
// viewers get the latest policy. The Bus
// authenticates and validates first: an unauthenticated sender is
// dropped and counted there.

#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "dynapath/goal_request_t.hpp"
#include "dynapath/policy_t.hpp"
#include "protocol/bus.h"
#include "protocol/convert.h"
#include "runtime/goal_service.h"
#include "runtime/path_service.h"

namespace dynapath::runtime {

struct ServiceBusOptions {
  protocol::OccupancyThresholds thresholds;
  bool publish_policy = true;
  // The least time between two policy messages: commits in between are
  // published as the latest of them (0: every commit). A policy message
  // is 8 bytes a cell, and every process on the group receives it.
  double policy_gap_seconds = 1.0;
  // The last policy again after this long without a new one, for viewers
  // that joined since (0: never).
  double republish_seconds = 5.0;
  // Requests of this client are not answered: the service's own probe for
  // another service of its run (dynapath serve asks before it starts).
  std::string own_probe_client;
  // Answers goal_request_t on GOAL_REQUEST (null: not subscribed). Its
  // frame is also the one of obstacle points and occupancy grids.
  GoalService* goals = nullptr;
};

class ServiceBus {
 public:
  // Subscribes: construct before the bus's dispatching starts.
  ServiceBus(protocol::Bus& bus, PathService& service, ServiceBusOptions options);
  // Stops the policy publisher (a policy still waiting is not sent).
  ~ServiceBus();
  ServiceBus(const ServiceBus&) = delete;
  ServiceBus& operator=(const ServiceBus&) = delete;
  // The service's commit hook (training thread): publishes the step report
  // and hands the policy to the publisher.
  void PublishCommit(const Commit& commit);
  // Policy messages sent (new policies and republished ones).
  int64_t policies_published() const;

 private:
  struct PendingPolicy {
    std::shared_ptr<const RouteSnapshot> snapshot;
    std::vector<Region> trained_regions;
  };
  void OnRequest(const path_request_t& request);
  void OnGoalRequest(const goal_request_t& request);
  void PublishPolicies();  // the publisher thread
  // An update refused by its conversion: counted by its reason, as the
  // service counts its own refusals, and what was wrong logged with its
  // channel, at most once a second (a flood of bad updates must not flood
  // the log).
  void RefuseUpdate(std::string_view channel, const UpdateError& refused);
  // A converted update of `channel` submitted to the service, or refused.
  void SubmitUpdate(std::string_view channel, const Result<MapUpdate, UpdateError>& update);

  protocol::Bus& bus_;
  PathService& service_;
  ServiceBusOptions options_;
  std::string approach_;
  MapFrame frame_;                   // metres of obstacle points and occupancy grids
  mutable std::mutex policy_mutex_;  // guards the five below
  std::condition_variable policy_waiting_;
  std::optional<PendingPolicy> pending_;  // the latest commit's, not yet sent
  bool stopping_ = false;
  std::shared_ptr<const policy_t> last_policy_;  // the last one sent
  int64_t policies_published_ = 0;
  std::thread publisher_;
  std::mutex refusal_mutex_;  // guards the two below
  int64_t last_refusal_warning_ms_ = -1;
  int64_t refusal_warnings_suppressed_ = 0;
};

}  // namespace dynapath::runtime
