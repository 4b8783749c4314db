// Paths and helpers shared by tests.
#pragma once

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace ldsm::test {

/// ../shared/data of the checkout, or an empty string when absent.
inline std::string sharedData(const std::string& sub = "") {
  const std::filesystem::path root(LDSM_SHARED_DATA);
  if (!std::filesystem::is_directory(root)) return {};
  const auto p = sub.empty() ? root : root / sub;
  return std::filesystem::exists(p) ? p.string() : std::string{};
}

/// A fresh, empty scratch folder for one test.
inline std::string scratchDir(const std::string& name) {
  const auto p = std::filesystem::path(LDSM_TEST_TMP) / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

/// The whole contents of a file (empty when it cannot be read).
inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Runs a shell command, returning its exit code and capturing stdout+stderr into `output`.
inline int runCommand(const std::string& cmd, std::string* output) {
  std::string full = cmd + " 2>&1";
  FILE* pipe = popen(full.c_str(), "r");
  if (pipe == nullptr) return -1;
  char buf[4096];
  std::string out;
  while (size_t n = fread(buf, 1, sizeof(buf), pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace ldsm::test
