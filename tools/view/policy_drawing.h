#pragma once
// Draws one policy_t (the POLICY message of a run) as an RGB picture:
//
//   * a header: the approach, the time step and the success rate (the share
//     of start cells whose policy reaches a station, from `reaches`);
//   * the grid: free cells light, obstacles dark, stations green, free cells
//     whose policy fails tinted red;
//   * the greedy action of every free cell as an arrow (when cells are at
//     least kMinArrowCell pixels; smaller cells show colour only);
//   * the regions retrained at this step, outlined in orange;
//   * obstacles on the cells a moving obstacle visits (DrawOptions::moving)
//     in purple rather than dark;
//   * optionally a legend below the grid naming every colour (render's frames).
//
// The picture uses only the colours of DrawingPalette(), so an animated GIF
// with that palette holds it exactly. No window system here: the render tool
// writes the picture to files, the viewer uploads it to a texture.

#include <string>
#include <vector>

#include "dynapath/policy_t.hpp"
#include "tools/view/raster.h"

namespace dynapath::view {

namespace colour {
inline constexpr Rgb kHeader{32, 36, 44};
inline constexpr Rgb kHeaderText{242, 242, 242};
inline constexpr Rgb kFree{238, 238, 232};
inline constexpr Rgb kObstacle{58, 62, 72};
inline constexpr Rgb kStation{40, 160, 72};
inline constexpr Rgb kFailing{244, 172, 172};
inline constexpr Rgb kArrow{34, 68, 150};
inline constexpr Rgb kRegion{255, 140, 0};
inline constexpr Rgb kGridLine{204, 204, 198};
inline constexpr Rgb kMover{150, 80, 190};
inline constexpr Rgb kLegend{255, 255, 255};
inline constexpr Rgb kLegendText{32, 36, 44};
}  // namespace colour

// Every colour a policy picture uses (the header text and background, the
// cells, arrows, outlines and grid lines).
const std::vector<Rgb>& DrawingPalette();

inline constexpr int kMaxCellPx = 64;
inline constexpr int kMinArrowCell = 6;  // smaller cells: colour only, no grid lines

// The cell size chosen when none is given: 16 px up to 50 cells a side, then
// what keeps the grid near 800 px (at least 1 px).
int AutoCellSize(int rows, int cols);

struct DrawOptions {
  int cell_px = 0;      // 0: AutoCellSize
  bool header = true;   // the text line(s) above the grid
  bool legend = false;  // the colours' names below the grid
  // Row-major, one per cell: 1 where an obstacle is a moving one at some
  // time step of the run (MovingCells); its obstacles are drawn kMover and
  // the legend names them. Null or empty: no moving obstacles.
  const std::vector<uint8_t>* moving = nullptr;
};

// Accumulates, over a run's pictures, the cells that are an obstacle in one
// and not in another: where its obstacles move (walls never change).
class MovingCells {
 public:
  void Add(const policy_t& policy);
  // One per cell; empty before any picture.
  const std::vector<uint8_t>& cells() const { return moving_; }
  bool any() const;

 private:
  std::vector<int8_t> first_;
  std::vector<uint8_t> moving_;
};

// Where things are in a picture.
struct PolicyLayout {
  int cell = 0;   // pixels per cell side
  int width = 0;  // of the whole picture
  int height = 0;
  int grid_x = 0;       // top-left pixel of cell (0, 0)
  int grid_y = 0;       // = header height
  int text_scale = 1;   // font scale of the header
  bool arrows = false;  // cell >= kMinArrowCell
  std::vector<std::string> header_lines;
  int legend_y = 0;  // top of the legend (= height when there is none)
  // Each legend entry's swatch colour and name, and its row and x offset.
  struct LegendEntry {
    Rgb colour;
    std::string name;
    int row = 0, x = 0;
  };
  std::vector<LegendEntry> legend;
};

// The header's numbers. success_rate is reaching / starts (-1 when there are
// no starts: approaches without a table send no outcomes).
struct PolicySummary {
  int starts = 0;
  int reaching = 0;
  double success_rate = -1.0;
};
PolicySummary Summarize(const policy_t& policy);

// The layout of `policy`'s picture. The policy must be valid
// (protocol::Validate): sizes are trusted here.
PolicyLayout LayoutFor(const policy_t& policy, const DrawOptions& options = {});
RgbImage DrawPolicy(const policy_t& policy, const DrawOptions& options = {});

// The centre of cell (row, col) in picture coordinates.
inline double CellCentreX(const PolicyLayout& layout, int col) {
  return layout.grid_x + (col + 0.5) * layout.cell;
}
inline double CellCentreY(const PolicyLayout& layout, int row) {
  return layout.grid_y + (row + 0.5) * layout.cell;
}

}  // namespace dynapath::view
