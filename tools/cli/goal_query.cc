#include "tools/cli/goal_query.h"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <thread>

#include "dynapath/goal_paths.h"
#include "dynapath/goal_reply_t.hpp"
#include "protocol/bus.h"
#include "protocol/channels.h"
#include "protocol/dispatcher.h"
#include "tools/cli/commands.h"

namespace dynapath::cli {
namespace {

constexpr const char* kGoalQueryProgram = "dynapath query";

const char* GoalByName(int8_t by) {
  switch (by) {
    case goal_reply_t::BY_FIELD:
      return "field";
    case goal_reply_t::BY_SEARCH:
      return "search";
    default:
      return "none";
  }
}

void PrintGoalReply(const goal_reply_t& r, bool json) {
  if (r.refused != goal_reply_t::ACCEPTED) {
    const char* why = r.refused == goal_reply_t::NOT_READY ? "not_ready" : "too_many_starts";
    if (json) {
      std::printf("{\"refused\":\"%s\",\"version\":%lld,\"step\":%d}\n", why,
                  static_cast<long long>(r.version), r.time_step);
    } else {
      std::printf("refused: %s\n", why);
    }
    return;
  }
  MapFrame frame{r.resolution, r.origin_x, r.origin_y, r.rows, r.cols};
  const char* goal_status = GoalCheckName(static_cast<GoalCheck>(r.goal_status));
  if (r.goal_status != goal_reply_t::GOAL_OK) {
    if (json) {
      std::printf("{\"goal_status\":\"%s\",\"goal\":[%d,%d],\"version\":%lld,\"step\":%d}\n",
                  goal_status, r.goal_row, r.goal_col, static_cast<long long>(r.version),
                  r.time_step);
    } else {
      std::printf("goal refused: %s\n", goal_status);
    }
    return;
  }
  char buffer[96];
  for (int i = 0; i < r.num_starts; ++i) {
    const auto status = static_cast<GoalStatus>(r.status[static_cast<size_t>(i)]);
    std::string cells, poses;
    for (int k = 0; k < r.path_cells[static_cast<size_t>(i)]; ++k) {
      const size_t at = static_cast<size_t>(r.path_offset[static_cast<size_t>(i)] + k);
      if (k > 0) {
        cells += json ? "," : " ";
        poses += json ? "," : " ";
      }
      std::snprintf(buffer, sizeof buffer, json ? "[%d,%d]" : "(%d,%d)", r.path_rows[at],
                    r.path_cols[at]);
      cells += buffer;
      std::snprintf(buffer, sizeof buffer, json ? "[%.3f,%.3f]" : "(%.3f,%.3f)",
                    frame.X(r.path_cols[at]), frame.Y(r.path_rows[at]));
      poses += buffer;
    }
    const int row = r.start_rows[static_cast<size_t>(i)];
    const int col = r.start_cols[static_cast<size_t>(i)];
    if (json) {
      std::printf(
          "{\"start\":[%d,%d],\"goal\":[%d,%d],\"status\":\"%s\",\"cost\":%d,\"path\":[%s],"
          "\"path_xy\":[%s],\"version\":%lld,\"step\":%d,\"answered_by\":\"%s\"}\n",
          row, col, r.goal_row, r.goal_col, GoalStatusName(status), r.cost[static_cast<size_t>(i)],
          cells.c_str(), poses.c_str(), static_cast<long long>(r.version), r.time_step,
          GoalByName(r.answered_by[static_cast<size_t>(i)]));
    } else {
      std::printf("(%d,%d) to (%d,%d): %s", row, col, r.goal_row, r.goal_col,
                  GoalStatusName(status));
      if (status == GoalStatus::kReached) {
        std::printf(", %d moves by %s on map version %lld (step %d): %s; in metres: %s",
                    r.cost[static_cast<size_t>(i)],
                    GoalByName(r.answered_by[static_cast<size_t>(i)]),
                    static_cast<long long>(r.version), r.time_step, cells.c_str(), poses.c_str());
      }
      std::printf("\n");
    }
  }
}

}  // namespace

Result<std::pair<double, double>> ParsePoint(const std::string& option, const std::string& text) {
  const size_t comma = text.find(',');
  if (comma != std::string::npos && text.size() <= 64) {
    const std::string xs = text.substr(0, comma), ys = text.substr(comma + 1);
    char* end_x = nullptr;
    char* end_y = nullptr;
    const double x = std::strtod(xs.c_str(), &end_x);
    const double y = std::strtod(ys.c_str(), &end_y);
    if (!xs.empty() && !ys.empty() && end_x == xs.c_str() + xs.size() &&
        end_y == ys.c_str() + ys.size() && std::isfinite(x) && std::isfinite(y)) {
      return std::make_pair(x, y);
    }
  }
  return Error::Option(option, "must be X,Y (two numbers of metres), got '" + text + "'");
}

int AskGoal(const runtime::ProcessSetup& process, goal_request_t request, bool json,
            double timeout) {
  Result<std::unique_ptr<lcm::LCM>> lcm = protocol::OpenLcm(process.lcm_url);
  if (!lcm) return runtime::ProcessError(kGoalQueryProgram, lcm.error().message, kExitFailure);
  protocol::Bus bus(**lcm, process.run_id, process.bus);
  std::mutex mutex;
  std::condition_variable arrived;
  std::optional<goal_reply_t> reply;
  bus.Subscribe<goal_reply_t>(protocol::channel::kGoalReply, [&](goal_reply_t& message) {
    if (message.client != request.client) return;
    {
      std::lock_guard lock(mutex);
      if (!reply || reply->request_id < message.request_id) reply = std::move(message);
    }
    arrived.notify_all();
  });
  std::optional<goal_reply_t> answer;
  {
    protocol::Dispatcher dispatcher(**lcm);
    request.run_id = process.run_id;
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(timeout));
    for (int64_t id = 1; std::chrono::steady_clock::now() < deadline; ++id) {
      request.request_id = id;
      bus.Publish(protocol::channel::kGoalRequest, request);
      std::unique_lock lock(mutex);
      const auto retry =
          std::min(deadline, std::chrono::steady_clock::now() + std::chrono::milliseconds(200));
      arrived.wait_until(lock, retry, [&] { return reply && reply->request_id == id; });
      if (reply && reply->request_id == id) {
        answer = reply;
        if (reply->refused != goal_reply_t::NOT_READY) break;
        lock.unlock();
        std::this_thread::sleep_for(std::chrono::milliseconds(100));  // still training
      }
    }
  }
  if (!answer) {
    return runtime::ProcessError(
        kGoalQueryProgram, "no reply from a service of run " + process.run_id + " within --timeout",
        kExitFailure);
  }
  PrintGoalReply(*answer, json);
  std::fflush(stdout);
  return answer->refused == goal_reply_t::ACCEPTED && answer->goal_status == goal_reply_t::GOAL_OK
             ? 0
             : kExitFailure;
}

}  // namespace dynapath::cli
