#include "concurrency/parallel_tasks.h"

#include <limits>
#include <stdexcept>

namespace ldsm::concurrency {

ParallelTasks::ParallelTasks(int threads) {
  if (threads < 1) throw std::invalid_argument("ParallelTasks: threads must be at least 1");
  helpers_.reserve(static_cast<std::size_t>(threads - 1));
  for (int i = 1; i < threads; ++i) helpers_.emplace_back([this] { helperLoop(); });
}

ParallelTasks::~ParallelTasks() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& t : helpers_) t.join();
}

void ParallelTasks::runTasks(int count, TaskFunction function, void* task) {
  if (count <= 0) return;
  if (helpers_.empty() || count == 1) {
    for (int i = 0; i < count; ++i) function(task, i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    function_ = function;
    task_ = task;
    count_ = count;
    next_.store(0, std::memory_order_relaxed);
    error_ = nullptr;
    error_index_ = std::numeric_limits<int>::max();
    busy_helpers_ = static_cast<int>(helpers_.size());
    ++generation_;
  }
  work_ready_.notify_all();
  work();
  std::exception_ptr error;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    work_done_.wait(lock, [this] { return busy_helpers_ == 0; });
    task_ = nullptr;
    error = error_;
    error_ = nullptr;
  }
  if (error) std::rethrow_exception(error);
}

void ParallelTasks::work() {
  for (;;) {
    const int i = next_.fetch_add(1, std::memory_order_relaxed);
    if (i >= count_) return;
    try {
      function_(task_, i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (i < error_index_) {
        error_index_ = i;
        error_ = std::current_exception();
      }
    }
  }
}

void ParallelTasks::helperLoop() {
  // Generation 0 is the constructor's: a run() may have started before this thread got here,
  // and it waits for this helper too.
  std::uint64_t seen = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_ready_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    lock.unlock();
    work();
    lock.lock();
    if (--busy_helpers_ == 0) work_done_.notify_one();
  }
}

}  // namespace ldsm::concurrency
