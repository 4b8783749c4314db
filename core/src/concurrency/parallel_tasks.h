// A small fork-join pool for data-parallel work whose results do not depend on the number of
// threads: run(count, task) calls task(0) ... task(count - 1), each exactly once, spread over
// the calling thread and the pool's helper threads, and returns when all of them have ended.
// Each task must write only its own outputs; the caller combines them afterwards in task order,
// so that the result is the same with one thread or many (the fixed reduction order that
// deterministic mode needs). Helpers sleep on a condition variable between runs (no spinning:
// on a small board the cores they do not use belong to tracking and mapping).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace ldsm::concurrency {

class ParallelTasks {
 public:
  /// `threads` >= 1 threads in all, the calling thread included (threads - 1 helpers are
  /// started). Throws std::invalid_argument when threads < 1.
  explicit ParallelTasks(int threads);
  ~ParallelTasks();
  ParallelTasks(const ParallelTasks&) = delete;
  ParallelTasks& operator=(const ParallelTasks&) = delete;

  /// Threads in all, the caller included.
  int threads() const { return static_cast<int>(helpers_.size()) + 1; }

  /// Runs task(i) for i in [0, count) and returns when every one has ended. With one thread
  /// (or count 1) the tasks run in order on the caller. When tasks throw, the exception of the
  /// lowest-numbered failing task is rethrown after all started tasks ended (with several
  /// threads the tasks after it may have run too). Not reentrant: one run() at a time, and
  /// tasks must not call run().
  /// `task` is any callable taking the task index; it is called by reference (no copy, no
  /// allocation).
  template <class Task>
  void run(int count, Task&& task) {
    using T = std::remove_reference_t<Task>;
    runTasks(
        count, [](void* t, int i) { (*static_cast<T*>(t))(i); },
        const_cast<void*>(static_cast<const void*>(&task)));
  }

 private:
  using TaskFunction = void (*)(void* task, int index);
  void runTasks(int count, TaskFunction function, void* task);
  void helperLoop();
  void work();

  std::vector<std::thread> helpers_;
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable work_done_;
  // The current run; written under mutex_ before generation_ changes.
  TaskFunction function_ = nullptr;
  void* task_ = nullptr;
  int count_ = 0;
  std::atomic<int> next_{0};
  std::uint64_t generation_ = 0;
  int busy_helpers_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
  int error_index_ = 0;
};

/// `pool`->run(count, task), or the tasks in order on the caller when there is no pool: for
/// stages that run with or without one.
template <class Task>
void runTasks(ParallelTasks* pool, int count, Task&& task) {
  if (pool != nullptr) {
    pool->run(count, task);
  } else {
    for (int i = 0; i < count; ++i) task(i);
  }
}

}  // namespace ldsm::concurrency
