// The background task (loop closure runs on it): inline and threaded modes run the same processing,
// results arrive in order through the mailbox, a full ring drops (and counts) jobs, stop() aborts a
// running job, exceptions are contained, the worker runs at the lowest priority. Written to be
// race-free under ThreadSanitizer (all shared state is atomic or owned by the task).
#include <gtest/gtest.h>

#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <stdexcept>
#include <thread>

#include "concurrency/background_task.h"

namespace ldsm::concurrency {
namespace {

using namespace std::chrono_literals;

struct Job {
  int keyframe_id = -1;
  std::shared_ptr<const std::vector<int>> payload;
};

/// What the processor publishes (a result with an owning member, like a loop correction).
struct Result {
  int current_keyframe_id = -1;
  int candidate_keyframe_id = -1;
  std::map<int, double> values;
};

Result correctionFor(const Job& job) {
  Result c;
  c.current_keyframe_id = job.keyframe_id;
  c.candidate_keyframe_id = job.payload ? static_cast<int>(job.payload->size()) : -1;
  c.values[job.keyframe_id] = 2.0 * job.keyframe_id;
  return c;
}

TaskOptions options(TaskMode mode, std::size_t capacity = 32) {
  TaskOptions o;
  o.mode = mode;
  o.queue_capacity = capacity;
  o.priority = WorkerPriority::kNormal;
  return o;
}

// Runs `jobs` keyframes through a task whose processor publishes every third one.
std::vector<Result> runAll(TaskMode mode, int jobs, std::thread::id* worker_id) {
  std::atomic<std::thread::id> seen{};
  BackgroundTask<Job, Result> task(
      [&](Job& job, const std::atomic<bool>&) -> std::optional<Result> {
        seen.store(std::this_thread::get_id());
        if (job.keyframe_id % 3 != 0) return std::nullopt;
        return correctionFor(job);
      },
      options(mode));
  for (int i = 0; i < jobs; ++i) {
    EXPECT_TRUE(task.submit(Job{i, std::make_shared<const std::vector<int>>(i, 1)}));
  }
  EXPECT_TRUE(task.waitIdle(30s));
  EXPECT_EQ(task.processed(), static_cast<std::uint64_t>(jobs));
  EXPECT_EQ(task.dropped(), 0u);
  *worker_id = seen.load();
  return task.takeResults();
}

TEST(BackgroundTask, InlineAndThreadedGiveTheSameResults) {
  std::thread::id inline_id, threaded_id;
  const auto a = runAll(TaskMode::kInline, 20, &inline_id);
  const auto b = runAll(TaskMode::kThreaded, 20, &threaded_id);
  EXPECT_EQ(inline_id, std::this_thread::get_id());
  EXPECT_NE(threaded_id, std::this_thread::get_id());
  ASSERT_EQ(a.size(), 7u);
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].current_keyframe_id, static_cast<int>(3 * k));
    EXPECT_EQ(b[k].current_keyframe_id, a[k].current_keyframe_id);
    EXPECT_EQ(b[k].candidate_keyframe_id, a[k].candidate_keyframe_id);
    EXPECT_EQ(b[k].values.at(b[k].current_keyframe_id), a[k].values.at(a[k].current_keyframe_id));
  }
}

TEST(BackgroundTask, InlineResultsAreAvailableRightAfterSubmit) {
  BackgroundTask<Job, Result> task(
      [](Job& job, const std::atomic<bool>&) -> std::optional<Result> {
        return correctionFor(job);
      },
      options(TaskMode::kInline));
  ASSERT_TRUE(task.submit(Job{5, nullptr}));
  const auto r = task.tryTakeResults();  // no other thread: try_lock succeeds
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].current_keyframe_id, 5);
  EXPECT_TRUE(task.tryTakeResults().empty());
}

TEST(BackgroundTask, FullRingDropsAndCountsJobs) {
  std::atomic<bool> started{false}, release{false};
  BackgroundTask<Job, Result> task(
      [&](Job&, const std::atomic<bool>&) -> std::optional<Result> {
        started.store(true);
        while (!release.load()) std::this_thread::sleep_for(1ms);
        return std::nullopt;
      },
      options(TaskMode::kThreaded, 3));  // rounded up to 4
  ASSERT_TRUE(task.submit(Job{0, nullptr}));
  while (!started.load()) std::this_thread::sleep_for(1ms);  // job 0 left the ring
  for (int i = 1; i <= 4; ++i) EXPECT_TRUE(task.submit(Job{i, nullptr})) << i;
  EXPECT_FALSE(task.submit(Job{5, nullptr}));
  EXPECT_EQ(task.dropped(), 1u);
  EXPECT_FALSE(task.waitIdle(5ms));
  release.store(true);
  EXPECT_TRUE(task.waitIdle(30s));
  EXPECT_EQ(task.processed(), 5u);
  EXPECT_EQ(task.submitted(), 5u);
}

TEST(BackgroundTask, StopAbortsTheRunningJobAndRefusesNewOnes) {
  std::atomic<bool> started{false};
  std::atomic<int> finished{0};
  auto task = std::make_unique<BackgroundTask<Job, Result>>(
      [&](Job&, const std::atomic<bool>& abort) -> std::optional<Result> {
        started.store(true);
        while (!abort.load()) std::this_thread::sleep_for(1ms);  // a "long pose-graph solve"
        finished.fetch_add(1);
        return std::nullopt;
      },
      options(TaskMode::kThreaded));
  ASSERT_TRUE(task->submit(Job{0, nullptr}));
  ASSERT_TRUE(task->submit(Job{1, nullptr}));
  while (!started.load()) std::this_thread::sleep_for(1ms);
  const auto t0 = std::chrono::steady_clock::now();
  task->stop();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 2s);
  EXPECT_EQ(finished.load(), 1);  // job 1 was dropped, not started
  EXPECT_EQ(task->unfinished(), 2u);
  EXPECT_FALSE(task->submit(Job{2, nullptr}));
  EXPECT_FALSE(task->waitIdle(1ms));
  task.reset();  // destructor after stop(): fine
}

TEST(BackgroundTask, FinishStopsWorkThatOutlastsItsTimeAndSaysHowMuch) {
  std::atomic<bool> started{false};
  std::atomic<int> finished{0};
  BackgroundTask<Job, Result> task(
      [&](Job&, const std::atomic<bool>& abort) -> std::optional<Result> {
        started.store(true);
        while (!abort.load()) std::this_thread::sleep_for(1ms);  // never done by itself
        finished.fetch_add(1);
        return std::nullopt;
      },
      options(TaskMode::kThreaded));
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(task.submit(Job{i, nullptr}));
  while (!started.load()) std::this_thread::sleep_for(1ms);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(task.finish(20ms), 3u);  // the running job and the two queued ones
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5s);
  EXPECT_TRUE(task.stopped());
  EXPECT_EQ(finished.load(), 1);  // the running one aborted; the worker joined before return
  EXPECT_FALSE(task.submit(Job{3, nullptr}));
  EXPECT_EQ(task.unfinished(), 3u);
  EXPECT_EQ(task.finish(20ms), 3u);  // idempotent: the same count, nothing new accepted
}

TEST(BackgroundTask, FinishWithinItsTimeLeavesTheTaskRunning) {
  for (const TaskMode mode : {TaskMode::kInline, TaskMode::kThreaded}) {
    BackgroundTask<Job, Result> task(
        [](Job& job, const std::atomic<bool>&) -> std::optional<Result> {
          return correctionFor(job);
        },
        options(mode));
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(task.submit(Job{i, nullptr}));
    EXPECT_EQ(task.finish(30s), 0u);
    EXPECT_FALSE(task.stopped());
    EXPECT_EQ(task.processed(), 5u);
    EXPECT_TRUE(task.submit(Job{5, nullptr}));  // still accepts work
    EXPECT_EQ(task.finish(30s), 0u);
    EXPECT_EQ(task.takeResults().size(), 6u);
  }
}

TEST(BackgroundTask, ExceptionsAreContainedInBothModes) {
  for (const TaskMode mode : {TaskMode::kInline, TaskMode::kThreaded}) {
    BackgroundTask<Job, Result> task(
        [](Job& job, const std::atomic<bool>&) -> std::optional<Result> {
          if (job.keyframe_id == 1) throw std::runtime_error("verification blew up");
          if (job.keyframe_id == 2) throw 42;
          return correctionFor(job);
        },
        options(mode));
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(task.submit(Job{i, nullptr}));
    EXPECT_TRUE(task.waitIdle(30s));
    EXPECT_EQ(task.failed(), 2u);
    const auto r = task.takeResults();
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(r[0].current_keyframe_id, 0);
    EXPECT_EQ(r[1].current_keyframe_id, 3);
  }
}

TEST(BackgroundTask, WorkerRunsAtTheLowestPriority) {
  std::atomic<int> policy{-1}, nice_value{-100};
  TaskOptions o = options(TaskMode::kThreaded);
  o.priority = WorkerPriority::kLowest;
  BackgroundTask<Job, Result> task(
      [&](Job&, const std::atomic<bool>&) -> std::optional<Result> {
        policy.store(sched_getscheduler(0));
        errno = 0;
        nice_value.store(getpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid))));
        return std::nullopt;
      },
      o);
  ASSERT_TRUE(task.submit(Job{}));
  ASSERT_TRUE(task.waitIdle(60s));  // SCHED_IDLE may wait for a busy machine
  EXPECT_TRUE(policy.load() == SCHED_IDLE || nice_value.load() == 19)
      << "policy " << policy.load() << " nice " << nice_value.load();
  // The submitting thread is untouched.
  EXPECT_NE(sched_getscheduler(0), SCHED_IDLE);
}

TEST(BackgroundTask, ManyJobsArriveExactlyOnceInOrder) {
  // Producer retries when the ring is full; the consumer polls concurrently with tryTakeResults.
  constexpr int kJobs = 5000;
  BackgroundTask<Job, int> task(
      [](Job& job, const std::atomic<bool>&) -> std::optional<int> { return job.keyframe_id; },
      options(TaskMode::kThreaded, 16));
  std::vector<int> received;
  for (int i = 0; i < kJobs; ++i) {
    while (!task.submit(Job{i, nullptr})) {
      for (int r : task.tryTakeResults()) received.push_back(r);
      std::this_thread::yield();
    }
  }
  ASSERT_TRUE(task.waitIdle(60s));
  for (int r : task.takeResults()) received.push_back(r);
  ASSERT_EQ(received.size(), static_cast<std::size_t>(kJobs));
  for (int i = 0; i < kJobs; ++i) ASSERT_EQ(received[i], i);
}

TEST(BackgroundTask, RequiresAProcessor) {
  using Task = BackgroundTask<Job, Result>;
  EXPECT_THROW(Task(nullptr, options(TaskMode::kInline)), ConfigError);
}

}  // namespace
}  // namespace ldsm::concurrency
