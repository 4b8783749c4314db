// Reading small text files of datasets line by line: comments ('#') and blank lines skipped,
// fields split at whitespace (and optionally at one extra separator such as ','), and strict
// number parsing that rejects trailing garbage.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ldsm::drivers::detail {

/// One data line of a text file: its 1-based line number and its fields.
struct TextLine {
  int number = 0;
  std::vector<std::string> fields;
};

/// Reads every non-blank line not starting with '#' of `path`, split at whitespace and at
/// `separator` when it is not '\0'. Throws ldsm::InputError "<path>: cannot open" on failure.
std::vector<TextLine> readDataLines(const std::string& path, char separator = '\0');

/// Parses the whole of `text` as a finite double (C locale). False on any other content.
bool parseFiniteDouble(std::string_view text, double& value);

/// Parses the whole of `text` as a signed 64-bit integer. False on any other content.
bool parseInt64(std::string_view text, std::int64_t& value);

}  // namespace ldsm::drivers::detail
