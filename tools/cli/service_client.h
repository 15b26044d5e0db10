#pragma once
// The CLI's side of a client of `dynapath serve` (query, feed, robots): the
// client itself is runtime's (runtime/service_client.h, shared with the
// Python module); here its --timeout option and --from cells.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "dynapath/result.h"
#include "runtime/option_group.h"
#include "runtime/service_client.h"

namespace dynapath::cli {

using runtime::kSecondReplySeconds;
using runtime::ServiceClient;

// --timeout of query and feed: how long to wait for the service.
void DeclareServiceWaitOption(runtime::OptionGroup& group, double& seconds);
// --source of the commands that publish obstacle updates (feed, query);
// `default_text` is the help's default ("feed-PID").
void DeclareUpdateSourceOption(runtime::OptionGroup& group, std::optional<std::string>& source,
                               const std::string& default_text);
// "R,C" as a cell, or an error naming the option.
Result<std::pair<int32_t, int32_t>> ParseCell(const std::string& text);

}  // namespace dynapath::cli
