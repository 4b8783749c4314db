// PLACEHOLDER: replaced by the real `ldsm sim` command.
#include "commands.h"

namespace ldsm::app {
void addSimCommand(CLI::App& app, CommandResult& result) {
  (void)app;
  (void)result;
}
}  // namespace ldsm::app
