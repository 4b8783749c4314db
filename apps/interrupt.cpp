#include "interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>

namespace ldsm::app {
namespace {

// Touched from the signal handler: a lock-free atomic is async-signal-safe.
std::atomic<int> g_signals{0};
static_assert(std::atomic<int>::is_always_lock_free);

void onSignal(int) {
  if (g_signals.fetch_add(1) == 0) {
    constexpr char kFirst[] =
        "\nstopping after this frame; the results are kept (again: quit now)\n";
    [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kFirst, sizeof(kFirst) - 1);
    return;
  }
  constexpr char kSecond[] = "\ninterrupted twice: quitting now (outputs as last written)\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kSecond, sizeof(kSecond) - 1);
  ::_exit(130);
}

}  // namespace

InterruptHandler::InterruptHandler() {
  g_signals.store(0);
  previous_int_ = std::signal(SIGINT, onSignal);
  previous_term_ = std::signal(SIGTERM, onSignal);
}

InterruptHandler::~InterruptHandler() {
  std::signal(SIGINT, previous_int_);
  std::signal(SIGTERM, previous_term_);
}

bool InterruptHandler::requested() {
  return g_signals.load() > 0;
}

}  // namespace ldsm::app
