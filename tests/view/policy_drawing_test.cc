#include "tools/view/policy_drawing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "protocol/validate.h"
#include "tests/view/policy_test_support.h"
#include "tools/view/safe_name.h"

namespace dynapath::view {
namespace {

using testing::AddRegion;
using testing::MakePolicy;

constexpr int kE = 2, kN = 0, kSW = 5;

// A 4x5 maze:      row 0: . . . # C
//                  row 1: . > . . .     (1,1) points east, reaches a station
//                  row 2: . . ^ x .     (2,2) points north; (2,3) fails
//                  row 3: . . . . .
// with the region rows 2-3, columns 0-1 retrained.
policy_t SmallPolicy() {
  policy_t policy = MakePolicy(4, 5);
  policy.cells[0 * 5 + 3] = 0;
  policy.cells[0 * 5 + 4] = 2;
  policy.actions[1 * 5 + 1] = kE;
  policy.reaches[1 * 5 + 1] = 1;
  policy.actions[2 * 5 + 2] = kN;
  policy.reaches[2 * 5 + 2] = 1;
  policy.reaches[2 * 5 + 3] = 0;
  AddRegion(policy, 2, 0, 2, 2);
  return policy;
}

// The pixel at an offset from a cell's centre.
Rgb Near(const RgbImage& image, const PolicyLayout& layout, int row, int col, int dx, int dy) {
  const int x = layout.grid_x + col * layout.cell + layout.cell / 2 + dx;
  const int y = layout.grid_y + row * layout.cell + layout.cell / 2 + dy;
  return image.At(x, y);
}

TEST(PolicyDrawing, TheTestPolicyIsValid) { EXPECT_TRUE(protocol::Validate(SmallPolicy()).ok()); }

TEST(PolicyDrawing, AutoCellSize) {
  EXPECT_EQ(AutoCellSize(5, 5), 16);
  EXPECT_EQ(AutoCellSize(20, 20), 16);
  EXPECT_EQ(AutoCellSize(50, 50), 16);
  EXPECT_EQ(AutoCellSize(30, 50), 16);
  EXPECT_EQ(AutoCellSize(100, 100), 8);
  EXPECT_EQ(AutoCellSize(100, 200), 4);
  EXPECT_EQ(AutoCellSize(300, 300), 2);
  EXPECT_EQ(AutoCellSize(4096, 4096), 1);
}

TEST(PolicyDrawing, ImageSizeForGridAndCellSize) {
  const policy_t policy = SmallPolicy();
  DrawOptions options;
  options.header = false;
  options.cell_px = 16;
  RgbImage image = DrawPolicy(policy, options);
  EXPECT_EQ(image.width(), 5 * 16);
  EXPECT_EQ(image.height(), 4 * 16);

  options.cell_px = 7;
  image = DrawPolicy(policy, options);
  EXPECT_EQ(image.width(), 35);
  EXPECT_EQ(image.height(), 28);

  // With the header: the grid below it, the width unchanged.
  options.header = true;
  options.cell_px = 16;
  const PolicyLayout layout = LayoutFor(policy, options);
  image = DrawPolicy(policy, options);
  EXPECT_GT(layout.grid_y, 0);
  EXPECT_EQ(layout.grid_x, 0);
  EXPECT_EQ(image.width(), 80);
  EXPECT_EQ(image.height(), layout.grid_y + 64);
  EXPECT_EQ(image.width(), layout.width);
  EXPECT_EQ(image.height(), layout.height);

  // Automatic cell sizes: 16 px for 20x20, 8 px for 100x100.
  EXPECT_EQ(DrawPolicy(MakePolicy(20, 20), DrawOptions{0, false}).width(), 320);
  EXPECT_EQ(DrawPolicy(MakePolicy(100, 100), DrawOptions{0, false}).width(), 800);
  EXPECT_EQ(DrawPolicy(MakePolicy(100, 100), DrawOptions{0, false}).height(), 800);
}

TEST(PolicyDrawing, SizeDoesNotDependOnTheStepsNumbers) {
  // All frames of an animation must have one size.
  policy_t a = MakePolicy(6, 6, "A* Oracle", 0);
  policy_t b = MakePolicy(6, 6, "A* Oracle", 1234);
  std::fill(b.reaches.begin(), b.reaches.end(), 1);
  const RgbImage first = DrawPolicy(a), second = DrawPolicy(b);
  EXPECT_EQ(first.width(), second.width());
  EXPECT_EQ(first.height(), second.height());
}

TEST(PolicyDrawing, CellColours) {
  const policy_t policy = SmallPolicy();
  for (int cell : {16, 9, 4, 1}) {
    SCOPED_TRACE("cell " + std::to_string(cell));
    DrawOptions options;
    options.cell_px = cell;
    const PolicyLayout layout = LayoutFor(policy, options);
    const RgbImage image = DrawPolicy(policy, options);
    EXPECT_EQ(Near(image, layout, 0, 3, 0, 0), colour::kObstacle);
    EXPECT_EQ(Near(image, layout, 0, 4, 0, 0), colour::kStation);
    EXPECT_EQ(Near(image, layout, 0, 0, 0, 0), colour::kFree);
    // The failing cell is tinted red all over (it has no arrow).
    EXPECT_EQ(Near(image, layout, 2, 3, 0, 0), colour::kFailing);
    if (cell > 2) {
      EXPECT_EQ(Near(image, layout, 2, 3, cell / 4, cell / 4), colour::kFailing);
    }
  }
}

TEST(PolicyDrawing, RetrainedRegionIsOutlined) {
  const policy_t policy = SmallPolicy();
  for (int cell : {16, 8, 3}) {
    SCOPED_TRACE("cell " + std::to_string(cell));
    DrawOptions options;
    options.cell_px = cell;
    const PolicyLayout layout = LayoutFor(policy, options);
    const RgbImage image = DrawPolicy(policy, options);
    const int left = layout.grid_x, top = layout.grid_y + 2 * cell;
    const int right = left + 2 * cell - 1, bottom = top + 2 * cell - 1;
    EXPECT_EQ(image.At(left, top), colour::kRegion);
    EXPECT_EQ(image.At(right, top), colour::kRegion);
    EXPECT_EQ(image.At(left, bottom), colour::kRegion);
    EXPECT_EQ(image.At(right, bottom), colour::kRegion);
    EXPECT_EQ(image.At(left + cell, top), colour::kRegion);   // along the top edge
    EXPECT_EQ(image.At(right, top + cell), colour::kRegion);  // along the right edge
    // Inside the region: the cells' own colour.
    EXPECT_EQ(Near(image, layout, 2, 0, 0, 0), colour::kFree);
    EXPECT_EQ(Near(image, layout, 3, 1, 0, 0), colour::kFree);
    // Outside it: no outline.
    EXPECT_NE(image.At(left, top - 3), colour::kRegion);
  }
}

TEST(PolicyDrawing, ArrowPixels) {
  const policy_t policy = SmallPolicy();
  DrawOptions options;
  options.cell_px = 16;
  const PolicyLayout layout = LayoutFor(policy, options);
  ASSERT_TRUE(layout.arrows);
  const RgbImage image = DrawPolicy(policy, options);
  // (1,1) points east: the head right of the centre, the shaft left of it,
  // nothing above or below.
  EXPECT_EQ(Near(image, layout, 1, 1, 5, 0), colour::kArrow);
  EXPECT_EQ(Near(image, layout, 1, 1, 2, 2), colour::kArrow);  // the head is wide
  EXPECT_EQ(Near(image, layout, 1, 1, -4, 0), colour::kArrow);
  EXPECT_EQ(Near(image, layout, 1, 1, 0, -5), colour::kFree);
  EXPECT_EQ(Near(image, layout, 1, 1, 0, 5), colour::kFree);
  EXPECT_EQ(Near(image, layout, 1, 1, -4, -4), colour::kFree);
  // (2,2) points north.
  EXPECT_EQ(Near(image, layout, 2, 2, 0, -5), colour::kArrow);
  EXPECT_EQ(Near(image, layout, 2, 2, 0, 4), colour::kArrow);
  EXPECT_EQ(Near(image, layout, 2, 2, -5, 0), colour::kFree);
  EXPECT_EQ(Near(image, layout, 2, 2, 5, 0), colour::kFree);
  // A cell without an action has no arrow.
  EXPECT_EQ(Near(image, layout, 3, 3, 0, 0), colour::kFree);

  // A diagonal (south-west): the head down-left, the shaft up-right.
  policy_t diagonal = MakePolicy(3, 3);
  diagonal.actions[4] = kSW;
  const RgbImage picture = DrawPolicy(diagonal, options);
  const PolicyLayout diagonal_layout = LayoutFor(diagonal, options);
  EXPECT_EQ(Near(picture, diagonal_layout, 1, 1, -3, 3), colour::kArrow);
  EXPECT_EQ(Near(picture, diagonal_layout, 1, 1, 3, -3), colour::kArrow);
  EXPECT_EQ(Near(picture, diagonal_layout, 1, 1, 4, 4), colour::kFree);
  EXPECT_EQ(Near(picture, diagonal_layout, 1, 1, -4, -4), colour::kFree);
}

TEST(PolicyDrawing, SmallCellsAreColourOnly) {
  const policy_t policy = SmallPolicy();
  DrawOptions options;
  options.cell_px = kMinArrowCell - 1;
  const PolicyLayout layout = LayoutFor(policy, options);
  EXPECT_FALSE(layout.arrows);
  const RgbImage image = DrawPolicy(policy, options);
  // The whole arrow cell is free colour: no arrow, no grid lines.
  for (int dy = 0; dy < layout.cell; ++dy) {
    for (int dx = 0; dx < layout.cell; ++dx) {
      EXPECT_EQ(image.At(layout.grid_x + layout.cell + dx, layout.grid_y + layout.cell + dy),
                colour::kFree);
    }
  }
  options.cell_px = kMinArrowCell;
  EXPECT_TRUE(LayoutFor(policy, options).arrows);
}

TEST(PolicyDrawing, GridLinesBetweenCells) {
  const policy_t policy = SmallPolicy();
  DrawOptions options;
  options.cell_px = 16;
  const PolicyLayout layout = LayoutFor(policy, options);
  const RgbImage image = DrawPolicy(policy, options);
  EXPECT_EQ(image.At(layout.grid_x + 16, layout.grid_y + 8), colour::kGridLine);
  EXPECT_EQ(image.At(layout.grid_x + 8, layout.grid_y + 16), colour::kGridLine);
}

TEST(PolicyDrawing, HeaderShowsApproachStepAndSuccess) {
  policy_t policy = SmallPolicy();
  const PolicyLayout layout = LayoutFor(policy);
  ASSERT_FALSE(layout.header_lines.empty());
  std::string text;
  for (const std::string& line : layout.header_lines) text += line + "\n";
  EXPECT_NE(text.find("fedAsynQ_EqAvg"), std::string::npos) << text;
  EXPECT_NE(text.find("step 3"), std::string::npos) << text;
  // Two of the three starts reach a station.
  EXPECT_NE(text.find("success 66.7%"), std::string::npos) << text;

  const RgbImage image = DrawPolicy(policy);
  int text_pixels = 0;
  for (int y = 0; y < layout.grid_y; ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const Rgb c = image.At(x, y);
      EXPECT_TRUE(c == colour::kHeader || c == colour::kHeaderText);
      text_pixels += c == colour::kHeaderText;
    }
  }
  EXPECT_GT(text_pixels, 50);

  // No outcomes (the baselines send none): no rate.
  policy_t baseline = MakePolicy(20, 20, "A* Oracle", 7);
  const PolicyLayout baseline_layout = LayoutFor(baseline);
  std::string baseline_text;
  for (const std::string& line : baseline_layout.header_lines) baseline_text += line + "\n";
  EXPECT_NE(baseline_text.find("success -"), std::string::npos) << baseline_text;
}

TEST(PolicyDrawing, Summary) {
  policy_t policy = MakePolicy(2, 2);
  EXPECT_EQ(Summarize(policy).success_rate, -1.0);
  policy.reaches = {1, 1, 0, -1};
  const PolicySummary summary = Summarize(policy);
  EXPECT_EQ(summary.starts, 3);
  EXPECT_EQ(summary.reaching, 2);
  EXPECT_DOUBLE_EQ(summary.success_rate, 2.0 / 3.0);
}

TEST(PolicyDrawing, OnlyPaletteColours) {
  policy_t policy = MakePolicy(12, 9, "singleAgent", 17);
  for (int i = 0; i < policy.num_cells; ++i) {
    policy.cells[i] = static_cast<int8_t>(i % 7 == 0 ? 0 : (i % 11 == 0 ? 2 : 1));
    if (policy.cells[i] == 1) {
      policy.actions[i] = static_cast<int8_t>(i % 8);
      policy.reaches[i] = static_cast<int8_t>(i % 3 == 0 ? 0 : 1);
    }
  }
  AddRegion(policy, 0, 0, 12, 9);
  AddRegion(policy, 3, 4, 5, 2);
  ASSERT_TRUE(protocol::Validate(policy).ok());
  const std::vector<Rgb>& palette = DrawingPalette();
  std::vector<uint8_t> moving(static_cast<size_t>(policy.num_cells), 0);
  moving[0] = 1;
  for (int cell : {1, 4, 6, 16, 33}) {
    DrawOptions options;
    options.cell_px = cell;
    options.legend = cell != 4;
    options.moving = &moving;
    const RgbImage image = DrawPolicy(policy, options);
    std::set<int> used;
    for (int y = 0; y < image.height(); ++y) {
      for (int x = 0; x < image.width(); ++x) {
        const auto it = std::find(palette.begin(), palette.end(), image.At(x, y));
        ASSERT_NE(it, palette.end()) << "cell " << cell << " pixel " << x << "," << y;
        used.insert(static_cast<int>(it - palette.begin()));
      }
    }
    EXPECT_GE(used.size(), 5u);
  }
}

// Cells where an obstacle is at one step and not at another: the run's
// moving obstacles; walls (obstacles at every step) are not among them.
TEST(PolicyDrawing, MovingCellsAreWhereObstaclesChange) {
  policy_t step0 = SmallPolicy();  // an obstacle at (0, 3)
  step0.cells[3 * 5 + 0] = 0;      // and a wall at (3, 0)
  policy_t step1 = step0;
  step1.cells[0 * 5 + 3] = 1;  // the obstacle moves to (1, 3)
  step1.cells[1 * 5 + 3] = 0;
  MovingCells moving;
  EXPECT_TRUE(moving.cells().empty());
  moving.Add(step0);
  EXPECT_FALSE(moving.any());
  moving.Add(step1);
  EXPECT_TRUE(moving.any());
  std::vector<uint8_t> expected(20, 0);
  expected[0 * 5 + 3] = expected[1 * 5 + 3] = 1;
  EXPECT_EQ(moving.cells(), expected);

  DrawOptions options;
  options.cell_px = 16;
  options.moving = &moving.cells();
  const PolicyLayout layout = LayoutFor(step1, options);
  const RgbImage image = DrawPolicy(step1, options);
  EXPECT_EQ(Near(image, layout, 1, 3, 0, 0), colour::kMover);
  EXPECT_EQ(Near(image, layout, 3, 0, 0, 0), colour::kObstacle) << "a wall stays dark";
  EXPECT_NE(Near(image, layout, 0, 3, 0, 0), colour::kMover) << "free now";
}

// The legend below the grid: a swatch of every colour in use with its name,
// wrapped to the picture's width, of one size for every frame of a run.
TEST(PolicyDrawing, LegendNamesTheColours) {
  const policy_t policy = MakePolicy(20, 20, "fedAsynQ_EqAvg", 3);
  std::vector<uint8_t> moving(400, 0);
  moving[5] = 1;
  DrawOptions options;
  options.legend = true;
  const PolicyLayout plain = LayoutFor(policy, DrawOptions{});
  const PolicyLayout with = LayoutFor(policy, options);
  EXPECT_EQ(with.legend_y, plain.height);
  EXPECT_GT(with.height, plain.height);
  std::vector<std::string> names;
  for (const auto& entry : with.legend) names.push_back(entry.name);
  EXPECT_EQ(names, (std::vector<std::string>{"free", "obstacle", "station", "start that fails",
                                             "action", "retrained region"}));
  options.moving = &moving;
  const PolicyLayout movers = LayoutFor(policy, options);
  ASSERT_GE(movers.legend.size(), 3u);
  EXPECT_EQ(movers.legend[2].name, "moving obstacle");
  EXPECT_EQ(movers.legend[2].colour, colour::kMover);
  const RgbImage image = DrawPolicy(policy, options);
  EXPECT_EQ(image.height(), movers.height);
  for (const auto& entry : movers.legend) {
    EXPECT_LT(entry.x + 9 + 3 + TextWidth(entry.name, 1), image.width()) << entry.name;
    // The swatch's inside holds its colour.
    EXPECT_EQ(image.At(entry.x + 4, movers.legend_y + 3 + entry.row * (kLineHeight + 2) + 4),
              entry.colour)
        << entry.name;
  }
  // Another step, other numbers: the same size.
  policy_t later = MakePolicy(20, 20, "fedAsynQ_EqAvg", 4567);
  std::fill(later.reaches.begin(), later.reaches.end(), 0);
  EXPECT_EQ(DrawPolicy(later, options).height(), image.height());
  // A narrow picture wraps the legend onto more rows.
  const PolicyLayout narrow = LayoutFor(MakePolicy(4, 4), options);
  EXPECT_GT(narrow.legend.back().row, movers.legend.back().row);
}

TEST(SafeName, Approaches) {
  EXPECT_EQ(SafeName("A* Oracle"), "A_Oracle");
  EXPECT_EQ(SafeName("A* Static"), "A_Static");
  EXPECT_EQ(SafeName("BFS Oracle"), "BFS_Oracle");
  EXPECT_EQ(SafeName("fedAsynQ_EqAvg"), "fedAsynQ_EqAvg");
  EXPECT_EQ(SafeName("../x/y"), "x_y");
  EXPECT_EQ(SafeName("**"), "approach");
  EXPECT_EQ(SafeName(".."), "approach");
  EXPECT_EQ(SafeName(""), "approach");
}

}  // namespace
}  // namespace dynapath::view
