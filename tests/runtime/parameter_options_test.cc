// The learner and strategy parameters as options (runtime/parameter_options.h):
// every one is accepted by name from the command line and a config file,
// range-checked with an error naming it, carried to the coordinator's config,
// preset by --semantics report under the ones given, and params.toml reads
// back as the same values.

#include "runtime/parameter_options.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <string>

#include "runtime/run_driver.h"

namespace dynapath::runtime {
namespace {

// Parses `args` into run options with `dynapath run`'s declaration; -1 on
// success, as ParseCommandLine.
int Parse(std::vector<std::string> args, RunOptions& options) {
  CLI::App app;
  OptionGroup group(app);
  DeclareRunOptions(group, options);
  AddConfigOption(app);
  return ParseCommandLine(app, std::move(args), "test");
}

class TempFile {
 public:
  TempFile() {
    char name[] = "/tmp/parameter_options_test_XXXXXX";
    const int fd = mkstemp(name);
    EXPECT_GE(fd, 0);
    close(fd);
    path_ = name;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }
  void Write(const std::string& text) const { std::ofstream(path_) << text; }

 private:
  std::string path_;
};

// An in-range value other than the default.
double OtherValue(const Parameter& p) { return p.default_value == p.max ? p.min : p.max; }

TEST(ParameterOptionsTest, EveryParameterIsAnOptionReachingThePlannerOptions) {
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    const Parameter& p = parameters[i];
    SCOPED_TRACE(p.name);
    RunOptions options;
    ASSERT_EQ(Parse({"--" + p.name, ParameterText(p, OtherValue(p))}, options), -1);
    Result<RunPlan> plan = ResolveRunOptions(options);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    for (size_t j = 0; j < parameters.size(); ++j) {
      EXPECT_EQ(ParameterValue(plan->options, j),
                j == i ? OtherValue(p) : parameters[j].default_value);
    }
  }
}

TEST(ParameterOptionsTest, OutOfRangeIsOneErrorNamingTheOption) {
  for (const Parameter& p : Parameters()) {
    SCOPED_TRACE(p.name);
    for (const double bad : {p.min - 1, p.max * 2 + 1}) {
      RunOptions options;
      ASSERT_EQ(Parse({"--" + p.name, ParameterText(p, bad)}, options), -1);
      Result<RunPlan> plan = ResolveRunOptions(options);
      ASSERT_FALSE(plan.ok());
      EXPECT_EQ(plan.error().subject, p.name);
      EXPECT_EQ(plan.error().code, Error::Code::kInvalidArgument);
      EXPECT_EQ(plan.error().message.rfind("option --" + p.name + " must be ", 0), 0u)
          << plan.error().message;
    }
  }
}

TEST(ParameterOptionsTest, CommandLineAndConfigFileAreTheSame) {
  TempFile config;
  config.Write("epsilon-start = 0.3\nlearners = 5\n");
  RunOptions from_file, from_line;
  ASSERT_EQ(Parse({"--config", config.path()}, from_file), -1);
  ASSERT_EQ(Parse({"--epsilon-start", "0.3", "--learners", "5"}, from_line), -1);
  Result<RunPlan> a = ResolveRunOptions(from_file);
  Result<RunPlan> b = ResolveRunOptions(from_line);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->options.single_agent.epsilon_start, 0.3);
  EXPECT_EQ(a->options.federated.learners, 5);
  EXPECT_EQ(ParametersToml(a->options), ParametersToml(b->options));
}

TEST(ParameterOptionsTest, ReportPresetUnderTheParametersGiven) {
  RunOptions options;
  ASSERT_EQ(Parse({"--semantics", "report", "--epsilon-start", "0.05"}, options), -1);
  Result<RunPlan> plan = ResolveRunOptions(options);
  ASSERT_TRUE(plan.ok()) << plan.error().message;
  EXPECT_EQ(plan->options.semantics, Semantics::kReport);
  for (size_t i = 0; i < Parameters().size(); ++i) {
    const Parameter& p = Parameters()[i];
    EXPECT_EQ(ParameterValue(plan->options, i), p.name == "epsilon-start" ? 0.05 : p.report_value)
        << p.name;
  }
}

// The launcher hands the coordinator its run options as a config file
// written by the same declaration: the parameters given travel, exactly.
TEST(ParameterOptionsTest, ChildConfigCarriesTheParametersGiven) {
  RunOptions given;
  ASSERT_EQ(Parse({"--epsilon-decay", "0.1", "--replay-batch", "3", "--max-drop", "0.07"}, given),
            -1);
  ConfigWriter writer;
  OptionGroup out(writer);
  DeclareRunOptions(out, given);
  ASSERT_TRUE(writer.status());
  TempFile config;
  config.Write(writer.Text());
  RunOptions read;
  ASSERT_EQ(Parse({"--config", config.path()}, read), -1);
  Result<RunPlan> a = ResolveRunOptions(given);
  Result<RunPlan> b = ResolveRunOptions(read);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(b->options.single_agent.epsilon_decay, 0.1);
  EXPECT_EQ(b->options.single_agent.replay_batch, 3);
  EXPECT_EQ(b->options.thresholds.max_drop, 0.07);
  EXPECT_EQ(ParametersToml(a->options), ParametersToml(b->options));
}

// The run plan of `args` (a command line or `--config FILE`), or an error.
Result<RunPlan> PlanOf(std::vector<std::string> args) {
  RunOptions options;
  if (Parse(std::move(args), options) != -1) return Error{"bad command line"};
  return ResolveRunOptions(options);
}

// The run plan `toml` gives as a --config file.
Result<RunPlan> PlanOfConfig(const std::string& toml) {
  TempFile config;
  config.Write(toml);
  return PlanOf({"--config", config.path()});
}

// params.toml holds every parameter and reads back as the same values.
TEST(ParameterOptionsTest, ParamsTomlReadsBack) {
  Result<RunPlan> plan = PlanOf({"--convergence-threshold", "0.000123", "--sync-period", "77",
                                 "--escalate-below", "0.5", "--epsilon-min", "0.1"});
  ASSERT_TRUE(plan.ok());
  const std::string toml = ParametersToml(plan->options);
  for (const Parameter& p : Parameters()) {
    EXPECT_NE(toml.find("\n" + p.name + " = "), std::string::npos) << p.name;
  }
  Result<RunPlan> again = PlanOfConfig(toml);
  ASSERT_TRUE(again.ok());
  for (size_t i = 0; i < Parameters().size(); ++i) {
    EXPECT_EQ(ParameterValue(again->options, i), ParameterValue(plan->options, i))
        << Parameters()[i].name;
  }
  EXPECT_EQ(again->options.single_agent.epsilon_min, 0.1);
}

// A run's params.toml holds what determines its results besides the maze:
// with report semantics and a leaf limit, it reads back as the same plan
// (not ours with the default leaf limit).
TEST(ParameterOptionsTest, RunPlanTomlHoldsTheLearnerOptions) {
  Result<RunPlan> plan = PlanOf({"--semantics", "report", "--leaf-limit", "10", "--approach",
                                 "singleAgent,BFS Oracle", "--learner-seed", "77"});
  ASSERT_TRUE(plan.ok());
  const std::string toml = RunPlanToml(*plan);
  EXPECT_NE(toml.find("\nsemantics = \"report\"\n"), std::string::npos) << toml;
  EXPECT_NE(toml.find("\nleaf-limit = 10\n"), std::string::npos) << toml;
  EXPECT_EQ(toml.find("bootstrap"), std::string::npos) << toml;  // report's own
  Result<RunPlan> again = PlanOfConfig(toml);
  ASSERT_TRUE(again.ok()) << again.error().message;
  EXPECT_EQ(again->options.semantics, Semantics::kReport);
  EXPECT_EQ(again->options.leaf_limit, 10);
  EXPECT_EQ(again->options.bootstrap, plan->options.bootstrap);
  EXPECT_EQ(again->approaches, plan->approaches);
  EXPECT_EQ(again->learner_seed, 77u);
  EXPECT_EQ(RunPlanToml(*again), toml);

  // Ours: the bootstrap is written too.
  Result<RunPlan> in_region = PlanOf({"--bootstrap", "in-region"});
  ASSERT_TRUE(in_region.ok());
  EXPECT_NE(RunPlanToml(*in_region).find("\nbootstrap = \"in-region\"\n"), std::string::npos);
}

}  // namespace
}  // namespace dynapath::runtime
