#include "concurrency/worker_thread.h"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include <spdlog/spdlog.h>

#include "ldsm/error.h"

namespace ldsm::concurrency {

bool lowerCurrentThreadPriority() {
  bool lowered = false;
#ifdef SCHED_IDLE
  sched_param param{};
  param.sched_priority = 0;
  const int idle_err = pthread_setschedparam(pthread_self(), SCHED_IDLE, &param);
  lowered = idle_err == 0;
#else
  const int idle_err = ENOSYS;
#endif
  // On Linux the nice value is per thread (setpriority on the thread id).
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  const bool niced = setpriority(PRIO_PROCESS, tid, 19) == 0;
  const int nice_err = niced ? 0 : errno;
  lowered = lowered || niced;
  if (!lowered) {
    spdlog::info(
        "loop closing: cannot lower the worker thread's priority (SCHED_IDLE: {}, nice 19: {}); "
        "it runs at normal priority",
        std::strerror(idle_err), std::strerror(nice_err));
  } else if (idle_err != 0) {
    spdlog::debug("loop closing: SCHED_IDLE refused ({}), worker runs at nice 19",
                  std::strerror(idle_err));
  }
  return lowered;
}

void logBackgroundJobFailure(const char* what) {
  spdlog::error("loop closing: a background job failed and was skipped: {}", what);
}

WorkerThread::WorkerThread(std::function<void()> drain, WorkerPriority priority)
    : drain_(std::move(drain)) {
  if (sem_init(&wakeups_, 0, 0) != 0) {
    throw Error(std::string("loop closing: sem_init failed: ") + std::strerror(errno));
  }
  try {
    thread_ = std::thread([this, priority] { run(priority); });
  } catch (...) {
    sem_destroy(&wakeups_);
    throw;
  }
}

WorkerThread::~WorkerThread() {
  stop();
  sem_destroy(&wakeups_);
}

void WorkerThread::wake() {
  sem_post(&wakeups_);
}

void WorkerThread::stop() {
  stop_.store(true, std::memory_order_release);
  if (thread_.joinable()) {
    sem_post(&wakeups_);
    thread_.join();
  }
}

void WorkerThread::run(WorkerPriority priority) {
  if (priority == WorkerPriority::kLowest) lowerCurrentThreadPriority();
  for (;;) {
    while (sem_wait(&wakeups_) != 0) {
      if (errno != EINTR) return;  // cannot happen with a valid semaphore
    }
    if (stopping()) return;
    drain_();
  }
}

}  // namespace ldsm::concurrency
