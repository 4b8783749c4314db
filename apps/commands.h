// Subcommands of the `ldsm` tool. Each lives in its own cmd_<name>.cpp and registers itself on the
// top-level CLI11 app. Commands report failures by throwing ldsm::Error (the message is printed
// and the exit code is 1) or by returning a non-zero exit code through CommandResult.
#pragma once

#include <CLI/CLI.hpp>

namespace ldsm::app {

/// Exit code of the command that ran; commands set it, main() returns it.
struct CommandResult {
  int exit_code = 0;
};

void addConfigCommand(CLI::App& app, CommandResult& result);
void addInfoCommand(CLI::App& app, CommandResult& result);
void addSimCommand(CLI::App& app, CommandResult& result);
void addEvalCommand(CLI::App& app, CommandResult& result);
void addRunCommand(CLI::App& app, CommandResult& result);
void addRecordCommand(CLI::App& app, CommandResult& result);
void addCalibCommand(CLI::App& app, CommandResult& result);
void addVocabCommand(CLI::App& app, CommandResult& result);
void addViewCommand(CLI::App& app, CommandResult& result);
void addMapCommand(CLI::App& app, CommandResult& result);

}  // namespace ldsm::app
