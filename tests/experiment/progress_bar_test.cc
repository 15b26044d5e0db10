#include "tools/common/progress_bar.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
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

// Waits until the display's thread has written `needle` to `out` (a
// tmpfile; the display flushes each line), at most a minute for a loaded
// machine: the test waits for the line, not for a time it hopes enough.
bool WaitForText(std::FILE* out, const std::string& needle) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  do {
    std::string text;
    char buffer[512];
    ssize_t read = 0;
    while ((read = pread(fileno(out), buffer, sizeof buffer, static_cast<off_t>(text.size()))) >
           0) {
      text.append(buffer, static_cast<size_t>(read));
    }
    if (text.find(needle) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  } while (std::chrono::steady_clock::now() < give_up);
  return false;
}

TEST(ProgressBarTest, FormatsDurations) {
  EXPECT_EQ(FormatDuration(0.04), "0.0 s");
  EXPECT_EQ(FormatDuration(4.25), "4.2 s");
  EXPECT_EQ(FormatDuration(42), "42 s");
  EXPECT_EQ(FormatDuration(723), "12:03");
  EXPECT_EQ(FormatDuration(3723), "1:02:03");
  EXPECT_EQ(FormatDuration(-5), "0.0 s");
}

// A configuration `fraction` done by approaches and steps, in approach
// `approach` (0-based) of `count`, `approach_elapsed` s into it.
ConfigurationProgress At(double work, double elapsed, int approach, int count,
                         double approach_elapsed, double approach_fraction) {
  ConfigurationProgress c;
  c.work = work;
  c.elapsed = elapsed;
  c.approach = approach;
  c.approach_count = count;
  c.approach_elapsed = approach_elapsed;
  c.approach_fraction = approach_fraction;
  c.fraction = approach < 0 ? 0.0 : (approach + approach_fraction) / count;
  return c;
}

TEST(ProgressBarTest, EstimatesFromEarlierSessionsScaledByWork) {
  TimeEstimator estimator;
  EXPECT_FALSE(estimator.Remaining(At(100, 0.5, -1, 0, 0, 0), 1000).has_value());
  estimator.AddFinished(100, 10);  // 0.1 s per unit of work
  const std::optional<TimeLeft> left = estimator.Remaining(At(200, 5, 0, 2, 5, 0.1), 300);
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(left->seconds, 15 + 30, 1e-9);
  EXPECT_FALSE(left->at_least);
}

// Each approach costs what it cost before (per unit of work), so the
// estimate counts the approaches still to come at their own cost: a fast
// first approach does not make the slow ones look fast.
TEST(ProgressBarTest, EstimatesEachApproachAtItsOwnCost) {
  TimeEstimator estimator;
  // A first configuration (work 100): approaches of 1 s, 60 s and 4 s.
  estimator.AddApproachFinished(0, 100, 1);
  // Only the first has run: the rest is unknown, the estimate a lower bound.
  std::optional<TimeLeft> left = estimator.Remaining(At(100, 20, 1, 3, 19, 0.0), 0);
  EXPECT_FALSE(left.has_value()) << "nothing known of the approach in hand";
  left = estimator.Remaining(At(100, 20, 1, 3, 19, 0.0), 100);
  ASSERT_TRUE(left.has_value());
  EXPECT_TRUE(left->at_least);
  EXPECT_NEAR(left->seconds, 1, 1e-9);  // the next configuration's first approach
  estimator.AddApproachFinished(1, 100, 60);
  estimator.AddApproachFinished(2, 100, 4);
  // The second configuration, as long again: at every point of it the
  // estimate is the truth (65 s in all, then 65 s for the third).
  const double costs[] = {1, 60, 4};
  double elapsed = 0;
  for (int approach = 0; approach < 3; ++approach) {
    for (int step = 0; step <= 10; ++step) {
      const double in_approach = costs[approach] * step / 10;
      left = estimator.Remaining(
          At(100, elapsed + in_approach, approach, 3, in_approach, step / 10.0), 100);
      ASSERT_TRUE(left.has_value());
      EXPECT_FALSE(left->at_least);
      EXPECT_NEAR(left->seconds, 65 - elapsed - in_approach + 65, 1e-6)
          << "approach " << approach << " step " << step;
    }
    elapsed += costs[approach];
  }
  // Slower than before: past its cost, its own steps.
  left = estimator.Remaining(At(100, 80, 1, 3, 79, 0.5), 0);
  EXPECT_NEAR(left->seconds, 79 + 4, 1e-6);
}

// A larger configuration's rate stands for an approach (a superlinear
// A* Oracle), not the mean with the smaller ones.
TEST(ProgressBarTest, TheLargestConfigurationGivesTheRate) {
  TimeEstimator estimator;
  estimator.AddApproachFinished(0, 100, 1);
  estimator.AddApproachFinished(0, 1000, 30);
  estimator.AddApproachFinished(0, 100, 1);  // smaller: ignored
  estimator.AddApproachFinished(0, 1000, 50);
  const std::optional<TimeLeft> left = estimator.Remaining(At(2000, 0, -1, 0, 0, 0), 0);
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(left->seconds, 80, 1e-9);  // 40 s per 1000
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
  s.remaining_at_least = true;
  EXPECT_EQ(
      PlainLine(s),
      "[12:03] configuration 3/13 50 Hard, seed 52 | fedAsynQ_EqAvg 6/7 step 45/100; at least "
      "40:00 left");
  EXPECT_EQ(BarLine(s, 80), "3/13 50 Hard s52 fedAsynQ_EqAvg 6/7 t45/100 12:03 >40:00 left");
  s.remaining_at_least = false;
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
    EXPECT_TRUE(
        WaitForText(out, "singleAgent 1/2 step 0/10, training 3/12 jobs, 25% of episodes;"));
    training.Start(4, 225);
    training.rounds_done = 40;
    display.Step("fedAsynQ_EqAvg", 1, 2, 0, 10);
    EXPECT_TRUE(WaitForText(out, "fedAsynQ_EqAvg 2/2 step 0/10, training round 40/225 of 4 jobs;"));
    training.Finish();
    display.WatchTraining(0, nullptr);
    display.EndConfiguration(0, 1.0, true);
    display.Stop();
  }
  std::fclose(out);
}

TEST(ProgressBarTest, PlainDisplayPrintsLinesPerApproach) {
  std::FILE* out = std::tmpfile();
  ASSERT_NE(out, nullptr);
  {
    ProgressDisplay display(out, false);
    display.Start({100, 100}, {true, false});
    display.BeginConfiguration(1, "20 Easy, seed 50", "20 Easy s50");
    display.Step("A* Static", 0, 2, 0, 10);
    EXPECT_TRUE(WaitForText(out, "configuration 2/2 20 Easy, seed 50 | A* Static 1/2 step 0/10"));
    display.Step("BFS Oracle", 1, 2, 3, 10);
    EXPECT_TRUE(WaitForText(out, "configuration 2/2 20 Easy, seed 50 | BFS Oracle 2/2 step 3/10"));
    display.Print("a message");
    display.EndConfiguration(1, 1.5, true);
    display.Stop();
  }
  const std::string text = ReadAndClose(out);
  EXPECT_NE(text.find("a message\n"), std::string::npos) << text;
  EXPECT_EQ(text.find('\r'), std::string::npos) << "no bar when not on a terminal";
}

}  // namespace
}  // namespace dynapath::cli
