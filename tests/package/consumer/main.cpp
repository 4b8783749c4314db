#include <cstdio>

#include "ldsm/config.h"
#include "ldsm/version.h"

int main() {
  ldsm::Config config;
  config.points.points_per_keyframe = 10;  // out of range on purpose
  const auto problems = ldsm::configProblems(config);
  std::printf("ldsm %s, %zu problem(s)\n", ldsm::versionString(), problems.size());
  return problems.size() == 1 ? 0 : 1;
}
