#include "protocol/log_scenario.h"

#include <cstdio>
#include <map>
#include <optional>

#include "dynapath/changes_t.hpp"
#include "dynapath/grid_t.hpp"
#include "protocol/auth.h"
#include "protocol/channels.h"
#include "protocol/convert.h"
#include "protocol/decode.h"
#include "protocol/log_reader.h"
#include "protocol/validate.h"

namespace dynapath::protocol {
namespace {

// Recorded messages carry the run's authentication trailer (auth.h): not
// checked (the reader has no secret), only stripped.
template <class T>
bool Decode(const LogEvent& event, T& message) {
  const int size = PayloadSize(event.data.data(), static_cast<int>(event.data.size()));
  return DecodeExactly(event.data.data(), size, message) && Validate(message).ok();
}

bool EndsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

Result<LoggedScenario> ReadScenarioLog(const std::string& path, const std::string& run_id) {
  Result<LogReader> log = LogReader::Open(path);
  if (!log) return log.error();
  std::optional<grid_t> grid;
  std::map<int, changes_t> steps;
  std::string run = run_id;
  int64_t events = 0;
  const std::string grid_suffix = "/" + std::string(channel::kEnvGrid);
  const std::string changes_suffix = "/" + std::string(channel::kEnvChanges);
  while (true) {
    Result<std::optional<LogEvent>> next = log->Next();
    if (!next) return next.error();
    if (!*next) break;
    const LogEvent& event = **next;
    ++events;
    if (EndsWith(event.channel, grid_suffix)) {
      grid_t message{};
      if (!Decode(event, message)) continue;
      if (run.empty()) run = message.run_id;
      if (message.run_id != run) continue;
      if (grid && (grid->cells != message.cells || grid->total_steps != message.total_steps)) {
        return Error::Corrupt("log " + path + " holds two different mazes for run " + run);
      }
      grid = message;
    } else if (EndsWith(event.channel, changes_suffix)) {
      changes_t message{};
      if (!Decode(event, message)) continue;
      if (run.empty()) run = message.run_id;
      if (message.run_id != run) continue;
      auto [it, inserted] = steps.emplace(message.time_step, message);
      if (!inserted && (it->second.cells != message.cells || it->second.codes != message.codes ||
                        it->second.requested_moves != message.requested_moves)) {
        return Error::Corrupt("log " + path + " holds two different versions of time step " +
                              std::to_string(message.time_step));
      }
    }
  }
  if (events == 0) return Error::Corrupt(path + " is empty or not an LCM log");
  if (!grid)
    return Error::Corrupt("log " + path + " holds no maze" + (run.empty() ? "" : " of run " + run));
  LoggedScenario logged;
  logged.run_id = run;
  logged.scenario.grid = GridFromMessage(*grid);
  logged.size_label = grid->size_label;
  logged.difficulty = grid->difficulty;
  logged.seed = static_cast<uint64_t>(grid->seed);
  for (int t = 1; t <= grid->total_steps; ++t) {
    auto it = steps.find(t);
    if (it == steps.end()) {
      return Error::Corrupt("log " + path + " misses time step " + std::to_string(t) + " of " +
                            std::to_string(grid->total_steps) + " (was the run complete?)");
    }
    Result<ChangeStep> step = ChangesFromMessage(it->second, grid->rows, grid->cols);
    if (!step) return step.error();
    logged.scenario.changes.steps.push_back(std::move(*step));
  }
  return logged;
}

}  // namespace dynapath::protocol
