#pragma once
// A client of `dynapath serve` (the CLI's query, feed and robots, and the
// Python module's ServiceClient): the run's bus (its authentication
// included), path requests matched with their replies, and the service's
// latest policy message and step reports.

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dynapath/grid.h"
#include "dynapath/path_reply_t.hpp"
#include "dynapath/path_request_t.hpp"
#include "dynapath/policy_t.hpp"
#include "protocol/bus.h"
#include "protocol/dispatcher.h"
#include "runtime/process_options.h"
#include "runtime/reply_witness.h"

namespace dynapath::runtime {

class ServiceClient {
 public:
  // `on_reply`, when given, sees every reply to this client (the dispatch
  // thread; the first to each request) instead of Ask's matching.
  using ReplyHook = std::function<void(const path_reply_t&)>;
  // What a client listens to besides its replies: the service's policy
  // messages (large: only a client that needs the map) and its step reports.
  enum Listen { kRepliesOnly = 0, kPolicy = 1, kReports = 2 };
  static Result<std::unique_ptr<ServiceClient>> Open(const ProcessSetup& process,
                                                     std::string client, int listen,
                                                     ReplyHook on_reply = {});
  ~ServiceClient();

  const std::string& client() const { return client_; }
  protocol::Bus& bus() { return *bus_; }
  // Publishes a request for `starts` with id `request_id`.
  void Send(int64_t request_id, const std::vector<std::pair<int32_t, int32_t>>& starts);
  // Sends (again every 200 ms) until a reply that is not NOT_READY comes,
  // or `seconds` pass (nullopt; the last NOT_READY reply if one came).
  // No starts: a probe (the service's maze, version and step).
  std::optional<path_reply_t> Ask(const std::vector<std::pair<int32_t, int32_t>>& starts,
                                  double seconds);
  // Waits for the replies still coming to the requests sent so far (a
  // second service's are as quick as the first's), then: the conflict of
  // two different replies to one request (runtime/reply_witness.h), if any.
  std::optional<std::string> SecondService();
  // Before a client changes the service's map: probes until its first
  // policy answers (`seconds`), checks that one service answers and that it
  // serves `maze` (the maze at step 0 the client's changes were made for).
  // The reply to the probe (its version and step), or the error:
  // kInvalidArgument for another maze, kUnavailable for no service or two.
  Result<path_reply_t> Meet(const Grid& maze, double seconds);
  // The latest POLICY message, waiting up to `seconds` for one (kPolicy).
  std::optional<policy_t> LatestPolicy(double seconds);
  // (kReports) When the service's step report (REPORT, published when a step's own
  // policy is committed, after any interim one) of `time_step` or a later
  // step arrived, waiting up to `seconds` for it.
  std::optional<std::chrono::steady_clock::time_point> ReportArrival(int time_step, double seconds);

 private:
  ServiceClient() = default;
  std::string client_;
  ReplyHook on_reply_;
  std::unique_ptr<lcm::LCM> lcm_;
  std::unique_ptr<protocol::Bus> bus_;
  std::unique_ptr<protocol::Dispatcher> dispatcher_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<path_reply_t> reply_;  // the latest reply to this client
  ReplyWitness witness_;               // every reply to this client
  std::optional<policy_t> policy_;
  // Step reports' arrival times by time step (the latest kKeptReports).
  static constexpr size_t kKeptReports = 1024;
  std::map<int, std::chrono::steady_clock::time_point> reports_;
  int64_t next_id_ = 1;
};

// How long a second service's reply may come after the first's: both
// answer within a millisecond or two on one network.
inline constexpr double kSecondReplySeconds = 0.2;

}  // namespace dynapath::runtime
