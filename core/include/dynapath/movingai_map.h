#pragma once
// MovingAI grid maps (the benchmark format of movingai.com, `.map`):
//   type octile
//   height H
//   width W
//   map
//   H rows of W characters
// Passable: '.' (ground), 'G' (ground), 'S' (swamp: passable, our moves all
// cost 1). Obstacles: '@' and 'O' (out of bounds), 'T' (trees), 'W' (water:
// impassable for octile ground moves). Any other character is refused with
// its line and column: guessing what an unknown terrain letter means would
// silently change the map. Maps have no stations (see map_scenario.h).

#include <string>
#include <string_view>

#include "dynapath/grid.h"
#include "dynapath/result.h"

namespace dynapath {

// Parses a whole file's bytes; one clear error (with the line) when the bytes
// are not a well-formed map. Sides are limited to kMaxGridSide (limits.h),
// like GridFromText's, so no count from the file can ask for unbounded memory.
Result<Grid> ParseMovingAiMap(std::string_view bytes);

// True when the bytes start like a MovingAI map ("type ").
bool LooksLikeMovingAiMap(std::string_view bytes);

// A maze file of any kind: a ROS map_server map (path ending .yaml/.yml,
// ros_map.h), a MovingAI map, or the text format of grid.h. `movingai` (if
// given) is true for a map of either kind (treated alike: no stations of its
// own, walls that do not move).
Result<Grid> LoadMazeFile(const std::string& path, bool* movingai = nullptr);

}  // namespace dynapath
