#pragma once
// Draws one policy_t (the POLICY message of a run) as an RGB picture:
//
//   * a header: the approach, the time step and the success rate (the share
//     of start cells whose policy reaches a station, from `reaches`);
//   * the grid: free cells light, obstacles dark, stations green, free cells
//     whose policy fails tinted red;
//   * the greedy action of every free cell as an arrow (when cells are at
//     least kMinArrowCell pixels; smaller cells show colour only);
//   * the regions retrained at this step, outlined in orange.
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
  int cell_px = 0;     // 0: AutoCellSize
  bool header = true;  // the text line(s) above the grid
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
