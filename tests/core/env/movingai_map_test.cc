#include "dynapath/movingai_map.h"

#include <gtest/gtest.h>

#include <string>

namespace dynapath {
namespace {

const char kWide[] =
    "type octile\n"
    "height 3\n"
    "width 5\n"
    "map\n"
    ".@G..\n"
    "TSWO.\n"
    ".....\n";

TEST(MovingAiMapTest, ParsesTerrainOfEveryKind) {
  Result<Grid> grid = ParseMovingAiMap(kWide);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(grid->rows(), 3);
  EXPECT_EQ(grid->cols(), 5);
  EXPECT_EQ(GridToText(*grid), ".#...\n#.##.\n.....\n");
  EXPECT_EQ(grid->Count(Cell::kStation), 0);
}

TEST(MovingAiMapTest, AcceptsCrLfAndTrailingBlankLines) {
  std::string text = kWide;
  std::string crlf;
  for (char ch : text) crlf += ch == '\n' ? std::string("\r\n") : std::string(1, ch);
  Result<Grid> grid = ParseMovingAiMap(crlf + "\r\n\n");
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(*grid, *ParseMovingAiMap(kWide));
}

// One clear error, naming the line, for each kind of damage.
TEST(MovingAiMapTest, RefusesBadFilesWithOneClearError) {
  const std::string header = "type octile\nheight 2\nwidth 3\nmap\n";
  const struct {
    std::string text;
    std::string error;
  } cases[] = {
      {"", "line 1: expected 'type octile'"},
      {"type tile\nheight 2\nwidth 3\nmap\n...\n...\n", "line 1: expected 'type octile'"},
      {"type octile\nwidth 3\nheight 2\nmap\n...\n...\n", "line 2: expected 'height N'"},
      {"type octile\nheight 0\nwidth 3\nmap\n", "line 2: expected 'height N'"},
      {"type octile\nheight 2x\nwidth 3\nmap\n", "line 2: expected 'height N'"},
      {"type octile\nheight 4097\nwidth 3\nmap\n", "line 2: expected 'height N'"},
      {"type octile\nheight 2\nwidth -3\nmap\n", "line 3: expected 'width N'"},
      {"type octile\nheight 2\n", "the header ends before 'width N'"},
      {"type octile\nheight 2\nwidth 3\nmaps\n...\n...\n", "line 4: expected 'map'"},
      {header + "...\n..\n", "line 6: a row of 2 cells, the header says width 3"},
      {header + "...\n", "the map ends after 1 of its 2 rows"},
      {header + "...\n...", ""},  // a last row without newline is fine
      {header + "...\n.X.\n", "line 6: column 2: unknown terrain 'X'"},
      {header + "...\n.\x01.\n", "line 6: column 2: unknown terrain byte 1"},
      {header + "...\n...\n...\n", "line 7: unexpected data after the map's rows"},
      {"type octile\nheight 4096\nwidth 4096\nmap\n...\n", "too short"},
  };
  for (const auto& c : cases) {
    Result<Grid> grid = ParseMovingAiMap(c.text);
    if (c.error.empty()) {
      EXPECT_TRUE(grid.ok()) << c.text;
      continue;
    }
    ASSERT_FALSE(grid.ok()) << c.text;
    EXPECT_NE(grid.error().message.find(c.error), std::string::npos)
        << c.text << " -> " << grid.error().message;
  }
}

TEST(MovingAiMapTest, EveryTruncationIsAnErrorOrAMapNeverACrash) {
  const std::string text = kWide;
  for (size_t n = 0; n <= text.size(); ++n) {
    Result<Grid> grid = ParseMovingAiMap(text.substr(0, n));
    if (grid.ok()) {
      EXPECT_EQ(grid->size(), 15);
    }
  }
}

TEST(MovingAiMapTest, LoadMazeFileTellsTheKinds) {
  bool movingai = false;
  Result<Grid> map =
      LoadMazeFile(std::string(DYNAPATH_TEST_DATA_DIR) + "/maps/wide-5-9.map", &movingai);
  ASSERT_TRUE(map.ok()) << map.error().message;
  EXPECT_TRUE(movingai);
  EXPECT_EQ(map->rows(), 5);
  EXPECT_EQ(map->cols(), 9);
  EXPECT_FALSE(LoadMazeFile("/nonexistent/x.map").ok());
}

}  // namespace
}  // namespace dynapath
