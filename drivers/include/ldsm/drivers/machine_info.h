// The machine a run happened on, for stats.json and the benchmarks: the CPU model, the BLAS
// library the process loaded (SuiteSparse's, under the loop-closure pose graph) and the
// environment variables that change code paths at run time (OPENBLAS_CORETYPE).
#pragma once

#include <string>

#include "ldsm/build_info.h"

namespace ldsm::drivers {

struct MachineInfo {
  std::string cpu_model;          ///< /proc/cpuinfo "model name" (or the ARM CPU part), "unknown"
  std::string blas_library;       ///< path of the loaded libblas, empty when none is loaded
  std::string openblas_coretype;  ///< $OPENBLAS_CORETYPE, empty when unset
  BuildInfo build;
};

MachineInfo describeMachine();

/// One line: "cpu <model>, simd <kernels>, OpenCV <version> (optimized|unoptimized), blas <lib>".
std::string machineSummary(const MachineInfo& m);

}  // namespace ldsm::drivers
