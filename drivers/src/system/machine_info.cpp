#include "ldsm/drivers/machine_info.h"

#include <cstdlib>
#include <fstream>
#include <string>

namespace ldsm::drivers {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, arm_implementer, arm_part;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = trim(line.substr(0, colon));
    const std::string value = trim(line.substr(colon + 1));
    if (key == "model name" && !value.empty()) return value;
    if (key == "CPU implementer" && arm_implementer.empty()) arm_implementer = value;
    if (key == "CPU part" && arm_part.empty()) arm_part = value;
  }
  if (!arm_part.empty()) return "ARM implementer " + arm_implementer + " part " + arm_part;
  return "unknown";
}

std::string loadedLibrary(const std::string& name) {
  std::ifstream in("/proc/self/maps");
  std::string line;
  while (std::getline(in, line)) {
    const auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    const std::string path = line.substr(slash);
    const auto base = path.find_last_of('/');
    if (path.compare(base + 1, name.size(), name) == 0) return path;
  }
  return {};
}

}  // namespace

MachineInfo describeMachine() {
  MachineInfo m;
  m.cpu_model = cpuModel();
  m.blas_library = loadedLibrary("libblas");
  if (m.blas_library.empty()) m.blas_library = loadedLibrary("libopenblas");
  if (const char* c = std::getenv("OPENBLAS_CORETYPE")) m.openblas_coretype = c;
  m.build = buildInfo();
  return m;
}

std::string machineSummary(const MachineInfo& m) {
  std::string s = "cpu " + m.cpu_model + ", simd " + m.build.simd + ", OpenCV " +
                  m.build.opencv_version + (m.build.opencv_optimized ? "" : " (unoptimized)") +
                  ", blas " + (m.blas_library.empty() ? "not loaded" : m.blas_library);
  if (!m.openblas_coretype.empty()) s += " (OPENBLAS_CORETYPE=" + m.openblas_coretype + ")";
  return s;
}

}  // namespace ldsm::drivers
