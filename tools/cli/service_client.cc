#include "tools/cli/service_client.h"

#include <optional>

namespace dynapath::cli {

void DeclareServiceWaitOption(runtime::OptionGroup& group, double& seconds) {
  group.Option("--timeout", seconds, "SECONDS",
               "how long to wait for the service (a reply, its first policy, each commit)");
}

void DeclareUpdateSourceOption(runtime::OptionGroup& group, std::optional<std::string>& source,
                               const std::string& default_text) {
  group.Option("--source", source, "NAME",
               "the updates' source name (1-64 characters; sequence numbers count per source)",
               default_text);
}

Result<std::pair<int32_t, int32_t>> ParseCell(const std::string& text) {
  const size_t comma = text.find(',');
  auto number = [](const std::string& part) -> std::optional<int32_t> {
    if (part.empty() || part.size() > 9) return std::nullopt;
    size_t i = part[0] == '-' ? 1 : 0;
    if (i == part.size()) return std::nullopt;
    for (size_t k = i; k < part.size(); ++k) {
      if (part[k] < '0' || part[k] > '9') return std::nullopt;
    }
    return static_cast<int32_t>(std::stol(part));
  };
  if (comma != std::string::npos) {
    const auto row = number(text.substr(0, comma));
    const auto col = number(text.substr(comma + 1));
    if (row && col) return std::make_pair(*row, *col);
  }
  return Error::Option("from", "must be ROW,COL (two integers), got '" + text + "'");
}

}  // namespace dynapath::cli
