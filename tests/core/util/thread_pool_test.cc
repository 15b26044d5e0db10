#include "dynapath/thread_pool.h"

#include <gtest/gtest.h>

#include <atomic>

namespace dynapath {
namespace {

TEST(ThreadPoolTest, RunsEveryItemExactlyOnce) {
  for (int threads : {1, 2, 4}) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    for (int round = 0; round < 50; ++round) {
      std::vector<std::atomic<int>> hits(257);
      pool.ParallelFor(257, [&](int i) { hits[i].fetch_add(1); });
      for (auto& hit : hits) ASSERT_EQ(hit.load(), 1);
    }
  }
}

TEST(ThreadPoolTest, EmptyAndSingleLoops) {
  ThreadPool pool(3);
  int calls = 0;
  pool.ParallelFor(0, [&](int) { ++calls; });
  EXPECT_EQ(calls, 0);
  pool.ParallelFor(1, [&](int i) { calls += i + 1; });
  EXPECT_EQ(calls, 1);
}

TEST(ThreadPoolTest, UsesTheWorkers) {
  ThreadPool pool(2);
  std::atomic<int> concurrent{0}, peak{0};
  pool.ParallelFor(64, [&](int) {
    const int now = ++concurrent;
    int seen = peak.load();
    while (now > seen && !peak.compare_exchange_weak(seen, now)) {
    }
    volatile double sink = 0;
    for (int k = 0; k < 200000; ++k) sink = sink + k;
    --concurrent;
  });
  EXPECT_GE(peak.load(), 1);
  EXPECT_LE(peak.load(), 2);
}

}  // namespace
}  // namespace dynapath
