// libFuzzer target: ROS map_server maps (--maze FILE.yaml): the YAML subset
// parser, then the PGM image decoder with the thresholds it gave (or fixed
// ones when the YAML part is refused). The input is "YAML\0PGM".

#include <cstdint>
#include <string>
#include <string_view>

#include "dynapath/ros_map.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1 << 16)) return 0;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const size_t split = bytes.find('\0');
  const std::string_view yaml = bytes.substr(0, split);
  const std::string_view pgm = split == std::string_view::npos ? "" : bytes.substr(split + 1);
  dynapath::Result<dynapath::RosMapInfo> info = dynapath::ParseRosMapYaml(yaml);
  dynapath::RosMapInfo fixed;
  fixed.occupied_thresh = 0.65;
  fixed.free_thresh = 0.196;
  (void)dynapath::RosMapGrid(info ? *info : fixed, pgm);
  return 0;
}
