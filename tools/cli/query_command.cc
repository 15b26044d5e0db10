// dynapath query: asks a running `dynapath serve` for paths, or measures
// its query latency at a fixed rate (docs/howto/SERVICE.md).

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "dynapath/goal_reply_t.hpp"
#include "dynapath/goal_request_t.hpp"
#include "dynapath/latency_histogram.h"
#include "dynapath/obstacle_points_t.hpp"
#include "dynapath/routes.h"
#include "protocol/bus.h"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "protocol/dispatcher.h"
#include "protocol/limits.h"
#include "runtime/process_options.h"
#include "runtime/scenario_options.h"
#include "tools/cli/commands.h"
#include "tools/cli/goal_query.h"
#include "tools/cli/service_client.h"

namespace dynapath::cli {
namespace {

constexpr const char* kQueryProgram = "dynapath query";

using Cell2 = std::pair<int32_t, int32_t>;

std::string RefusalName(int8_t refused) {
  switch (refused) {
    case path_reply_t::TOO_MANY_STARTS:
      return "too_many_starts";
    case path_reply_t::NOT_READY:
      return "not_ready";
    default:
      return "accepted";
  }
}

void PrintReply(const path_reply_t& r, bool json) {
  if (r.refused != path_reply_t::ACCEPTED) {
    if (json) {
      std::printf("{\"refused\":\"%s\",\"version\":%lld,\"step\":%d}\n",
                  RefusalName(r.refused).c_str(), static_cast<long long>(r.version), r.time_step);
    } else {
      std::printf("refused: %s\n", RefusalName(r.refused).c_str());
    }
    return;
  }
  for (int i = 0; i < r.num_starts; ++i) {
    const auto status = static_cast<RouteStatus>(r.status[i]);
    const auto by = static_cast<AnsweredBy>(r.answered_by[i]);
    std::string path;
    for (int k = 0; k < r.path_cells[i]; ++k) {
      const size_t at = static_cast<size_t>(r.path_offset[i] + k);
      if (k > 0) path += json ? "," : " ";
      // Appended piece by piece: GCC 12's -Wrestrict misfires on
      // `const char* + std::string&&` (its bug 105329).
      path += json ? "[" : "(";
      path += std::to_string(r.path_rows[at]);
      path += ",";
      path += std::to_string(r.path_cols[at]);
      path += json ? "]" : ")";
    }
    if (json) {
      std::printf(
          "{\"start\":[%d,%d],\"status\":\"%s\",\"length\":%d,\"path\":[%s],\"version\":%lld,"
          "\"step\":%d,\"answered_by\":\"%s\"}\n",
          r.start_rows[i], r.start_cols[i], RouteStatusName(status), r.length[i], path.c_str(),
          static_cast<long long>(r.version), r.time_step, AnsweredByName(by));
    } else {
      std::printf("(%d,%d): %s", r.start_rows[i], r.start_cols[i], RouteStatusName(status));
      if (status == RouteStatus::kReached) {
        std::printf(", %d moves by %s policy version %lld (step %d): %s", r.length[i],
                    AnsweredByName(by), static_cast<long long>(r.version), r.time_step,
                    path.c_str());
      }
      std::printf("\n");
    }
  }
}

// --rate: Q requests a second, one random free start each, for S seconds;
// latencies from publishing to the reply's arrival. With `goal` (its goal
// set), goal requests to that goal (GOAL_REQUEST, answered on GOAL_REPLY)
// instead of path requests.
int MeasureRate(const runtime::ProcessSetup& process, const std::string& client, double rate,
                double duration, double timeout, std::optional<goal_request_t> goal) {
  const int64_t total = static_cast<int64_t>(rate * duration);
  // Written by the sending loop, read by the dispatch thread.
  std::vector<std::atomic<int64_t>> sent_us(static_cast<size_t>(total));
  std::vector<std::atomic<uint8_t>> answered(static_cast<size_t>(total));
  std::mutex mutex;
  LatencyHistogram latency;
  std::atomic<int64_t> answered_count{0};
  auto now_us = [] {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  };
  // Starts come from the service's policy message; the measuring client
  // only counts replies (the policy client below is another connection).
  std::vector<Cell2> free_cells;
  {
    Result<std::unique_ptr<ServiceClient>> probe =
        ServiceClient::Open(process, client + "-map", ServiceClient::kPolicy);
    if (!probe) return runtime::ProcessError(kQueryProgram, probe.error().message, kExitFailure);
    std::optional<policy_t> policy = (*probe)->LatestPolicy(timeout);
    if (!policy) {
      return runtime::ProcessError(
          kQueryProgram,
          "no POLICY message from the service within --timeout (is it serving run " +
              process.run_id + "?)",
          kExitFailure);
    }
    for (int i = 0; i < policy->num_cells; ++i) {
      if (policy->cells[static_cast<size_t>(i)] != 0) {
        free_cells.emplace_back(i / policy->cols, i % policy->cols);
      }
    }
    if (free_cells.empty())
      return runtime::ProcessError(kQueryProgram, "the map has no free cell", 1);
  }
  auto on_reply = [&](int64_t id) {
    if (id < 0 || id >= total) return;
    const int64_t sent = sent_us[static_cast<size_t>(id)].load();
    if (sent == 0) return;
    if (answered[static_cast<size_t>(id)].exchange(1) != 0) return;
    const int64_t micros = now_us() - sent;
    std::lock_guard lock(mutex);
    latency.Add(micros);
    ++answered_count;
  };
  std::mt19937_64 random(static_cast<uint64_t>(getpid()));
  std::uniform_int_distribution<size_t> pick(0, free_cells.size() - 1);
  // Sends request i from `cell`; then waits up to a second for the replies
  // still in flight.
  auto send_all = [&](const std::function<void(int64_t, Cell2)>& send) {
    const int64_t start = now_us();
    for (int64_t i = 0; i < total; ++i) {
      const int64_t due = start + static_cast<int64_t>(static_cast<double>(i) * 1e6 / rate);
      // Sleep, not spin: on a small machine a spinning client takes the
      // core the service answers on.
      const int64_t wait = due - now_us();
      if (wait > 0) std::this_thread::sleep_for(std::chrono::microseconds(wait));
      const Cell2 cell = free_cells[pick(random)];
      sent_us[static_cast<size_t>(i)].store(now_us());
      send(i, cell);
    }
    const int64_t grace_end = now_us() + 1000000;
    while (answered_count.load() < total && now_us() < grace_end) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  };
  if (goal) {
    Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(process.lcm_url);
    if (!lcm) return runtime::ProcessError(kQueryProgram, lcm.error().message, kExitFailure);
    protocol::Bus bus(**lcm, process.run_id, process.bus);
    bus.Subscribe<goal_reply_t>(protocol::channel::kGoalReply, [&](goal_reply_t& reply) {
      if (reply.client == client && reply.refused == goal_reply_t::ACCEPTED) {
        on_reply(reply.request_id);
      }
    });
    protocol::Dispatcher dispatcher(**lcm);
    goal_request_t request = *goal;
    request.run_id = process.run_id;
    request.client = client;
    request.num_starts = 1;
    request.num_start_poses = 0;
    request.start_x.clear();
    request.start_y.clear();
    send_all([&](int64_t i, Cell2 cell) {
      request.request_id = i;
      request.start_rows = {cell.first};
      request.start_cols = {cell.second};
      bus.Publish(protocol::channel::kGoalRequest, request);
    });
  } else {
    Result<std::unique_ptr<ServiceClient>> opened =
        ServiceClient::Open(process, client, ServiceClient::kRepliesOnly,
                            [&](const path_reply_t& reply) { on_reply(reply.request_id); });
    if (!opened) return runtime::ProcessError(kQueryProgram, opened.error().message, kExitFailure);
    ServiceClient& c = **opened;
    send_all([&](int64_t i, Cell2 cell) { c.Send(i, {cell}); });
    if (std::optional<std::string> two = c.SecondService()) {
      return runtime::ProcessError(kQueryProgram, *two, kExitFailure);
    }
  }
  std::lock_guard lock(mutex);
  std::printf(
      "{\"sent\":%lld,\"answered\":%lld,\"rate\":%g,\"duration_s\":%g,\"p50_ms\":%.3f,"
      "\"p99_ms\":%.3f,\"max_ms\":%.3f}\n",
      static_cast<long long>(total), static_cast<long long>(answered_count.load()), rate, duration,
      static_cast<double>(latency.Quantile(0.5)) / 1000.0,
      static_cast<double>(latency.Quantile(0.99)) / 1000.0,
      static_cast<double>(latency.max()) / 1000.0);
  std::fflush(stdout);
  return answered_count.load() > 0 ? 0 : kExitFailure;
}

// --obstacle-xy / --free-xy: one obstacle_points_t for the service's maze
// (from a probe), published on MAP_POINTS.
int PublishPoints(const runtime::ProcessSetup& process, const std::string& client,
                  const std::vector<std::pair<double, double>>& blocked,
                  const std::vector<std::pair<double, double>>& freed, const std::string& source,
                  int64_t sequence, double timeout) {
  Result<std::unique_ptr<ServiceClient>> opened =
      ServiceClient::Open(process, client, ServiceClient::kRepliesOnly);
  if (!opened) return runtime::ProcessError(kQueryProgram, opened.error().message, kExitFailure);
  std::optional<path_reply_t> probe = (*opened)->Ask({}, timeout);
  if (!probe) {
    return runtime::ProcessError(
        kQueryProgram, "no reply from a service of run " + process.run_id + " within --timeout",
        kExitFailure);
  }
  if (std::optional<std::string> two = (*opened)->SecondService()) {
    return runtime::ProcessError(kQueryProgram, *two, kExitFailure);
  }
  obstacle_points_t points = protocol::PointsToMessage(
      blocked, freed, source, sequence, static_cast<uint64_t>(probe->maze_fingerprint));
  points.run_id = process.run_id;
  points.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                     std::chrono::system_clock::now().time_since_epoch())
                     .count();
  (*opened)->bus().Publish(protocol::channel::kMapPoints, points);
  std::printf("published update %lld of source %s: %zu obstacle, %zu free points\n",
              static_cast<long long>(sequence), source.c_str(), blocked.size(), freed.size());
  std::fflush(stdout);
  return 0;
}

}  // namespace

int QueryCommand(const std::vector<std::string>& args) {
  CLI::App app(
      "Asks a running `dynapath serve` for the path to a station from each --from cell\n"
      "and prints the reply (with --json one object per start: start, status, length,\n"
      "path, version, step, answered_by). With --rate Q --duration S it measures\n"
      "instead: Q requests a second from random free cells for S seconds (to the goal\n"
      "when one is given), and prints one JSON line with sent, answered, p50_ms,\n"
      "p99_ms and max_ms.\n"
      "With a goal (--to ROW,COL, --to-xy X,Y in metres, or --goal NAME of the\n"
      "service's --goals file) it asks for the exact shortest path from each start\n"
      "(--from cells, --from-xy poses) to that goal on the current map instead\n"
      "(--json: start, goal, status, cost, path, path_xy, version, step, answered_by).\n"
      "With --obstacle-xy / --free-xy X,Y it publishes one obstacle update in metres\n"
      "(obstacle_points_t on MAP_POINTS) for the service's maze instead.",
      kQueryProgram);
  runtime::OptionGroup group(app);
  runtime::ProcessOptions process_options;
  runtime::DeclareProcessOptions(group, process_options, true);
  std::vector<std::string> from;
  app.add_option("--from", from, "a start cell ROW,COL (repeat for more)")->type_name("ROW,COL");
  std::vector<std::string> from_xy;
  app.add_option("--from-xy", from_xy, "a start pose X,Y in metres (with a goal; repeat for more)")
      ->type_name("X,Y");
  std::optional<std::string> to, to_xy, goal_name;
  group.Option("--to", to, "ROW,COL", "the goal cell: shortest paths to it instead of a station");
  group.Option("--to-xy", to_xy, "X,Y", "the goal as a pose in metres in the map's frame");
  group.Option("--goal", goal_name, "NAME", "the goal named NAME in the service's --goals file");
  bool json = false;
  group.Flag("--json", json, "one JSON object per start");
  double timeout = 10;
  DeclareServiceWaitOption(group, timeout);
  std::optional<double> rate, duration;
  group.Option("--rate", rate, "Q", "measure: requests per second (1-100000)");
  group.Option("--duration", duration, "SECONDS", "measure for this long (with --rate, 0.1-600)",
               "10");
  std::optional<std::string> client_given;
  group.Option("--client", client_given, "NAME",
               "the name replies are addressed to (1-64 characters)", "query-PID");
  std::vector<std::string> obstacle_xy, free_xy;
  app.add_option("--obstacle-xy", obstacle_xy,
                 "instead of asking: publish an obstacle at X,Y metres in the map's frame "
                 "(repeat for more; one update with --free-xy)")
      ->type_name("X,Y");
  app.add_option("--free-xy", free_xy,
                 "instead of asking: publish that the cell at X,Y metres is free (repeat for more)")
      ->type_name("X,Y");
  std::optional<std::string> source_given;
  DeclareUpdateSourceOption(group, source_given, "query-PID");
  std::optional<long long> sequence_given;
  group.Option("--sequence", sequence_given, "N",
               "the update's sequence number (>= 1; the default grows with the clock, so a "
               "later call of one --source is taken)",
               "the clock in microseconds");
  runtime::LogOptions log;
  runtime::DeclareLogOptions(group, log);
  if (int code = runtime::ParseCommandLine(app, args, kQueryProgram); code >= 0) return code;
  if (Status status = runtime::ApplyLogLevel(log); !status) {
    return runtime::ProcessError(kQueryProgram, status.error().message);
  }
  Result<runtime::ProcessSetup> process = runtime::ResolveProcessOptions(process_options, true);
  if (!process) return runtime::ProcessError(kQueryProgram, process.error().message);
  const std::string client = client_given.value_or("query-" + std::to_string(getpid()));
  if (client.empty() || client.size() > 64) {
    return runtime::ProcessError(kQueryProgram, "--client must have 1-64 characters");
  }
  if (!(timeout > 0 && timeout <= 3600)) {
    return runtime::ProcessError(kQueryProgram, "--timeout must be between 0 and 3600 seconds");
  }
  const int goals_given = (to ? 1 : 0) + (to_xy ? 1 : 0) + (goal_name ? 1 : 0);
  if (!obstacle_xy.empty() || !free_xy.empty()) {
    if (goals_given > 0 || rate || !from.empty() || !from_xy.empty()) {
      return runtime::ProcessError(kQueryProgram,
                                   "--obstacle-xy and --free-xy publish an update: no --from, "
                                   "--from-xy, goal or --rate with them");
    }
    if (obstacle_xy.size() + free_xy.size() > static_cast<size_t>(protocol::kMaxUpdateCells)) {
      return runtime::ProcessError(
          kQueryProgram,
          "at most " + std::to_string(protocol::kMaxUpdateCells) + " points in one update");
    }
    const std::string source = source_given.value_or("query-" + std::to_string(getpid()));
    if (source.empty() || source.size() > 64) {
      return runtime::ProcessError(kQueryProgram, "--source must have 1-64 characters");
    }
    if (sequence_given && *sequence_given < 1) {
      return runtime::ProcessError(kQueryProgram, "--sequence must be at least 1");
    }
    const int64_t sequence =
        sequence_given.value_or(std::chrono::duration_cast<std::chrono::microseconds>(
                                    std::chrono::system_clock::now().time_since_epoch())
                                    .count());
    std::vector<std::pair<double, double>> blocked, freed;
    for (const auto& [texts, option, points] : {std::tuple{&obstacle_xy, "obstacle-xy", &blocked},
                                                std::tuple{&free_xy, "free-xy", &freed}}) {
      for (const std::string& text : *texts) {
        Result<std::pair<double, double>> point = ParsePoint(option, text);
        if (!point) return runtime::ProcessError(kQueryProgram, point.error().message);
        points->push_back(*point);
      }
    }
    return PublishPoints(*process, client, blocked, freed, source, sequence, timeout);
  }
  if (source_given || sequence_given) {
    return runtime::ProcessError(kQueryProgram,
                                 "--source and --sequence need --obstacle-xy or --free-xy");
  }
  if (goals_given > 1) {
    return runtime::ProcessError(kQueryProgram, "give one goal: --to, --to-xy or --goal");
  }
  if (!from_xy.empty() && goals_given == 0) {
    return runtime::ProcessError(kQueryProgram, "--from-xy needs a goal (--to, --to-xy, --goal)");
  }
  std::optional<goal_request_t> goal;  // --rate with a goal: the goal's request
  if (goals_given == 1) {
    if (rate && (!from.empty() || !from_xy.empty())) {
      return runtime::ProcessError(kQueryProgram, "--rate picks its own starts: no --from");
    }
    if (!rate && from.empty() && from_xy.empty()) {
      return runtime::ProcessError(kQueryProgram, "give a start with --from or --from-xy");
    }
    if (from.size() + from_xy.size() > 65536) {
      return runtime::ProcessError(kQueryProgram, "at most 65536 starts");
    }
    goal_request_t request{};
    request.client = client;
    if (to) {
      Result<Cell2> cell = ParseCell(*to);
      if (!cell)
        return runtime::ProcessError(kQueryProgram, "--to must be ROW,COL, got '" + *to + "'");
      request.goal_kind = goal_request_t::GOAL_CELL;
      request.goal_row = cell->first;
      request.goal_col = cell->second;
    } else if (to_xy) {
      Result<std::pair<double, double>> point = ParsePoint("to-xy", *to_xy);
      if (!point) return runtime::ProcessError(kQueryProgram, point.error().message);
      request.goal_kind = goal_request_t::GOAL_POSE;
      request.goal_x = point->first;
      request.goal_y = point->second;
    } else {
      if (goal_name->empty() || goal_name->size() > 64) {
        return runtime::ProcessError(kQueryProgram, "--goal must have 1-64 characters");
      }
      request.goal_kind = goal_request_t::GOAL_NAMED;
      request.goal_name = *goal_name;
    }
    for (const std::string& text : from) {
      Result<Cell2> cell = ParseCell(text);
      if (!cell) return runtime::ProcessError(kQueryProgram, cell.error().message);
      request.start_rows.push_back(cell->first);
      request.start_cols.push_back(cell->second);
    }
    for (const std::string& text : from_xy) {
      Result<std::pair<double, double>> point = ParsePoint("from-xy", text);
      if (!point) return runtime::ProcessError(kQueryProgram, point.error().message);
      request.start_x.push_back(point->first);
      request.start_y.push_back(point->second);
    }
    request.num_starts = static_cast<int32_t>(request.start_rows.size());
    request.num_start_poses = static_cast<int32_t>(request.start_x.size());
    if (!rate) return AskGoal(*process, std::move(request), json, timeout);
    goal = std::move(request);
  }
  if (rate) {
    if (!from.empty())
      return runtime::ProcessError(kQueryProgram, "--rate picks its own starts: no --from");
    const double seconds = duration.value_or(10);
    if (!(*rate >= 1 && *rate <= 100000)) {
      return runtime::ProcessError(kQueryProgram, "--rate must be between 1 and 100000");
    }
    if (!(seconds >= 0.1 && seconds <= 600)) {
      return runtime::ProcessError(kQueryProgram, "--duration must be between 0.1 and 600 seconds");
    }
    return MeasureRate(*process, client, *rate, seconds, timeout, std::move(goal));
  }
  if (duration) return runtime::ProcessError(kQueryProgram, "--duration needs --rate");
  if (from.empty()) return runtime::ProcessError(kQueryProgram, "give a start with --from ROW,COL");
  if (from.size() > 65536)
    return runtime::ProcessError(kQueryProgram, "at most 65536 --from cells");
  std::vector<Cell2> starts;
  for (const std::string& text : from) {
    Result<Cell2> cell = ParseCell(text);
    if (!cell) return runtime::ProcessError(kQueryProgram, cell.error().message);
    starts.push_back(*cell);
  }
  Result<std::unique_ptr<ServiceClient>> opened =
      ServiceClient::Open(*process, client, ServiceClient::kRepliesOnly);
  if (!opened) return runtime::ProcessError(kQueryProgram, opened.error().message, kExitFailure);
  std::optional<path_reply_t> reply = (*opened)->Ask(starts, timeout);
  if (!reply) {
    return runtime::ProcessError(
        kQueryProgram, "no reply from a service of run " + process->run_id + " within --timeout",
        kExitFailure);
  }
  // Two services of one run id answer one request differently: which is
  // right cannot be told, so neither is printed.
  if (std::optional<std::string> two = (*opened)->SecondService()) {
    return runtime::ProcessError(kQueryProgram, *two, kExitFailure);
  }
  PrintReply(*reply, json);
  std::fflush(stdout);
  return reply->refused == path_reply_t::ACCEPTED ? 0 : kExitFailure;
}

}  // namespace dynapath::cli
