// The parameter table: its lines, their checks, the report preset, and for
// every parameter that a value other than its default, set by name, reaches
// the learner or the retraining strategy and changes what it does.
#include "dynapath/parameters.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "core/learn/region_model.h"
#include "core/plan/retraining_strategy.h"
#include "dynapath/learners.h"
#include "tests/learner_test_support.h"

namespace dynapath {
namespace {

size_t IndexOf(const std::string& name) {
  const std::vector<Parameter>& parameters = Parameters();
  for (size_t i = 0; i < parameters.size(); ++i) {
    if (parameters[i].name == name) return i;
  }
  ADD_FAILURE() << "no parameter " << name;
  return 0;
}

TEST(Parameters, EveryLineHasAUniqueDashedNameAndItsValuesInRange) {
  std::set<std::string> names;
  PlannerOptions defaults;
  const std::vector<Parameter>& parameters = Parameters();
  ASSERT_EQ(parameters.size(), 17u);
  for (size_t i = 0; i < parameters.size(); ++i) {
    const Parameter& p = parameters[i];
    EXPECT_TRUE(names.insert(p.name).second) << p.name;
    EXPECT_EQ(p.name.find('_'), std::string::npos) << p.name;
    EXPECT_FALSE(p.help.empty()) << p.name;
    EXPECT_LE(p.min, p.default_value) << p.name;
    EXPECT_GE(p.max, p.default_value) << p.name;
    EXPECT_LE(p.min, p.report_value) << p.name;
    EXPECT_GE(p.max, p.report_value) << p.name;
    // The table's default is the options struct's.
    EXPECT_EQ(ParameterValue(defaults, i), p.default_value) << p.name;
  }
  EXPECT_EQ(parameters.front().name, "max-episodes");
  EXPECT_EQ(parameters.back().name, "escalate-below");
}

TEST(Parameters, SetByNameReachesItsMember) {
  PlannerOptions options;
  ASSERT_TRUE(SetParameter(options, IndexOf("epsilon-start"), 0.3).ok());
  ASSERT_TRUE(SetParameter(options, IndexOf("learners"), 5).ok());
  ASSERT_TRUE(SetParameter(options, IndexOf("max-drop"), 0.05).ok());
  EXPECT_EQ(options.single_agent.epsilon_start, 0.3);
  EXPECT_EQ(options.federated.learners, 5);
  EXPECT_EQ(options.thresholds.max_drop, 0.05);
  EXPECT_EQ(ParameterValue(options, IndexOf("learners")), 5.0);
}

TEST(Parameters, OutOfRangeIsAnOptionErrorNamingIt) {
  PlannerOptions options;
  Status status = SetParameter(options, IndexOf("epsilon-start"), 1.5);
  ASSERT_FALSE(status.ok());
  EXPECT_TRUE(status.error().IsInvalidArgument());
  EXPECT_EQ(status.error().message,
            "option --epsilon-start must be a number from 0.0 to 1.0, got 1.5");
  status = SetParameter(options, IndexOf("learners"), 0);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message, "option --learners must be an integer from 1 to 4096, got 0");
  EXPECT_FALSE(SetParameter(options, IndexOf("learners"), 2.5).ok());
  EXPECT_FALSE(SetParameter(options, IndexOf("max-drop"), std::nan("")).ok());
  EXPECT_EQ(options.single_agent.epsilon_start, 1.0);  // unchanged
  EXPECT_EQ(options.federated.learners, 12);
}

TEST(Parameters, ReportPresetSetsTheReportValues) {
  PlannerOptions options;
  for (size_t i = 0; i < Parameters().size(); ++i) {
    const Parameter& p = Parameters()[i];
    // Any in-range value other than the report's, to see the preset set it.
    ASSERT_TRUE(SetParameter(options, i, p.report_value == p.min ? p.max : p.min).ok());
  }
  ApplyReportPreset(options);
  for (size_t i = 0; i < Parameters().size(); ++i) {
    EXPECT_EQ(ParameterValue(options, i), Parameters()[i].report_value) << Parameters()[i].name;
  }
  // The report's code uses our numbers for every parameter (SPEC 5-7) but
  // the episode numbers of its single-agent learner (SPEC 11.5).
  EXPECT_EQ(ReportPresetText(), "replay-start-episode 501 convergence-start-episode 501");
}

TEST(Parameters, ApproachesReadingEachGroup) {
  EXPECT_EQ(ApproachesReading(ParameterGroup::kSingleAgent),
            (std::vector<Approach>{Approach::kOnlyTrainLeafNodes, Approach::kSingleAgent}));
  EXPECT_EQ(ApproachesReading(ParameterGroup::kFederated),
            (std::vector<Approach>{Approach::kFedAsynQEqAvg, Approach::kFedAsynQImAvg}));
  EXPECT_EQ(ApproachesReading(ParameterGroup::kStrategy),
            (std::vector<Approach>{Approach::kSingleAgent, Approach::kFedAsynQEqAvg,
                                   Approach::kFedAsynQImAvg}));
}

TEST(Parameters, TextReadsBackAsTomlNumbers) {
  const Parameter& threshold = Parameters()[IndexOf("convergence-threshold")];
  const Parameter& episodes = Parameters()[IndexOf("max-episodes")];
  EXPECT_EQ(ParameterText(threshold, 5e-4), "5e-04");
  EXPECT_EQ(ParameterText(threshold, 1.0), "1.0");
  EXPECT_EQ(ParameterText(threshold, 0.3), "0.3");
  EXPECT_EQ(ParameterText(episodes, 10000), "10000");
}

// A value other than the default for every parameter, one that changes the
// result of the approaches reading it on the hand-made 10x10 map (learners)
// or in a scripted adaptation (strategy). A parameter added to a list fails
// here until it has one.
const std::map<std::string, double>& ChangedValues() {
  static const std::map<std::string, double> values = {
      {"max-episodes", 100},
      {"epsilon-start", 0.3},
      {"epsilon-decay", 0.9},
      {"epsilon-min", 0.5},
      {"replay-capacity", 10},
      {"replay-start-episode", 0},
      {"replay-batch", 0},
      {"convergence-start-episode", 1025},
      {"convergence-interval", 10},
      {"convergence-threshold", 1.0},
      {"convergence-checks", 2},
      {"learners", 3},
      {"sync-period", 100},
      {"iterations-per-cell", 10},
      {"max-drop", 0.1},
      {"min-success-rate", 0.999},
      {"escalate-below", 0.99},
  };
  return values;
}

// The whole 10x10 map as one job of `kind`, with the learner options of
// `options` (as the planner hands them to every job).
TrainingResult Train(const PlannerOptions& options, LearnerKind kind) {
  const Grid grid = test_maps::MapFromText(test_maps::kMap10);
  TrainingJob job;
  static_cast<LearnerOptions&>(job) = options;
  job.node = 0;
  job.region = Region{0, grid.rows() - 1, 0, grid.cols() - 1};
  job.codes = RegionCodes(grid, job.region);
  job.warm_start = QTable(job.region.cells());
  job.seed = 7;
  job.kind = kind;
  return TrainJob(job);
}

bool SameTraining(const TrainingResult& a, const TrainingResult& b) {
  return a.episodes_or_rounds == b.episodes_or_rounds && a.steps == b.steps &&
         test_maps::BytesEqual(a.table, b.table);
}

// Success rates scripted per node (1 when not scripted); records trainings.
class ScriptedRates : public TrainingContext {
 public:
  std::map<NodeId, double> rate;
  std::vector<NodeId> trained;
  double SuccessRate(NodeId node) override {
    const auto it = rate.find(node);
    return it == rate.end() ? 1.0 : it->second;
  }
  void Train(const std::vector<NodeId>& nodes) override {
    trained.insert(trained.end(), nodes.begin(), nodes.end());
  }
};

// The nodes the tree strategy of `options` trains in a scripted adaptation
// that each threshold decides: leaf 5 of a 16x16 tree (leaf limit 4) at
// 0.95 from the start (escalate-below), then changed leaves 6 (down from 1
// to 0.95: max-drop) and 7 (down to 0.995: min-success-rate).
std::vector<NodeId> StrategyTrainings(const PlannerOptions& options) {
  const QuadTree tree(16, 16, 4);
  std::unique_ptr<RetrainingStrategy> strategy = MakeTreeStrategy(tree, options.thresholds);
  ScriptedRates context;
  context.rate[5] = 0.95;
  strategy->Adapt({}, context);
  context.rate[6] = 0.95;
  context.rate[7] = 0.995;
  strategy->Adapt({6, 7}, context);
  return context.trained;
}

TEST(Parameters, EveryParameterChangesTheResultOfTheApproachesReadingIt) {
  const PlannerOptions defaults;
  for (size_t i = 0; i < Parameters().size(); ++i) {
    const Parameter& p = Parameters()[i];
    SCOPED_TRACE(p.name);
    const auto changed = ChangedValues().find(p.name);
    ASSERT_NE(changed, ChangedValues().end()) << "no changed value for " << p.name;
    PlannerOptions options;
    ASSERT_TRUE(SetParameter(options, i, changed->second).ok());
    switch (p.group) {
      case ParameterGroup::kSingleAgent:
        EXPECT_FALSE(SameTraining(Train(defaults, LearnerKind::kSingleAgent),
                                  Train(options, LearnerKind::kSingleAgent)));
        // The federated learner does not read it.
        EXPECT_TRUE(SameTraining(Train(defaults, LearnerKind::kFedAsynQ),
                                 Train(options, LearnerKind::kFedAsynQ)));
        break;
      case ParameterGroup::kFederated:
        EXPECT_FALSE(SameTraining(Train(defaults, LearnerKind::kFedAsynQ),
                                  Train(options, LearnerKind::kFedAsynQ)));
        EXPECT_TRUE(SameTraining(Train(defaults, LearnerKind::kSingleAgent),
                                 Train(options, LearnerKind::kSingleAgent)));
        break;
      case ParameterGroup::kStrategy:
        EXPECT_NE(StrategyTrainings(defaults), StrategyTrainings(options));
        break;
    }
  }
}

// Each threshold decides the scripted adaptation as SPEC 5 says.
TEST(Parameters, ThresholdsDecideTheScriptedAdaptation) {
  const QuadTree tree(16, 16, 4);
  std::vector<NodeId> initial = tree.leaves();
  // Defaults: leaf 5 (0.95) is not escalated, 6 (drop 0.05) is retrained,
  // 7 (0.995, drop 0.005) is not.
  std::vector<NodeId> expected = initial;
  expected.push_back(6);
  EXPECT_EQ(StrategyTrainings(PlannerOptions{}), expected);
}

}  // namespace
}  // namespace dynapath
