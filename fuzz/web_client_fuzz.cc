// libFuzzer: what `dynapath web` parses of outside bytes: a Foxglove
// client's text message (tools/web/messages.h ParseClientMessage), the
// Host and Origin headers and --allow-host values (tools/web/host_check.h),
// and the page's frame codec read back (ParseFrame, ApplyDelta) on any bytes.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "tools/web/host_check.h"
#include "tools/web/messages.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  dynapath::web::ClientMessage message = dynapath::web::ParseClientMessage(text, 16);
  if (message.kind == dynapath::web::ClientMessage::kSubscribe && message.subscribe.size() > 16) {
    __builtin_trap();
  }
  const dynapath::web::HostPolicy policy{"::1", 8080, {"runs.example.org", "[fe80::1]:80"}};
  const bool host = dynapath::web::HostAllowed(text, policy);
  dynapath::web::OriginAllowed(text, policy);
  // What is allowed names this server or an allowed name, so it is itself
  // a usable --allow-host value.
  if (host && !dynapath::web::AllowHostError(text).empty()) __builtin_trap();
  dynapath::web::FrameHeader header;
  std::vector<uint32_t> indices;
  std::vector<uint8_t> cells;
  if (dynapath::web::ParseFrame(data, size, header, indices, cells) &&
      header.kind == dynapath::web::FrameKind::kDelta) {
    std::vector<uint8_t> grid(static_cast<size_t>(header.rows) * static_cast<size_t>(header.cols) >
                                      (size_t{1} << 20)
                                  ? 0
                                  : static_cast<size_t>(header.rows) * header.cols);
    dynapath::web::ApplyDelta(indices, cells, grid);
  }
  return 0;
}
