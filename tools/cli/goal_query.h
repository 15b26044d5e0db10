#pragma once
// dynapath query --to / --to-xy / --goal: one goal_request_t to a running
// `dynapath serve` and its goal_reply_t printed (docs/howto/SERVICE.md).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dynapath/goal_request_t.hpp"
#include "dynapath/result.h"
#include "runtime/process_options.h"

namespace dynapath::cli {

// "X,Y" in metres, or an error naming the option.
Result<std::pair<double, double>> ParsePoint(const std::string& option, const std::string& text);

// Sends `request` (its run_id and request_id set here) until a reply that
// is not NOT_READY comes or `timeout` passes; prints it. The exit status:
// 0 when accepted with a goal in the map, 1 otherwise.
int AskGoal(const runtime::ProcessSetup& process, goal_request_t request, bool json,
            double timeout);

}  // namespace dynapath::cli
