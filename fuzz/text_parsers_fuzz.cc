// libFuzzer target: the text parsers of files a user hands DynaPath: the
// maze (--maze: DynaPath's text format and MovingAI .map files), the change
// sequence (--changes: its header and fingerprint, then every change
// checked against a 20x20 grid) and the
// study config (dynapath experiment CONFIG). The first byte picks the parser.

#include <cstdint>
#include <string>
#include <string_view>

#include "dynapath/change_sequence.h"
#include "dynapath/goal_paths.h"
#include "dynapath/grid.h"
#include "dynapath/movingai_map.h"
#include "study/study_config.h"
#include "study/study_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > (1 << 16)) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  switch (data[0] % 4) {
    case 3:
      (void)dynapath::LooksLikeMovingAiMap(text);
      (void)dynapath::ParseMovingAiMap(text);
      break;
    case 0: {
      dynapath::Result<dynapath::Grid> grid = dynapath::GridFromText(text);
      (void)dynapath::ParseGoalsText(text);  // a goals file (serve --goals)
      if (grid) (void)dynapath::ChangesFromText("", grid->rows(), grid->cols());
      break;
    }
    case 1: {
      // The header's fingerprint, then every change checked against a
      // 20x20 grid with obstacles, free cells and a station.
      dynapath::ChangeFileHeader header;
      dynapath::Result<dynapath::ChangeSequence> changes =
          dynapath::ChangesFromText(text, 20, 20, &header);
      if (changes) {
        dynapath::Grid grid(20, 20);
        for (int cell = 0; cell < grid.size(); cell += 3) grid.set(cell, dynapath::Cell::kObstacle);
        grid.set(7, dynapath::Cell::kStation);
        (void)dynapath::CheckChangesFit(*changes, grid);
        (void)(header.fingerprint == dynapath::MazeFingerprint(grid));
      }
      break;
    }
    default: {
      auto config = dynapath::study::ParseConfigText(text, "fuzz.toml");
      if (config) {
        auto values = dynapath::study::StudyFileOptions(*config);
        if (values) (void)dynapath::study::ResolveStudyOptions(*values, 2);
        dynapath::study::StudyCommandLine typed;
        dynapath::runtime::OptionFields fields;
        dynapath::runtime::OptionGroup group(fields);
        dynapath::study::DeclareStudyCommandLine(group, typed);
        (void)dynapath::study::SetOptionFields(*config, fields, nullptr);
      }
      break;
    }
  }
  return 0;
}
