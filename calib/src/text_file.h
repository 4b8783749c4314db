// Helpers of the calibration text parsers (private to calib/src): reading a file, splitting it
// into numbered lines of tokens, strict number parsing with "file:line: what" errors.
#pragma once

#include <string>
#include <vector>

namespace ldsm::calib::detail {

/// The whole file. Throws ldsm::InputError "path: cannot open ..." when it cannot be read.
std::string readTextFile(const std::string& path);

/// Writes `text` to `path`, throwing ldsm::Error "path: cannot write ..." on failure.
void writeTextFile(const std::string& path, const std::string& text);

/// One non-empty line: its 1-based number in the file and its whitespace-separated tokens.
struct TextLine {
  int number = 0;
  std::vector<std::string> tokens;
};

/// The lines of `text` that are neither blank nor comments (first token starting with '#').
std::vector<TextLine> contentLines(const std::string& text);

/// Parses a whole token as a finite number. Throws ldsm::InputError "file:line: <field> ..." when
/// it is not a number or not finite.
double parseNumber(const std::string& token, const std::string& file, int line,
                   const std::string& field);

/// Parses a whole token as a positive integer (a pixel count).
int parsePositiveInt(const std::string& token, const std::string& file, int line,
                     const std::string& field);

/// Shortest text that reads back as the same double.
std::string formatNumber(double value);

/// Lower-case copy.
std::string toLower(std::string s);

}  // namespace ldsm::calib::detail
