#include "text_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ldsm/error.h"

namespace ldsm::calib::detail {

std::string readTextFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file (" + std::strerror(errno) + ")");
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return s.str();
}

void writeTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw Error(path + ": cannot open for writing (" + std::strerror(errno) + ")");
  out << text;
  out.close();
  if (!out) throw Error(path + ": write error");
}

std::vector<TextLine> contentLines(const std::string& text) {
  std::vector<TextLine> lines;
  std::istringstream in(text);
  std::string raw;
  int number = 0;
  while (std::getline(in, raw)) {
    ++number;
    TextLine line;
    line.number = number;
    std::istringstream words(raw);
    std::string token;
    while (words >> token) line.tokens.push_back(token);
    if (line.tokens.empty() || line.tokens.front()[0] == '#') continue;
    lines.push_back(std::move(line));
  }
  return lines;
}

double parseNumber(const std::string& token, const std::string& file, int line,
                   const std::string& field) {
  // from_chars: locale-independent; it rejects a leading '+', which we allow.
  const char* begin = token.data();
  const char* end = token.data() + token.size();
  if (begin != end && *begin == '+') ++begin;
  double v = 0.0;
  const auto res = std::from_chars(begin, end, v);
  if (res.ptr == begin || res.ptr != end ||
      (res.ec != std::errc() && res.ec != std::errc::result_out_of_range))
    throw InputError(atLine(file, line, field + ": '" + token + "' is not a number"));
  if (res.ec == std::errc::result_out_of_range)
    throw InputError(atLine(file, line, field + " is out of range (" + token + ")"));
  if (!std::isfinite(v))
    throw InputError(atLine(file, line, field + " is not finite (" + token + ")"));
  return v;
}

int parsePositiveInt(const std::string& token, const std::string& file, int line,
                     const std::string& field) {
  int v = 0;
  const char* end = token.data() + token.size();
  const auto res = std::from_chars(token.data(), end, v);
  if (res.ec != std::errc() || res.ptr != end || v <= 0)
    throw InputError(
        atLine(file, line, field + " must be a positive integer (got '" + token + "')"));
  return v;
}

std::string formatNumber(double value) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof(buf), value);
  return std::string(buf, res.ptr);
}

std::string toLower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace ldsm::calib::detail
