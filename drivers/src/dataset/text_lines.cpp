// Line reading and strict number parsing for dataset text files.
#include "dataset/text_lines.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <system_error>

#include "ldsm/error.h"

namespace ldsm::drivers::detail {
namespace {

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v';
}

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && isSpace(s[b])) ++b;
  while (e > b && isSpace(s[e - 1])) --e;
  return s.substr(b, e - b);
}

std::vector<std::string> splitFields(const std::string& line, char separator) {
  std::vector<std::string> fields;
  if (separator != '\0') {
    std::size_t begin = 0;
    while (true) {
      const std::size_t at = line.find(separator, begin);
      fields.push_back(trim(line.substr(begin, at == std::string::npos ? at : at - begin)));
      if (at == std::string::npos) break;
      begin = at + 1;
    }
    return fields;
  }
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const std::size_t begin = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > begin) fields.push_back(line.substr(begin, i - begin));
  }
  return fields;
}

}  // namespace

std::vector<TextLine> readDataLines(const std::string& path, char separator) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  std::vector<TextLine> lines;
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    std::size_t first = 0;
    while (first < text.size() && isSpace(text[first])) ++first;
    if (first == text.size() || text[first] == '#') continue;
    lines.push_back({number, splitFields(text.substr(first), separator)});
  }
  if (in.bad()) throw InputError(path + ": read error");
  return lines;
}

bool parseFiniteDouble(std::string_view text, double& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(value);
}

bool parseInt64(std::string_view text, std::int64_t& value) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return false;
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

}  // namespace ldsm::drivers::detail
