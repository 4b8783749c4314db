// Helpers of the calibration file tests.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm::test {

inline std::string writeFile(const std::string& dir, const std::string& name,
                             const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// Runs `fn`, expecting an ldsm::InputError whose message starts with "<path>:<line>: " (or
/// "<path>: " when line is 0) and contains `text`.
template <typename Fn>
void expectInputError(Fn fn, const std::string& path, int line, const std::string& text) {
  try {
    fn();
    ADD_FAILURE() << "no error for " << path << " (expected '" << text << "')";
  } catch (const InputError& e) {
    const std::string what = e.what();
    const std::string prefix = line > 0 ? path + ":" + std::to_string(line) + ": " : path + ": ";
    EXPECT_EQ(what.rfind(prefix, 0), 0u)
        << "message '" << what << "' should start with '" << prefix << "'";
    EXPECT_NE(what.find(text), std::string::npos)
        << "message '" << what << "' should contain '" << text << "'";
  }
}

}  // namespace ldsm::test
