// run --resume DIR: the run's recorded options (DIR/run.toml) read into the
// run's options, under those given now.

#include "tools/cli/run_resume.h"

#include "dynapath/text_file.h"
#include "runtime/checkpoint_file.h"
#include "runtime/option_group.h"

namespace dynapath::cli {

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

Result<study::ConfigFile> ReadRecordedOptions(const std::string& dir,
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
  return study::ParseConfigText(*recorded, recorded_path);
}

Status ApplyRecordedOptions(const std::string& dir, const study::ConfigFile& recorded,
                            const std::function<bool(const std::string& key)>& given_now,
                            app::RunOptions& o) {
  if (given_now("checkpoint")) {
    return Error::Option(
        "resume", "continues the run whose checkpoints are in " + dir + "; not with --checkpoint");
  }
  const bool mode_given = given_now("local") || given_now("agents") || given_now("embedded");
  runtime::OptionFields fields;
  runtime::OptionGroup group(fields);
  app::DeclareRecordedOptions(group, o);
  Status set = study::SetOptionFields(recorded, fields, [&](const std::string& key) {
    const bool mode = key == "local" || key == "agents" || key == "embedded";
    return (mode && mode_given) || given_now(key);
  });
  if (!set) return set;
  // DIR as given now: the recorded path may be relative to another folder,
  // or the directory copied.
  o.run.checkpoint = dir;
  o.run.resume_checkpoint = true;
  return Ok{};
}

}  // namespace dynapath::cli
