#pragma once
// run --resume DIR (docs/howto/CHECKPOINTS.md).

#include <optional>
#include <string>
#include <vector>

#include "dynapath/result.h"

namespace dynapath::cli {

// `--resume DIR` (or --resume=DIR) in `args`: its DIR, and `rest` the other
// arguments; nullopt when absent.
std::optional<std::string> TakeResume(const std::vector<std::string>& args,
                                      std::vector<std::string>& rest);
// The arguments that resume the run whose checkpoints are in `dir`: its
// recorded options (DIR/run.toml) as a config file over a pipe, then the
// ones given now, which override them. A mode given now (--local, --agents,
// --embedded) replaces the recorded one.
Result<std::vector<std::string>> ResumeArgs(const std::string& dir,
                                            const std::vector<std::string>& given);

}  // namespace dynapath::cli
