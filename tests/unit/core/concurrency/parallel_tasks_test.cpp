#include "concurrency/parallel_tasks.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace ldsm::concurrency {
namespace {

TEST(ParallelTasks, RunsEveryTaskExactlyOnce) {
  for (int threads : {1, 2, 3, 5}) {
    ParallelTasks pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    for (int count : {0, 1, 2, 7, 100}) {
      std::vector<std::atomic<int>> calls(static_cast<std::size_t>(count));
      for (auto& c : calls) c = 0;
      pool.run(count, [&](int i) { calls[static_cast<std::size_t>(i)].fetch_add(1); });
      for (int i = 0; i < count; ++i)
        EXPECT_EQ(calls[static_cast<std::size_t>(i)].load(), 1)
            << "task " << i << " of " << count << " with " << threads << " threads";
    }
  }
}

TEST(ParallelTasks, UsesTheHelperThreads) {
  ParallelTasks pool(3);
  std::mutex m;
  std::set<std::thread::id> ids;
  // Tasks that wait a little so that every thread gets some.
  for (int round = 0; round < 20 && ids.size() < 3; ++round) {
    pool.run(12, [&](int) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      std::lock_guard<std::mutex> lock(m);
      ids.insert(std::this_thread::get_id());
    });
  }
  EXPECT_EQ(ids.size(), 3u);
}

TEST(ParallelTasks, OutputsCombinedInTaskOrderDoNotDependOnTheThreads) {
  // Per-task float sums combined in task order: bit-identical for any number of threads.
  auto compute = [](int threads) {
    ParallelTasks pool(threads);
    std::vector<float> partial(64);
    pool.run(64, [&](int t) {
      float s = 0.f;
      for (int k = 0; k < 1000; ++k) s += 1.f / static_cast<float>(t * 1000 + k + 1);
      partial[static_cast<std::size_t>(t)] = s;
    });
    return std::accumulate(partial.begin(), partial.end(), 0.f);
  };
  const float one = compute(1);
  EXPECT_EQ(compute(2), one);
  EXPECT_EQ(compute(4), one);
}

TEST(ParallelTasks, RethrowsTheLowestFailingTaskAndStaysUsable) {
  for (int threads : {1, 2, 4}) {
    ParallelTasks pool(threads);
    try {
      pool.run(16, [](int i) {
        if (i == 3 || i == 9) throw std::runtime_error("task " + std::to_string(i));
      });
      ADD_FAILURE() << "no exception with " << threads << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "task 3") << threads << " threads";
    }
    std::atomic<int> n{0};
    pool.run(10, [&](int) { n.fetch_add(1); });
    EXPECT_EQ(n.load(), 10);
  }
}

TEST(ParallelTasks, RefusesNoThreads) {
  EXPECT_THROW(ParallelTasks(0), std::invalid_argument);
}

TEST(ParallelTasks, ManyShortRunsInARow) {
  ParallelTasks pool(2);
  long long total = 0;
  for (int round = 0; round < 2000; ++round) {
    std::vector<int> out(3);
    pool.run(3, [&](int i) { out[static_cast<std::size_t>(i)] = i + round; });
    total += out[0] + out[1] + out[2];
  }
  long long expected = 0;
  for (int round = 0; round < 2000; ++round) expected += 3 + 3LL * round;
  EXPECT_EQ(total, expected);
}

}  // namespace
}  // namespace ldsm::concurrency
