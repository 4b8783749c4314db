// Ctrl-C (SIGINT) and SIGTERM for the long-running commands (`ldsm run`, `ldsm record`): the
// first signal asks the command to stop after the current frame and keep everything computed so
// far; a second one quits at once with exit status 130, for a shutdown that hangs (a camera that
// does not answer, a disk that does not return).
#pragma once

namespace ldsm::app {

/// Installs the handlers for SIGINT and SIGTERM for its lifetime (one at a time); the previous
/// handlers come back when it goes.
class InterruptHandler {
 public:
  InterruptHandler();
  ~InterruptHandler();
  InterruptHandler(const InterruptHandler&) = delete;
  InterruptHandler& operator=(const InterruptHandler&) = delete;

  /// Whether a stop was asked for since the handler was installed.
  static bool requested();

 private:
  void (*previous_int_)(int);
  void (*previous_term_)(int);
};

}  // namespace ldsm::app
