#pragma once
// run --resume DIR (docs/howto/CHECKPOINTS.md).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/run_session.h"
#include "dynapath/result.h"
#include "study/study_config.h"

namespace dynapath::cli {

// `--resume DIR` (or --resume=DIR) in `args`: its DIR, and `rest` the other
// arguments; nullopt when absent.
std::optional<std::string> TakeResume(const std::vector<std::string>& args,
                                      std::vector<std::string>& rest);
// The options recorded by the run whose checkpoints are in `dir`
// (DIR/run.toml), read by the options files' one rule. `given` are the
// arguments given now: --config is refused with --resume.
Result<study::ConfigFile> ReadRecordedOptions(const std::string& dir,
                                              const std::vector<std::string>& given);
// Makes `o`, the options given now (`given_now(key)`: the option --KEY was
// on the command line), resume that run: each recorded option not given now
// is set into `o` (a mode given now, --local, --agents or --embedded,
// replaces the recorded one), and the run continues from DIR's checkpoint.
Status ApplyRecordedOptions(const std::string& dir, const study::ConfigFile& recorded,
                            const std::function<bool(const std::string& key)>& given_now,
                            app::RunOptions& o);

}  // namespace dynapath::cli
