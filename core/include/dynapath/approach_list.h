#pragma once
// THE list of approaches: one line each, in the order of `--approach all`
// (SPEC section 9's seven, then ours). Everything else about an approach is
// derived from its line: the Approach enumerator, its result-file name, its
// planner, and for learning approaches the learner and the retraining
// strategy (core/plan/approach_registry.h). Adding an approach is one module
// defining its factory plus one line here (CONTRIBUTING.md, "Adding an
// approach").
//
// Columns: enumerator, result-file name, planner factory, learner (kNoLearner
// or a LearnerKind enumerator), averaging (federated learners), retraining
// strategy factory (nullptr without a learner). Factories have the
// signatures PlannerFactory and StrategyFactory of core/plan/approach_registry.h
// and are defined in the approach's own module.
//
// clang-format off
#define DYNAPATH_APPROACHES(X)                                                                                          \
  X(kAStarStatic,        "A* Static",          MakeAStarStaticPlanner,        kNoLearner,  kEqual,      nullptr)            \
  X(kAStarOracle,        "A* Oracle",          MakeAStarOraclePlanner,        kNoLearner,  kEqual,      nullptr)            \
  X(kBfsOracle,          "BFS Oracle",         MakeBfsOraclePlanner,          kNoLearner,  kEqual,      nullptr)            \
  X(kOnlyTrainLeafNodes, "onlyTrainLeafNodes", MakeLearningPlanner,           kSingleAgent, kEqual,     MakeLeavesOnlyStrategy) \
  X(kSingleAgent,        "singleAgent",        MakeLearningPlanner,           kSingleAgent, kEqual,     MakeTreeStrategy)   \
  X(kFedAsynQEqAvg,      "fedAsynQ_EqAvg",     MakeLearningPlanner,           kFedAsynQ,   kEqual,      MakeTreeStrategy)   \
  X(kFedAsynQImAvg,      "fedAsynQ_ImAvg",     MakeLearningPlanner,           kFedAsynQ,   kImportance, MakeTreeStrategy)   \
  X(kIncrementalOracle,  "Incremental Oracle", MakeIncrementalOraclePlanner,  kNoLearner,  kEqual,      nullptr)            \
  X(kConvQ,              "convQ",              MakeConvQPlanner,              kNoLearner,  kEqual,      nullptr)

// The approaches `all` leaves out (named explicitly only): those beyond the
// report's method whose rows would change what `all` runs have always
// written.
#define DYNAPATH_APPROACHES_OUTSIDE_ALL(X) X(kConvQ)
// clang-format on
