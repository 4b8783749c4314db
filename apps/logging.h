// Logging set-up shared by every subcommand: spdlog to stderr, quiet (warn) by default.
#pragma once

#include <string>

namespace ldsm::app {

/// Sets the global spdlog level from a name (trace, debug, info, warn, error, off).
void setupLogging(const std::string& level);

}  // namespace ldsm::app
