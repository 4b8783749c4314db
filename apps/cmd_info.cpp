// PLACEHOLDER: replaced by the real `ldsm info` command.
#include "commands.h"

namespace ldsm::app {
void addInfoCommand(CLI::App& app, CommandResult& result) {
  (void)app;
  (void)result;
}
}  // namespace ldsm::app
