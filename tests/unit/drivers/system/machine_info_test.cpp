// The machine description of stats.json and the benchmarks (drivers/src/system/machine_info.cpp).
#include "ldsm/drivers/machine_info.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace ldsm::drivers {
namespace {

TEST(MachineInfo, DescribesThisMachine) {
  const MachineInfo m = describeMachine();
  EXPECT_FALSE(m.cpu_model.empty()) << "a model name, an ARM part or \"unknown\"";
  EXPECT_EQ(m.cpu_model.find_first_of("\r\n"), std::string::npos);
  EXPECT_EQ(m.cpu_model.front() == ' ' || m.cpu_model.back() == ' ', false) << "trimmed";
  EXPECT_EQ(m.build.version, buildInfo().version);
  EXPECT_EQ(m.build.simd, buildInfo().simd);
  if (!m.blas_library.empty()) {
    EXPECT_EQ(m.blas_library.front(), '/') << "a path from /proc/self/maps";
    EXPECT_NE(m.blas_library.find("blas"), std::string::npos);
  }
}

TEST(MachineInfo, ReadsOpenBlasCoretypeFromTheEnvironment) {
  const char* old = std::getenv("OPENBLAS_CORETYPE");
  const std::string saved = old ? old : "";
  ::setenv("OPENBLAS_CORETYPE", "ARMV8", 1);
  EXPECT_EQ(describeMachine().openblas_coretype, "ARMV8");
  ::unsetenv("OPENBLAS_CORETYPE");
  EXPECT_EQ(describeMachine().openblas_coretype, "");
  if (old) ::setenv("OPENBLAS_CORETYPE", saved.c_str(), 1);
}

TEST(MachineInfo, SummaryNamesEveryPart) {
  MachineInfo m;
  m.cpu_model = "Test CPU 3000";
  m.build.simd = "sse";
  m.build.opencv_version = "4.6.0";
  m.build.opencv_optimized = true;
  EXPECT_EQ(machineSummary(m), "cpu Test CPU 3000, simd sse, OpenCV 4.6.0, blas not loaded");
  m.build.opencv_optimized = false;
  m.blas_library = "/usr/lib/libblas.so.3";
  m.openblas_coretype = "ARMV8";
  EXPECT_EQ(machineSummary(m),
            "cpu Test CPU 3000, simd sse, OpenCV 4.6.0 (unoptimized), blas /usr/lib/libblas.so.3 "
            "(OPENBLAS_CORETYPE=ARMV8)");
}

}  // namespace
}  // namespace ldsm::drivers
