// run --resume DIR: the run's recorded options (DIR/run.toml) handed back
// to `dynapath run` as a config file over a pipe, before those given now.

#include "tools/cli/run_resume.h"

#include "dynapath/text_file.h"
#include "launch/launcher.h"
#include "runtime/checkpoint_file.h"
#include "tools/common/toml_config.h"

namespace dynapath::cli {

// `--resume DIR` (or --resume=DIR) in `args`: its DIR, and `rest` the other
// arguments; nullopt when absent.
std::optional<std::string> TakeResume(const std::vector<std::string>& args,
                                      std::vector<std::string>& rest) {
  std::optional<std::string> dir;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--resume" && i + 1 < args.size()) {
      dir = args[++i];
    } else if (args[i].rfind("--resume=", 0) == 0) {
      dir = args[i].substr(9);
    } else {
      rest.push_back(args[i]);
    }
  }
  return dir;
}

// The arguments that resume the run whose checkpoints are in `dir`: its
// recorded options (DIR/run.toml) as a config file over a pipe, then the
// ones given now, which override them. A mode given now (--local, --agents,
// --embedded) replaces the recorded one.
Result<std::vector<std::string>> ResumeArgs(const std::string& dir,
                                            const std::vector<std::string>& given) {
  for (const std::string& arg : given) {
    if (arg == "--config" || arg.rfind("--config=", 0) == 0) {
      return Error::Option("resume", "takes the run's options from " + dir + "; not with --config");
    }
  }
  const std::string recorded_path = dir + "/" + runtime::kCheckpointOptionsName;
  Result<std::string> recorded = ReadTextFile(recorded_path);
  if (!recorded) {
    return Error::Option("resume", dir + " is not the checkpoint directory of a run (" +
                                       recorded.error().message + ")");
  }
  // The options files' one rule, checked here so that an error names the
  // file (the run reads it from a pipe).
  if (Result<study::ConfigFile> checked = study::ParseConfigText(*recorded, recorded_path);
      !checked) {
    return checked.error();
  }
  bool mode_given = false;
  for (const std::string& arg : given) {
    for (const char* mode : {"--local", "--agents", "--embedded"}) {
      mode_given = mode_given || arg == mode || arg.rfind(std::string(mode) + "=", 0) == 0;
    }
  }
  std::string text;
  size_t at = 0;
  while (at < recorded->size()) {
    size_t end = recorded->find('\n', at);
    if (end == std::string::npos) end = recorded->size();
    const std::string line = recorded->substr(at, end - at);
    at = end + 1;
    const bool mode_line = line.rfind("local=", 0) == 0 || line.rfind("agents=", 0) == 0 ||
                           line.rfind("embedded=", 0) == 0;
    if (mode_given && mode_line) continue;
    text += line + "\n";
  }
  const int fd = launch::TextPipe(text);
  if (fd < 0) return Error::Io(recorded_path + ": cannot hand it to the run");
  // DIR as given now: the recorded path may be relative to another folder,
  // or the directory copied.
  std::vector<std::string> args = {"--config", "/dev/fd/" + std::to_string(fd),
                                   "--resume-checkpoint", "--checkpoint", dir};
  args.insert(args.end(), given.begin(), given.end());
  return args;
}

}  // namespace dynapath::cli
