#pragma once
// ROS map_server maps: a YAML file naming a grayscale PGM image.
//   image: office.pgm          (path relative to the YAML file's folder)
//   resolution: 0.05           (metres per cell; > 0, checked, not used)
//   origin: [-10.0, -10.0, 0.0] (three numbers; checked, not used)
//   occupied_thresh: 0.65      (0..1)
//   free_thresh: 0.196         (0..1, below occupied_thresh)
//   negate: 0                  (0/1 or false/true; default 0)
//   mode: trinary              (trinary (default), scale or raw)
// The YAML is read by a small strict parser of exactly this flat
// "key: value" subset (comments and blank lines allowed); any other key,
// a nested or repeated key, or a missing required one is refused.
// The image is a PGM, binary P5 or ascii P2, maxval 1..255.
// Cells, per map_server: trinary and scale take the pixel v scaled to
// 0..255 (v * 255 / maxval, rounded) and p = (255 - v) / 255, or v / 255
// with negate; p > occupied_thresh is an obstacle, p < free_thresh free,
// anything between (map_server's "unknown", or scale's partly occupied) is
// an obstacle: a planner must not route through cells nobody saw free. For
// a grayscale PGM (no alpha) scale therefore gives the same cells as
// trinary. raw: the unscaled pixel value is the occupancy in percent,
// p = v / 100 compared with the same thresholds, v > 100 (unknown) an
// obstacle; negate does not apply. The PGM's first row (the top of the
// image) is row 0 of the grid. Sides are limited to kMaxGridSide
// (limits.h), as for MovingAI maps. Maps have no stations (map_scenario.h).

#include <string>
#include <string_view>

#include "dynapath/grid.h"
#include "dynapath/result.h"

namespace dynapath {

enum class RosMapMode { kTrinary, kScale, kRaw };

struct RosMapInfo {
  std::string image;  // as written in the YAML
  double resolution = 0;
  double origin[3] = {0, 0, 0};
  double occupied_thresh = 0;
  double free_thresh = 0;
  bool negate = false;
  RosMapMode mode = RosMapMode::kTrinary;
};

// The YAML file's bytes; one clear error (with the line) when they are not
// a well-formed map_server file.
Result<RosMapInfo> ParseRosMapYaml(std::string_view bytes);

// The PGM image's bytes as a grid, cells decided by `info`.
Result<Grid> RosMapGrid(const RosMapInfo& info, std::string_view pgm);

// True when `path` ends in .yaml or .yml (how --maze tells a ROS map).
bool IsRosMapPath(const std::string& path);

// The YAML file at `path` and the image it names; errors name the file.
Result<Grid> LoadRosMap(const std::string& path);

}  // namespace dynapath
