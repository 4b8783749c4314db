#include <cmath>
#include <sstream>

#include "ldsm/config.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

/// Checks every numeric field against its declared range, building "section.key" paths.
class RangeChecker {
 public:
  explicit RangeChecker(std::vector<std::string>& problems) : problems_(problems) {}

  template <typename S>
  void section(const char* name, S& s, const char* /*help*/) {
    const std::string saved = prefix_;
    prefix_ += std::string(name) + ".";
    s.visit(*this);
    prefix_ = saved;
  }
  void field(const char*, bool&, const char*) {}
  template <typename T>
  void field(const char* key, T& value, Range<T> range, const char* /*help*/) {
    const bool finite = std::isfinite(static_cast<double>(value));
    if (!finite || value < range.min || value > range.max) {
      std::ostringstream os;
      os << prefix_ << key << " = " << value << " is outside the allowed range [" << range.min
         << ", " << range.max << "]";
      problems_.push_back(os.str());
    }
  }

 private:
  std::vector<std::string>& problems_;
  std::string prefix_;
};

}  // namespace

std::vector<std::string> configProblems(const Config& config) {
  std::vector<std::string> problems;
  Config copy = config;
  RangeChecker checker(problems);
  copy.visit(checker);
  if (config.window.min_keyframes > config.window.max_keyframes)
    problems.push_back("window.min_keyframes (" + std::to_string(config.window.min_keyframes) +
                       ") must not exceed window.max_keyframes (" +
                       std::to_string(config.window.max_keyframes) + ")");
  if (config.initializer.min_rotation_free_parallax_px > config.initializer.min_parallax_px)
    problems.push_back("initializer.min_rotation_free_parallax_px (" +
                       std::to_string(config.initializer.min_rotation_free_parallax_px) +
                       ") must not exceed initializer.min_parallax_px (" +
                       std::to_string(config.initializer.min_parallax_px) + ")");
  if (config.loop.min_pnp_inliers > config.loop.min_matches)
    problems.push_back("loop.min_pnp_inliers (" + std::to_string(config.loop.min_pnp_inliers) +
                       ") must not exceed loop.min_matches (" +
                       std::to_string(config.loop.min_matches) + ")");
  if (config.system.live && config.system.deterministic)
    problems.push_back(
        "system.live = true needs system.deterministic = false (deterministic mode processes "
        "each frame inside submit(): there is no queue to drop frames from)");
  return problems;
}

void validateConfig(const Config& config) {
  const std::vector<std::string> problems = configProblems(config);
  if (problems.empty()) return;
  std::string msg = "invalid configuration:";
  for (const auto& p : problems) msg += "\n  " + p;
  throw ConfigError(msg);
}

}  // namespace ldsm
