// Runs one benchmark case in a forked child process so that its peak memory (ru_maxrss) is its
// own, and hands a trivially copyable result back through a pipe.
#pragma once

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <type_traits>

namespace ldsm::bench {

/// What came back from the child.
enum class ChildStatus { kOk, kError, kCrashed };

/// Calls `fn(result)` in a child process. `Result` must be trivially copyable and have a
/// `char error[N]` member that the child fills with an exception's message. `rss_mb` receives
/// the child's peak resident set size.
template <typename Result, typename Fn>
ChildStatus runInChild(Fn&& fn, Result& result, double& rss_mb) {
  static_assert(std::is_trivially_copyable_v<Result>, "the result crosses a pipe");
  std::fflush(stdout);
  int fd[2];
  if (pipe(fd) != 0) return ChildStatus::kCrashed;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    Result r{};
    try {
      fn(r);
    } catch (const std::exception& e) {
      std::snprintf(r.error, sizeof(r.error), "%s", e.what());
    }
    if (write(fd[1], &r, sizeof(r)) != static_cast<ssize_t>(sizeof(r))) _exit(3);
    _exit(0);
  }
  close(fd[1]);
  const bool got = read(fd[0], &result, sizeof(result)) == static_cast<ssize_t>(sizeof(result));
  close(fd[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
  if (!got) return ChildStatus::kCrashed;
  return result.error[0] ? ChildStatus::kError : ChildStatus::kOk;
}

}  // namespace ldsm::bench
