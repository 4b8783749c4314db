// Errors raised by ldsm. Every message names what was wrong (the file and line, the config key and
// its allowed range, the frame index) so that a user can act on it without reading the source.
#pragma once

#include <stdexcept>
#include <string>

namespace ldsm {

/// Base class of every exception ldsm throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input data: a missing, unreadable or malformed file, a wrongly sized image, a NaN in a
/// calibration, non-monotonic timestamps. The message starts with the file (and line) at fault.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A configuration value outside its allowed range. The message names the key and the range.
class ConfigError : public Error {
 public:
  using Error::Error;
};

/// A device or stream that failed at run time (camera unplugged, poll timeout).
class DeviceError : public Error {
 public:
  using Error::Error;
};

/// "file:line: what" — the format every parser uses for InputError messages.
inline std::string atLine(const std::string& file, int line, const std::string& what) {
  return file + ":" + std::to_string(line) + ": " + what;
}

}  // namespace ldsm
