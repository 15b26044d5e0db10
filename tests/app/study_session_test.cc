#include "tools/study/study_session.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "tests/study_command_line.h"

namespace dynapath::cli {
namespace {

namespace fs = std::filesystem;

// Options as a command line gives them, parsed by CLI11 ("option --NAME").
study::GivenStudyOptions Cli(std::initializer_list<std::pair<std::string, std::string>> given) {
  Result<study::GivenStudyOptions> parsed = study::test_support::ParseStudyCommandLine(given);
  EXPECT_TRUE(parsed) << parsed.error().message;
  return parsed ? *parsed : study::GivenStudyOptions{};
}

fs::path TempPath(const std::string& name) {
  const fs::path path =
      fs::temp_directory_path() / ("dynapath-study-" + name + "-" + std::to_string(getpid()));
  fs::remove_all(path);
  return path;
}

TEST(PlanStudy, TakesTheOptionsAndMakesThePlan) {
  StudyInput input;
  input.command_line = Cli({{"sizes", "20"},
                            {"difficulties", "easy,hard"},
                            {"edge-case", "false"},
                            {"out", "somewhere"}});
  input.force = true;
  input.hardware_threads = 2;
  Result<StudyPlan> plan = PlanStudy(input);
  ASSERT_TRUE(plan) << plan.error().message;
  ASSERT_EQ(plan->configurations.size(), 2u);
  EXPECT_EQ(plan->configurations[0].Name(), "20_easy_50");
  EXPECT_EQ(plan->out(), fs::path("somewhere"));
  EXPECT_TRUE(plan->force);
  EXPECT_EQ(plan->options.threads, 2);
}

TEST(PlanStudy, AnErrorNamesItsOption) {
  const std::pair<study::GivenStudyOptions, std::string> cases[] = {
      {Cli({{"sizes", "twenty"}}), "option --sizes: "},
      {Cli({{"difficulties", "medium-rare"}}), "option --difficulties: "},
      {Cli({{"repeats", "0"}}), "option --repeats: "},
      {Cli({{"parallel", "0"}}), "option --parallel: "},
      {Cli({{"stations", "3"}}), "option --stations: "},
  };
  for (const auto& [values, expected] : cases) {
    StudyInput input;
    input.command_line = values;
    Result<StudyPlan> plan = PlanStudy(input);
    ASSERT_FALSE(plan) << expected;
    EXPECT_EQ(plan.error().message.rfind(expected, 0), 0u) << plan.error().message;
  }
}

TEST(PlanStudy, TheCommandLineOverridesTheConfigFile) {
  const fs::path dir = TempPath("config");
  fs::create_directories(dir);
  const fs::path file = dir / "study.toml";
  std::ofstream(file) << "sizes = [20, 30]\ndifficulties = [\"easy\"]\nedge_case = false\n";
  StudyInput input;
  input.config_path = file.string();
  Result<StudyPlan> plan = PlanStudy(input);
  ASSERT_TRUE(plan) << plan.error().message;
  EXPECT_EQ(plan->configurations.size(), 2u);
  input.command_line = Cli({{"sizes", "20"}});
  plan = PlanStudy(input);
  ASSERT_TRUE(plan) << plan.error().message;
  EXPECT_EQ(plan->configurations.size(), 1u);
  // An error in the file names its line.
  std::ofstream(file) << "sizes = [20]\nbogus = 1\n";
  plan = PlanStudy(input);
  ASSERT_FALSE(plan);
  EXPECT_NE(plan.error().message.find(file.string() + ":2"), std::string::npos)
      << plan.error().message;
  fs::remove_all(dir);
}

TEST(StudySession, AnOutThatIsAFileIsAnErrorOfTheOptions) {
  const fs::path out = TempPath("file");
  std::ofstream(out) << "not a directory\n";
  StudyInput input;
  input.command_line = Cli({{"sizes", "20"}, {"edge-case", "false"}, {"out", out.string()}});
  Result<StudyPlan> plan = PlanStudy(input);
  ASSERT_TRUE(plan) << plan.error().message;
  StudySession session(std::move(*plan));
  const Status prepared = session.Prepare();
  ASSERT_FALSE(prepared);
  EXPECT_TRUE(prepared.error().IsInvalidArgument());
  EXPECT_EQ(prepared.error().message, out.string() + " exists and is not a directory");
  fs::remove(out);
}

}  // namespace
}  // namespace dynapath::cli
