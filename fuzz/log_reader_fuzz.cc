// libFuzzer target: the checked LCM log reader, the maze/change sequence
// reader of --replay and the policy log reader of `dynapath render` on an
// arbitrary file. Each returns events or one error; none may crash or
// allocate more than the file holds.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "protocol/log_reader.h"
#include "protocol/log_scenario.h"
#include "tools/view/policy_stream.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = "/tmp/dynapath_log_fuzz_" + std::to_string(getpid()) + ".lcm";
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return 0;
  std::fwrite(data, 1, size, file);
  std::fclose(file);
  if (auto log = dynapath::protocol::LogReader::Open(path)) {
    while (true) {
      auto next = log->Next();
      if (!next || !*next) break;
      if ((*next)->data.size() > size) std::abort();
    }
  }
  (void)dynapath::protocol::ReadScenarioLog(path);
  (void)dynapath::view::ReadPolicyLog(path, "", [](dynapath::policy_t&) {});
  return 0;
}
