#include "app/service_session.h"

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <thread>

#include "dynapath/convq_model.h"

namespace dynapath::app {
namespace {

constexpr const char* kShippedModel = DYNAPATH_SOURCE_DIR "/docs/examples/models/convq.model";

// A small service: hard 12x12 maze, in process, on memq:// (no network).
ServiceOptions SmallService() {
  ServiceOptions options;
  options.scenario.size = 12;
  options.scenario.difficulty = "hard";
  options.scenario.steps = 3;
  options.process.run_id = "app-test";
  options.process.insecure = true;
  options.process.lcm_url = "memq://";
  options.threads.threads = 1;
  return options;
}

TEST(PlanService, TakesTheOptionsAsTyped) {
  ServiceOptions options = SmallService();
  options.answer = "exact";
  options.max_starts = 10;
  Result<ServicePlan> plan = PlanService(options);
  ASSERT_TRUE(plan) << plan.error().message;
  EXPECT_EQ(plan->config.approach, Approach::kFedAsynQEqAvg);
  EXPECT_EQ(plan->config.answer, AnswerMode::kExact);
  EXPECT_EQ(plan->config.max_starts, 10);
  EXPECT_EQ(plan->config.options.run_seed, plan->setup.seed);
  EXPECT_EQ(plan->setup.scenario.grid.rows(), 12);
  EXPECT_EQ(plan->mode.kind, runtime::RunMode::kLocal);
  EXPECT_FALSE(plan->write_results);
}

// convQ is served with its model (--model's, else the built-in one).
TEST(PlanService, ServesConvQWithItsModel) {
  ServiceOptions options = SmallService();
  options.run.approach = "convQ";
  options.run.model = kShippedModel;
  Result<ServicePlan> plan = PlanService(options);
  ASSERT_TRUE(plan) << plan.error().message;
  EXPECT_EQ(plan->config.approach, Approach::kConvQ);
  ASSERT_NE(plan->config.options.convq_model, nullptr);
  EXPECT_EQ(*plan->config.options.convq_model, ShippedConvQModel());
}

// Each bad option: one error, kInvalidArgument, naming the option.
TEST(PlanService, NamesTheOptionOfEachError) {
  struct Case {
    const char* option;
    void (*spoil)(ServiceOptions&);
  };
  const Case cases[] = {
      {"approach", [](ServiceOptions& o) { o.run.approach = "all"; }},
      {"placement", [](ServiceOptions& o) { o.placement_given = true; }},
      {"answer", [](ServiceOptions& o) { o.answer = "guess"; }},
      {"max-starts", [](ServiceOptions& o) { o.max_starts = 0; }},
      {"free-thresh", [](ServiceOptions& o) { o.free_thresh = 0.9; }},
      {"policy-every", [](ServiceOptions& o) { o.policy_every = -1; }},
      {"policy-gap", [](ServiceOptions& o) { o.policy_gap = 4000; }},
      {"save-policy", [](ServiceOptions& o) { o.save_at_given = true; }},
      // convQ trains nothing: no agents for it; --model is convQ's only.
      {"agents",
       [](ServiceOptions& o) {
         o.run.approach = "convQ";
         o.mode.agents = 2;
       }},
      {"agents",
       [](ServiceOptions& o) {
         o.run.approach = "convQ";
         o.mode.embedded = true;
       }},
      {"model", [](ServiceOptions& o) { o.run.model = kShippedModel; }},
  };
  for (const Case& c : cases) {
    ServiceOptions options = SmallService();
    c.spoil(options);
    Result<ServicePlan> plan = PlanService(options);
    ASSERT_FALSE(plan) << c.option;
    EXPECT_TRUE(plan.error().IsInvalidArgument()) << c.option;
    EXPECT_EQ(plan.error().subject, c.option) << plan.error().message;
  }
}

// In process: the session trains, commits a policy that answers, and on
// stop writes the run's result files.
TEST(ServiceSession, ServesInProcessAndWritesResults) {
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("dynapath-app-test-" + std::to_string(getpid()));
  std::filesystem::remove_all(out);
  ServiceOptions options = SmallService();
  options.run.out = out.string();
  options.out_given = true;
  Result<ServicePlan> plan = PlanService(options);
  ASSERT_TRUE(plan) << plan.error().message;
  ServiceSession session(std::move(*plan));
  ASSERT_TRUE(session.Open());
  EXPECT_FALSE(session.may_have_company());  // memq://
  std::atomic<bool> stop{false};
  std::thread stopper([&] {
    // The first policy, then one query answered from it.
    runtime::PathService* service = session.service();
    ASSERT_NE(service, nullptr);
    EXPECT_TRUE(service->WaitForVersion(1, 60));
    const runtime::Answer answer = service->Ask({{0, 0}});
    EXPECT_EQ(answer.refused, runtime::Answer::kAccepted);
    EXPECT_EQ(answer.routes.size(), 1u);
    stop = true;
  });
  const Status served = session.Serve(stop);
  stopper.join();
  ASSERT_TRUE(served) << served.error().message;
  EXPECT_NE(session.Summary().find("served: 1 queries"), std::string::npos) << session.Summary();
  ASSERT_TRUE(session.Finish());
  EXPECT_TRUE(std::filesystem::exists(out / "results.csv"));
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace dynapath::app
