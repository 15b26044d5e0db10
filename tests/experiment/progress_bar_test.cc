#include "tools/common/progress_bar.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

namespace dynapath::cli {
namespace {

// What a display wrote to `out` (a tmpfile), which is then closed.
std::string ReadAndClose(std::FILE* out) {
  std::rewind(out);
  std::string text;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, out) != nullptr) text += buffer;
  std::fclose(out);
  return text;
}

TEST(ProgressBarTest, FormatsDurations) {
  EXPECT_EQ(FormatDuration(0.04), "0.0 s");
  EXPECT_EQ(FormatDuration(4.25), "4.2 s");
  EXPECT_EQ(FormatDuration(42), "42 s");
  EXPECT_EQ(FormatDuration(723), "12:03");
  EXPECT_EQ(FormatDuration(3723), "1:02:03");
  EXPECT_EQ(FormatDuration(-5), "0.0 s");
}

TEST(ProgressBarTest, EstimatesFromFinishedConfigurationsScaledByWork) {
  TimeEstimator estimator;
  EXPECT_FALSE(estimator.Remaining(100, 0.5, 0.0, 1000).has_value());  // nothing to go on
  // Before any finished: the fraction of the current one.
  EXPECT_NEAR(*estimator.Remaining(100, 10, 0.5, 200), 10 + 40, 1e-9);
  estimator.AddFinished(100, 10);  // 0.1 s per unit of work
  EXPECT_NEAR(*estimator.Remaining(200, 5, 0.0, 300), 15 + 30, 1e-9);
  // Past its estimate: the fraction of the current one, else nothing for it.
  EXPECT_NEAR(*estimator.Remaining(100, 20, 0.8, 0), 5, 1e-9);
  EXPECT_NEAR(*estimator.Remaining(100, 20, 0.0, 100), 10, 1e-9);
}

TEST(ProgressBarTest, LinesShowWhereTheStudyIs) {
  ProgressSnapshot s;
  s.index = 3;
  s.count = 13;
  s.label = "50 Hard, seed 52";
  s.approach = "fedAsynQ_EqAvg";
  s.approach_index = 6;
  s.approach_count = 7;
  s.step = 45;
  s.total_steps = 100;
  s.elapsed = 723;
  s.done_fraction = 0.25;
  s.remaining = 2400;
  EXPECT_EQ(BarLine(s, 200),
            "[###.........]  25% 3/13 50 Hard, seed 52 | fedAsynQ_EqAvg 6/7 step 45/100 | 12:03 "
            "elapsed, ~40:00 left");
  s.short_label = "50 Hard s52";
  EXPECT_EQ(BarLine(s, 81),
            "[###.........]  25% 3/13 50 Hard s52 fedAsynQ_EqAvg 6/7 t45/100 12:03 ~40:00 left");
  EXPECT_EQ(BarLine(s, 80), "3/13 50 Hard s52 fedAsynQ_EqAvg 6/7 t45/100 12:03 ~40:00 left");
  EXPECT_EQ(BarLine(s, 40).size(), 40u);
  EXPECT_EQ(PlainLine(s),
            "[12:03] configuration 3/13 50 Hard, seed 52 | fedAsynQ_EqAvg 6/7 step 45/100; ~40:00 "
            "left");
  s.approach_index = 0;
  s.remaining.reset();
  EXPECT_EQ(PlainLine(s),
            "[12:03] configuration 3/13 50 Hard, seed 52 | starting; time left unknown");
  s.training = "training 3/12 jobs";
  EXPECT_EQ(PlainLine(s),
            "[12:03] configuration 3/13 50 Hard, seed 52 | starting, training 3/12 jobs; time left "
            "unknown");
}

// A watched training batch shows on the line while it runs, as
// DescribeTraining says: jobs and the share of their episodes, or rounds
// when the batch runs in rounds.
TEST(ProgressBarTest, PlainLinesShowTheTrainingBatchInHand) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  TrainingProgress training;
  {
    ProgressDisplay display(out, false);
    display.Start({100}, {false});
    display.BeginConfiguration(0, "300 Hard, seed 52", "300 Hard s52");
    display.WatchTraining(0, &training);
    training.Start(12, 0, 1200, TrainingWork::kEpisodes);
    training.jobs_done = 3;
    training.work_done = 300;
    display.Step("singleAgent", 0, 2, 0, 10);  // a new approach: a line
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    training.Start(4, 225);
    training.rounds_done = 40;
    display.Step("fedAsynQ_EqAvg", 1, 2, 0, 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    training.Finish();
    display.WatchTraining(0, nullptr);
    display.EndConfiguration(0, 1.0, true);
    display.Stop();
  }
  const std::string text = ReadAndClose(out);
  EXPECT_NE(text.find("singleAgent 1/2 step 0/10, training 3/12 jobs, 25% of episodes;"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("fedAsynQ_EqAvg 2/2 step 0/10, training round 40/225 of 4 jobs;"),
            std::string::npos)
      << text;
}

TEST(ProgressBarTest, PlainDisplayPrintsLinesPerApproach) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  {
    ProgressDisplay display(out, false);
    display.Start({100, 100}, {true, false});
    display.BeginConfiguration(1, "20 Easy, seed 50", "20 Easy s50");
    display.Step("A* Static", 0, 2, 0, 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    display.Step("BFS Oracle", 1, 2, 3, 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(700));
    display.Print("a message");
    display.EndConfiguration(1, 1.5, true);
    display.Stop();
  }
  const std::string text = ReadAndClose(out);
  EXPECT_NE(text.find("configuration 2/2 20 Easy, seed 50 | A* Static 1/2 step 0/10"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("configuration 2/2 20 Easy, seed 50 | BFS Oracle 2/2 step 3/10"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("a message\n"), std::string::npos) << text;
  EXPECT_EQ(text.find('\r'), std::string::npos) << "no bar when not on a terminal";
}

}  // namespace
}  // namespace dynapath::cli
