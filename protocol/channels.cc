#include "protocol/channels.h"

#include <unistd.h>

#include <ctime>

namespace dynapath::protocol {

std::string ChannelName(std::string_view run_id, std::string_view name) {
  std::string channel = "DYNAPATH/";
  channel += run_id;
  channel += '/';
  channel += name;
  return channel;
}

Status CheckRunId(std::string_view run_id) {
  bool ok = !run_id.empty() && run_id.size() <= 64;
  for (char c : run_id) {
    ok = ok && ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                c == '_' || c == '-');
  }
  if (!ok) {
    return Error{"run id '" + std::string(run_id) +
                 "' must be 1-64 characters of letters, digits, '_' and '-'"};
  }
  return Ok();
}

std::string NewRunId() {
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &local);
  return "r" + std::string(stamp) + "-" + std::to_string(getpid());
}

}  // namespace dynapath::protocol
