#pragma once
// dynapath serve on the bus: the PathService's messages
// (docs/howto/SERVICE.md). Updates (obstacle_update_t on MAP_UPDATES,
// occupancy_grid_t on MAP_GRID, and a recorded run's changes_t on
// ENV_CHANGES replayed by lcm-logplayer) are converted and submitted; requests
// (path_request_t on PATH_REQUEST) are answered on the dispatch thread
// itself from the committed snapshot (a few microseconds of work: no queue
// of ours to grow under a flood, LCM's own bounded one in front); every
// commit is published as runs publish steps (step_report_t on REPORT,
// policy_t on POLICY), so `dynapath view` works on a service. The Bus
// authenticates and validates first: an unauthenticated sender is
// dropped and counted there.

#include <mutex>
#include <optional>

#include "dynapath/policy_t.hpp"
#include "protocol/bus.h"
#include "protocol/convert.h"
#include "runtime/path_service.h"

namespace dynapath::runtime {

struct ServiceBusOptions {
  protocol::OccupancyThresholds thresholds;
  bool publish_policy = true;
};

class ServiceBus {
 public:
  // Subscribes: construct before the bus's dispatching starts.
  ServiceBus(protocol::Bus& bus, PathService& service, ServiceBusOptions options);
  // The service's commit hook (training thread).
  void PublishCommit(const Commit& commit);
  // Publishes the last committed policy again, for viewers and clients
  // that joined after it (the serve loop calls it every few seconds).
  void RepublishPolicy();

 private:
  void OnRequest(const path_request_t& request);

  protocol::Bus& bus_;
  PathService& service_;
  ServiceBusOptions options_;
  std::string approach_;
  std::mutex policy_mutex_;
  std::optional<policy_t> last_policy_;  // guarded by policy_mutex_
};

}  // namespace dynapath::runtime
