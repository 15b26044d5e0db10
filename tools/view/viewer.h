#pragma once
// The dynapath-view window (SFML): shows the latest policy of the chosen
// approach as drawn by policy_drawing, with zoom, pan and a status bar.

#include <string>

#include "tools/view/policy_feed.h"

namespace dynapath::view {

struct ViewerOptions {
  int window_width = 960;
  int window_height = 760;
  int cell_px = 0;       // 0: AutoCellSize
  std::string approach;  // shown first ("" follows the latest approach)
  std::string lcm_url;   // for the status bar
  // Screenshot mode: once `screenshot_after` valid policies have arrived,
  // save what the window shows to `screenshot` (PNG) and return; fail after
  // `timeout_seconds` without them.
  std::string screenshot;
  int screenshot_after = 1;
  double timeout_seconds = 60;
};

// Runs the window until it is closed (0), Q/Escape (0), SIGINT/SIGTERM (0),
// or the screenshot is saved (0) or timed out (1). Errors are printed.
int RunViewer(PolicyFeed& feed, const ViewerOptions& options);

}  // namespace dynapath::view
