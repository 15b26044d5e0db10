#pragma once
// `dynapath experiment` below its command line: what it was given
// (StudyInput), the study that describes, checked once (StudyPlan), and the
// session that runs it (StudySession): every configuration not done yet, one
// after the other (or --parallel at once), each exactly as `dynapath run`
// would, keeping the study directory resumable (per-configuration result
// files, merged result files, manifest.json and study.log).

#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dynapath/result.h"
#include "study/study_plan.h"

namespace CLI {
class App;
}

namespace dynapath::cli {

// What experiment was given: the options of its command line, its
// --config file and --force.
struct StudyInput {
  study::GivenStudyOptions command_line;
  std::optional<std::string> config_path;
  bool force = false;
  int hardware_threads = 1;  // the default of --threads
};

// A study, checked: what StudySession runs.
struct StudyPlan {
  study::StudyOptions options;
  std::vector<study::StudyConfiguration> configurations;  // in study order
  bool force = false;
  std::filesystem::path out() const { return options.out; }
};

// Reads the config file (if any), overrides it with the command line's
// values and checks the result once, before any work: an error says what is
// wrong and names the option (or the file's line) it is about.
Result<StudyPlan> PlanStudy(StudyInput input);

class StudySession {
 public:
  explicit StudySession(StudyPlan plan);
  ~StudySession();
  StudySession(const StudySession&) = delete;
  StudySession& operator=(const StudySession&) = delete;

  // Checks and locks the study directory (the manifest of the same study to
  // resume, or none; with --force the old study is deleted), opens
  // study.log as the default logger, enters the study's private network
  // (--agents; the process must still be single-threaded) and writes the
  // manifest. An error of the options is kInvalidArgument.
  Status Prepare();
  // Runs the configurations not done yet and prints the study's summary
  // line. Ok when all are done and every file is written; kCancelled when
  // stopped (Ctrl-C); otherwise an error whose message, when not empty, was
  // not printed yet.
  Status Run();

  const StudyPlan& plan() const { return plan_; }

 private:
  struct State;
  StudyPlan plan_;
  std::unique_ptr<State> state_;
};

}  // namespace dynapath::cli
