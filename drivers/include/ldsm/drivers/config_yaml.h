// Loading and writing ldsm::Config as YAML. Keys missing from the file keep their defaults; an
// unknown key, a value of the wrong type or out of range is an ldsm::ConfigError naming the file,
// line, key and the allowed range.
#pragma once

#include <string>

#include "ldsm/config.h"

namespace ldsm::drivers {

/// Reads and validates a YAML configuration file.
Config loadConfigYaml(const std::string& path);

/// Parses and validates YAML text; `name` is used in error messages (e.g. the file name).
Config parseConfigYaml(const std::string& text, const std::string& name);

/// The configuration as YAML, each key commented with its meaning and allowed range.
std::string configToYaml(const Config& config);

}  // namespace ldsm::drivers
