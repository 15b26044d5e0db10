#include "dynapath/ros_map.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "dynapath/movingai_map.h"
#include "dynapath/text_file.h"

namespace dynapath {
namespace {

const char kYaml[] =
    "image: m.pgm\nresolution: 0.05\norigin: [-1.0, 2, 0.0]  # comment\n"
    "occupied_thresh: 0.65\nfree_thresh: 0.196\n";

// 0 = black (occupied), 254 free, 205 unknown, 100 between.
std::string Pgm5() {
  return std::string("P5\n3 2\n255\n") + std::string("\x00\xfe\xcd\xfe\x64\xfe", 6);
}

Grid Cells(const std::string& yaml, const std::string& pgm) {
  Result<RosMapInfo> info = ParseRosMapYaml(yaml);
  EXPECT_TRUE(info.ok()) << info.error().message;
  Result<Grid> grid = RosMapGrid(*info, pgm);
  EXPECT_TRUE(grid.ok()) << grid.error().message;
  return *grid;
}

TEST(RosMapTest, TrinaryNegateScaleRawGiveExactCells) {
  EXPECT_EQ(GridToText(Cells(kYaml, Pgm5())), "#.#\n.#.\n");
  EXPECT_EQ(GridToText(Cells(kYaml + std::string("mode: scale\n"), Pgm5())), "#.#\n.#.\n");
  // negate: p = v/255: 0 free, 254 occupied, 205 (0.80) occupied, 100 (0.39) unknown.
  EXPECT_EQ(GridToText(Cells(kYaml + std::string("negate: 1\n"), Pgm5())), ".##\n###\n");
  // raw: p = v/100; 0 free, 100 occupied, >100 unknown.
  EXPECT_EQ(GridToText(Cells(kYaml + std::string("mode: raw\n"), Pgm5())), ".##\n###\n");
  // ascii P2 with maxval 15 (scaled to 0..255), same picture as P5.
  EXPECT_EQ(GridToText(Cells(kYaml, "P2\n# c\n3 2\n15\n0 15 12\n15 6 15\n")), "#.#\n.#.\n");
  Result<RosMapInfo> info = ParseRosMapYaml(kYaml);
  ASSERT_TRUE(info.ok());
  EXPECT_EQ(info->image, "m.pgm");
  EXPECT_DOUBLE_EQ(info->origin[0], -1.0);
  EXPECT_EQ(info->mode, RosMapMode::kTrinary);
}

TEST(RosMapTest, RefusesBadYamlWithOneClearError) {
  const std::string base = "resolution: 0.05\norigin: [0, 0, 0]\n";
  const struct {
    std::string text, message;
  } cases[] = {
      {base + "occupied_thresh: 0.65\nfree_thresh: 0.2\n", "missing key 'image'"},
      {"image: m.pgm\n" + base + "occupied_thresh: 1.5\nfree_thresh: 0.2\n",
       "line 4: 'occupied_thresh' must be a number in 0..1"},
      {"image: m.pgm\n" + base + "occupied_thresh: 0.2\nfree_thresh: 0.6\n",
       "free_thresh must be below occupied_thresh"},
      {"image: m.pgm\n" + base + "occupied_thresh: 0.6\nfree_thresh: 0.2\nmode: fancy\n",
       "line 6: 'mode' must be trinary, scale or raw, got 'fancy'"},
      {"image: m.pgm\nimage: n.pgm\n", "line 2: key 'image' given twice"},
      {"image: m.pgm\n  nested: 1\n",
       "line 2: indented line: only flat 'key: value' lines are read"},
      {"image: m.pgm\ncolour: red\n", "line 2: unknown key 'colour'"},
      {"image: m.pgm\norigin: [1, 2]\n", "line 2: 'origin' must be [x, y, yaw]"},
  };
  for (const auto& c : cases) {
    Result<RosMapInfo> info = ParseRosMapYaml(c.text);
    ASSERT_FALSE(info.ok()) << c.text;
    EXPECT_EQ(info.error().message.substr(0, c.message.size()), c.message) << info.error().message;
  }
}

TEST(RosMapTest, RefusesBadImagesWithOneClearError) {
  const RosMapInfo info = *ParseRosMapYaml(kYaml);
  const struct {
    std::string pgm, message;
  } cases[] = {
      {"P6\n1 1\n255\n\x01", "not a PGM image (expected magic P5 or P2)"},
      {"P5\n3 2\n255\n\x01\x02", "PGM data truncated: 2 of 6 pixels"},
      {"P5\n5000 2\n255\n", "image of 5000x2 pixels: each side must be 1..4096 (the grid limit)"},
      {"P5\n1 1\n65535\n\x01\x01", "PGM header: maxval must be 1..255 (8-bit images only)"},
      {"P2\n2 1\n255\n1\n", "PGM data truncated"},
      {"P2\n2 1\n9\n1 10\n", "pixel 1: expected a number 0..9"},
      {"P2\n1 1\n9\n1 2\n", "unexpected data after the PGM's pixels"},
  };
  for (const auto& c : cases) {
    Result<Grid> grid = RosMapGrid(info, c.pgm);
    ASSERT_FALSE(grid.ok()) << c.pgm;
    EXPECT_EQ(grid.error().message.substr(0, c.message.size()), c.message) << grid.error().message;
  }
  const std::string pgm = Pgm5();
  for (size_t n = 0; n < pgm.size(); ++n) EXPECT_FALSE(RosMapGrid(info, pgm.substr(0, n)).ok());
}

TEST(RosMapTest, LoadMazeFileReadsTheImageBesideTheYaml) {
  const std::string dir = testing::TempDir() + "ros_map_" + std::to_string(::getpid());
  std::filesystem::create_directories(dir);
  ASSERT_TRUE(WriteFileAtomically(dir + "/m.pgm", Pgm5()).ok());
  ASSERT_TRUE(WriteFileAtomically(dir + "/m.yaml", std::string(kYaml)).ok());
  bool movingai = false;
  Result<Grid> grid = LoadMazeFile(dir + "/m.yaml", &movingai);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_TRUE(movingai);
  EXPECT_EQ(GridToText(*grid), "#.#\n.#.\n");
  // The extension in any case (a map copied from a camera or Windows).
  ASSERT_TRUE(WriteFileAtomically(dir + "/M5.YAML", std::string(kYaml)).ok());
  grid = LoadMazeFile(dir + "/M5.YAML", &movingai);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(GridToText(*grid), "#.#\n.#.\n");
  EXPECT_TRUE(IsRosMapPath("a/M.Yml"));
  EXPECT_FALSE(IsRosMapPath("a/yaml"));
  ASSERT_TRUE(WriteFileAtomically(dir + "/m.pgm", std::string("P5\n9000 9000\n255\n")).ok());
  grid = LoadMazeFile(dir + "/m.yaml");
  ASSERT_FALSE(grid.ok());
  EXPECT_EQ(grid.error().message, dir +
                                      "/m.pgm: image of 9000x9000 pixels: each side must be "
                                      "1..4096 (the grid limit)");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace dynapath
