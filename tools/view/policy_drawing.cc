#include "tools/view/policy_drawing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dynapath/grid.h"
#include "dynapath/mdp.h"

namespace dynapath::view {
namespace {

constexpr int8_t kObstacleCode = static_cast<int8_t>(Cell::kObstacle);
constexpr int8_t kFreeCode = static_cast<int8_t>(Cell::kFree);
constexpr int8_t kStationCode = static_cast<int8_t>(Cell::kStation);

std::string StepText(int time_step) { return "step " + std::to_string(time_step); }

std::string SuccessText(const PolicySummary& summary) {
  if (summary.success_rate < 0) return "success -";
  char text[32];
  std::snprintf(text, sizeof text, "success %.1f%%", 100.0 * summary.success_rate);
  return text;
}

}  // namespace

const std::vector<Rgb>& DrawingPalette() {
  static const std::vector<Rgb> palette = {
      colour::kHeader,   colour::kHeaderText, colour::kFree,   colour::kObstacle,
      colour::kStation,  colour::kFailing,    colour::kArrow,  colour::kRegion,
      colour::kGridLine, colour::kMover,      colour::kLegend, colour::kLegendText,
  };
  return palette;
}

int AutoCellSize(int rows, int cols) {
  const int side = std::max({rows, cols, 1});
  if (side <= 50) return 16;
  return std::clamp(800 / side, 1, 16);
}

PolicySummary Summarize(const policy_t& policy) {
  PolicySummary summary;
  for (int8_t reach : policy.reaches) {
    if (reach < 0) continue;
    ++summary.starts;
    if (reach == 1) ++summary.reaching;
  }
  if (summary.starts > 0) {
    summary.success_rate = static_cast<double>(summary.reaching) / summary.starts;
  }
  return summary;
}

void MovingCells::Add(const policy_t& policy) {
  if (first_.empty()) {
    first_.assign(policy.cells.begin(), policy.cells.end());
    moving_.assign(first_.size(), 0);
  }
  if (policy.cells.size() != first_.size()) return;  // another grid: not this run's
  for (size_t i = 0; i < first_.size(); ++i) {
    if ((policy.cells[i] == kObstacleCode) != (first_[i] == kObstacleCode)) {
      moving_[i] = 1;
    }
  }
}

bool MovingCells::any() const {
  return std::find(moving_.begin(), moving_.end(), 1) != moving_.end();
}

namespace {

bool HasMovers(const DrawOptions& options) {
  return options.moving != nullptr &&
         std::find(options.moving->begin(), options.moving->end(), 1) != options.moving->end();
}

// The legend: a swatch and a name per colour the run's pictures use,
// wrapped to the picture's width. It depends on the options and the width
// only, so every frame of a run has the same size.
void LayOutLegend(PolicyLayout& layout, const DrawOptions& options) {
  std::vector<std::pair<Rgb, std::string>> entries = {{colour::kFree, "free"},
                                                      {colour::kObstacle, "obstacle"}};
  if (HasMovers(options)) entries.emplace_back(colour::kMover, "moving obstacle");
  entries.emplace_back(colour::kStation, "station");
  entries.emplace_back(colour::kFailing, "start that fails");
  if (layout.arrows) entries.emplace_back(colour::kArrow, "action");
  entries.emplace_back(colour::kRegion, "retrained region");
  const int swatch = kGlyphHeight + 2, gap = 8, margin = 3;
  const int width = std::max(layout.width, 1);
  int row = 0, x = margin;
  for (const auto& [rgb, name] : entries) {
    const int needed = swatch + 3 + TextWidth(name, 1);
    if (x > margin && x + needed > width - margin) {
      ++row;
      x = margin;
    }
    layout.legend.push_back({rgb, name, row, x});
    x += needed + gap;
  }
  layout.height = layout.legend_y + (row + 1) * (kLineHeight + 2) + 2 * margin;
}

}  // namespace

PolicyLayout LayoutFor(const policy_t& policy, const DrawOptions& options) {
  PolicyLayout layout;
  layout.cell = options.cell_px > 0 ? std::min(options.cell_px, kMaxCellPx)
                                    : AutoCellSize(policy.rows, policy.cols);
  layout.arrows = layout.cell >= kMinArrowCell;
  const int grid_width = policy.cols * layout.cell;
  const int grid_height = policy.rows * layout.cell;
  layout.width = grid_width;
  if (options.header) {
    // The header's shape depends only on the approach and the picture's
    // width (never on the step's numbers), so all frames of a run have the
    // same size: the widest numbers decide.
    const std::string widest = StepText(9999) + "  success 100.0%";
    const std::string joined = policy.approach + "  " + widest;
    int scale = 1;
    int lines = 2;
    for (int s : {2, 1}) {
      const int room = grid_width - 2 * 3 * s;
      if (TextWidth(joined, s) <= room) {
        scale = s, lines = 1;
        break;
      }
      if (TextWidth(policy.approach, s) <= room && TextWidth(widest, s) <= room) {
        scale = s, lines = 2;
        break;
      }
    }
    layout.text_scale = scale;
    const PolicySummary summary = Summarize(policy);
    const std::string numbers = StepText(policy.time_step) + "  " + SuccessText(summary);
    if (lines == 1) {
      layout.header_lines = {policy.approach + "  " + numbers};
    } else {
      layout.header_lines = {policy.approach, numbers};
    }
    layout.grid_y = scale * (lines * kLineHeight + 4);
  }
  layout.height = layout.grid_y + grid_height;
  layout.legend_y = layout.height;
  if (options.legend) LayOutLegend(layout, options);
  return layout;
}

RgbImage DrawPolicy(const policy_t& policy, const DrawOptions& options) {
  const PolicyLayout layout = LayoutFor(policy, options);
  RgbImage image(layout.width, layout.height, colour::kFree);
  const int cell = layout.cell;

  if (layout.grid_y > 0) {
    FillRect(image, 0, 0, layout.width, layout.grid_y, colour::kHeader);
    const int s = layout.text_scale;
    for (size_t i = 0; i < layout.header_lines.size(); ++i) {
      DrawText(image, 3 * s, 3 * s + static_cast<int>(i) * kLineHeight * s, layout.header_lines[i],
               s, colour::kHeaderText);
    }
  }

  // Cells.
  const std::vector<uint8_t>* moving =
      options.moving != nullptr && options.moving->size() == policy.cells.size() ? options.moving
                                                                                 : nullptr;
  for (int r = 0; r < policy.rows; ++r) {
    for (int c = 0; c < policy.cols; ++c) {
      const size_t i = static_cast<size_t>(r) * policy.cols + c;
      Rgb fill = colour::kFree;
      if (policy.cells[i] == kObstacleCode) {
        fill = moving != nullptr && (*moving)[i] ? colour::kMover : colour::kObstacle;
      } else if (policy.cells[i] == kStationCode) {
        fill = colour::kStation;
      } else if (policy.reaches[i] == 0) {
        fill = colour::kFailing;
      }
      FillRect(image, layout.grid_x + c * cell, layout.grid_y + r * cell, cell, cell, fill);
    }
  }

  if (layout.arrows) {
    // Grid lines on the top and left pixel of every cell, plus the far edges.
    for (int r = 0; r <= policy.rows; ++r) {
      const int y = std::min(layout.grid_y + r * cell, layout.height - 1);
      FillRect(image, layout.grid_x, y, policy.cols * cell, 1, colour::kGridLine);
    }
    for (int c = 0; c <= policy.cols; ++c) {
      const int x = std::min(layout.grid_x + c * cell, layout.width - 1);
      FillRect(image, x, layout.grid_y, 1, policy.rows * cell, colour::kGridLine);
    }
    // Arrows: a shaft from behind the centre and a head at the front.
    const double shaft_width = std::max(1.0, std::round(cell / 8.0));
    for (int r = 0; r < policy.rows; ++r) {
      for (int c = 0; c < policy.cols; ++c) {
        const size_t i = static_cast<size_t>(r) * policy.cols + c;
        const int action = policy.actions[i];
        if (action < 0 || action >= kNumActions || policy.cells[i] != kFreeCode) continue;
        double dx = kActionColOffset[action], dy = kActionRowOffset[action];
        const double norm = std::hypot(dx, dy);
        dx /= norm, dy /= norm;
        const double cx = CellCentreX(layout, c) + 0.5, cy = CellCentreY(layout, r) + 0.5;
        const double tip = 0.42 * cell, tail = 0.36 * cell;
        const double head = 0.40 * cell, half_width = 0.26 * cell;
        const double tx = cx + dx * tip, ty = cy + dy * tip;
        const double bx = tx - dx * head, by = ty - dy * head;
        ThickLine(image, cx - dx * tail, cy - dy * tail, bx + dx * 0.5, by + dy * 0.5, shaft_width,
                  colour::kArrow);
        FillTriangle(image, tx, ty, bx - dy * half_width, by + dx * half_width,
                     bx + dy * half_width, by - dx * half_width, colour::kArrow);
      }
    }
  }

  // Retrained regions, over everything else.
  const int thickness = cell >= 12 ? 2 : 1;
  for (int32_t k = 0; k < policy.num_regions; ++k) {
    OutlineRect(image, layout.grid_x + policy.region_col0[k] * cell,
                layout.grid_y + policy.region_row0[k] * cell, policy.region_cols[k] * cell,
                policy.region_rows[k] * cell, thickness, colour::kRegion);
  }

  if (!layout.legend.empty()) {
    FillRect(image, 0, layout.legend_y, layout.width, layout.height - layout.legend_y,
             colour::kLegend);
    const int swatch = kGlyphHeight + 2, margin = 3;
    for (const PolicyLayout::LegendEntry& entry : layout.legend) {
      const int y = layout.legend_y + margin + entry.row * (kLineHeight + 2);
      FillRect(image, entry.x, y, swatch, swatch, entry.colour);
      OutlineRect(image, entry.x, y, swatch, swatch, 1, colour::kLegendText);
      DrawText(image, entry.x + swatch + 3, y + 1, entry.name, 1, colour::kLegendText);
    }
  }
  return image;
}

}  // namespace dynapath::view
