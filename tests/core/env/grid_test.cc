#include "dynapath/grid.h"

#include <gtest/gtest.h>

#include "tests/temp_path.h"

#include <filesystem>

namespace dynapath {
namespace {

TEST(GridTest, IndexingIsRowMajor) {
  Grid grid(3, 4);
  EXPECT_EQ(grid.size(), 12);
  EXPECT_EQ(grid.Index(2, 1), 9);
  EXPECT_EQ(grid.RowOf(9), 2);
  EXPECT_EQ(grid.ColOf(9), 1);
  EXPECT_TRUE(grid.InBounds(2, 3));
  EXPECT_FALSE(grid.InBounds(3, 0));
  EXPECT_FALSE(grid.InBounds(0, -1));
  grid.set(1, 2, Cell::kStation);
  EXPECT_EQ(grid.at(6), Cell::kStation);
  EXPECT_EQ(grid.Count(Cell::kStation), 1);
  EXPECT_EQ(grid.Count(Cell::kFree), 11);
}

TEST(GridTest, TextRoundTrip) {
  const std::string text = "#.C\n..#\n";
  Result<Grid> grid = GridFromText(text);
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(grid->rows(), 2);
  EXPECT_EQ(grid->cols(), 3);
  EXPECT_EQ(grid->at(0, 0), Cell::kObstacle);
  EXPECT_EQ(grid->at(0, 2), Cell::kStation);
  EXPECT_EQ(grid->at(1, 2), Cell::kObstacle);
  EXPECT_EQ(GridToText(*grid), text);
}

TEST(GridTest, TextIgnoresCommentsBlankLinesAndCarriageReturns) {
  Result<Grid> grid = GridFromText("; a comment\n\n.C\r\n#.\r\n");
  ASSERT_TRUE(grid.ok()) << grid.error().message;
  EXPECT_EQ(grid->rows(), 2);
  EXPECT_EQ(grid->cols(), 2);
}

TEST(GridTest, BadTextGivesOneClearError) {
  Result<Grid> ragged = GridFromText("...\n..\n");
  ASSERT_FALSE(ragged.ok());
  EXPECT_NE(ragged.error().message.find("line 2"), std::string::npos);
  Result<Grid> bad_char = GridFromText("..x\n");
  ASSERT_FALSE(bad_char.ok());
  EXPECT_NE(bad_char.error().message.find("'x'"), std::string::npos);
  EXPECT_FALSE(GridFromText("").ok());
  EXPECT_FALSE(GridFromText("\n; only a comment\n").ok());
}

TEST(GridTest, SaveAndLoadFile) {
  const std::string path = test_paths::UniqueTempPath("grid_test_maze.txt");
  Grid grid(4, 5);
  grid.set(1, 1, Cell::kObstacle);
  grid.set(3, 4, Cell::kStation);
  ASSERT_TRUE(SaveGrid(grid, path).ok());
  Result<Grid> loaded = LoadGrid(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  EXPECT_EQ(*loaded, grid);
  std::filesystem::remove(path);
}

TEST(GridTest, MissingFileIsAnError) {
  Result<Grid> loaded = LoadGrid("/nonexistent/dir/maze.txt");
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().message.find("/nonexistent/dir/maze.txt"), std::string::npos);
}

}  // namespace
}  // namespace dynapath
