// libFuzzer target: the text parsers of files a user hands DynaPath: the
// maze (--maze: DynaPath's text format and MovingAI .map files), the change
// sequence (--changes, against the parsed maze or a 20x20 grid) and the
// study config (dynapath experiment CONFIG). The first byte picks the parser.

#include <cstdint>
#include <string>
#include <string_view>

#include "dynapath/change_sequence.h"
#include "dynapath/grid.h"
#include "dynapath/movingai_map.h"
#include "tools/common/study_config.h"
#include "tools/common/study_plan.h"

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
      if (grid) (void)dynapath::ChangesFromText("", grid->rows(), grid->cols());
      break;
    }
    case 1:
      (void)dynapath::ChangesFromText(text, 20, 20);
      break;
    default: {
      auto config = dynapath::cli::ParseConfigText(text, "fuzz.toml");
      if (config) {
        auto values = dynapath::cli::ConfigOptionValues(*config);
        if (values) (void)dynapath::cli::ResolveStudyOptions(*values, 2);
      }
      break;
    }
  }
  return 0;
}
