// PLACEHOLDER: replaced by the real `ldsm eval` command.
#include "commands.h"

namespace ldsm::app {
void addEvalCommand(CLI::App& app, CommandResult& result) {
  (void)app;
  (void)result;
}
}  // namespace ldsm::app
