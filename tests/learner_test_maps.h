#pragma once
// Hand-made maps shared by the learner tests: a 10x10 and a 20x20 maze with
// walls and two stations, where every free cell can reach a station.

#include <gtest/gtest.h>

#include "core/grid.h"

namespace dynapath::test_maps {

// Hand-made maps: walls, two stations, and (20x20) two enclosed pockets that
// no policy can get out of.
inline constexpr const char* kMap10 =
    "..........\n"
    "..#####...\n"
    "......#...\n"
    ".C....#...\n"
    "......#...\n"
    "###...#...\n"
    "......#.C.\n"
    "..#.......\n"
    "..#.......\n"
    "..#.......\n";
inline constexpr const char* kMap20 =
    "....................\n"
    ".C.....#............\n"
    ".......#............\n"
    ".......#.....####...\n"
    ".......#.....#..#...\n"
    ".......#.....#..#...\n"
    ".......#.....####...\n"
    ".......#............\n"
    ".......#............\n"
    ".......######.......\n"
    "....................\n"
    "..............#.....\n"
    "..............#.....\n"
    "....########..#.....\n"
    "..............#.....\n"
    "..............#...C.\n"
    "..............#.....\n"
    ".....###......#.....\n"
    ".....#.#............\n"
    ".....###............\n";

inline Grid MapFromText(const char* text) {
  Result<Grid> grid = GridFromText(text);
  EXPECT_TRUE(grid.ok());
  return *grid;
}

}  // namespace dynapath::test_maps
