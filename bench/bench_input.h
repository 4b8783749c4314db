// What the sequence benchmarks share: opening a real sequence (below ../shared/data) or a
// synthetic scene together with its System and ground truth, and formatting table cells.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/system.h"

namespace ldsm::bench {

struct BenchInput {
  std::unique_ptr<drivers::FrameSource> source;
  std::unique_ptr<System> system;
  Trajectory ground_truth;
};

/// `scene` non-empty: the synthetic scene (`frames` 0: its default length), the System told a
/// focal length off by `focal_error`; otherwise the dataset in `folder` with its own calibration.
inline BenchInput openBenchInput(const Config& config, const std::string& folder,
                                 const std::string& scene, std::int64_t frames = 0,
                                 double focal_error = 0.0) {
  BenchInput in;
  if (!scene.empty()) {
    drivers::sim::SimOptions opt;
    opt.frames = frames;
    auto sim = std::make_unique<drivers::sim::SimSource>(scene, opt);
    GeometricCalibration told = sim->geometricCalibration();
    told.input.fx *= 1.0 + focal_error;
    told.input.fy *= 1.0 + focal_error;
    in.ground_truth = sim->groundTruth();
    in.system = std::make_unique<System>(config, told, sim->photometricCalibration());
    in.source = std::move(sim);
    return in;
  }
  const auto desc = drivers::describeDataset(folder);
  const auto calib = drivers::loadDatasetCalibration(desc);
  in.system = std::make_unique<System>(config, calib.geometric, calib.photometric);
  if (!desc.groundtruth_file.empty())
    in.ground_truth =
        drivers::readTrajectory(desc.groundtruth_file, desc.groundtruth_format, &desc.timestamps);
  in.source = drivers::openDataset(desc);
  return in;
}

/// The sequence benches' shared options: takes argv[i] (and its value, advancing i) when it is
/// `--data DIR` or `--only NAME[,NAME...]`; false otherwise.
inline bool takeSequenceOption(int argc, char** argv, int& i, std::string& data,
                               std::string& only) {
  const std::string a = argv[i];
  if ((a != "--data" && a != "--only") || i + 1 >= argc) return false;
  (a == "--data" ? data : only) = argv[++i];
  return true;
}

/// Whether `name` is among the comma-separated `only` (empty: every name is).
inline bool selected(const std::string& only, const std::string& name) {
  return only.empty() || ("," + only + ",").find("," + name + ",") != std::string::npos;
}

/// printf-formatted value, "-" for NaN.
inline std::string cell(double v, const char* format) {
  if (std::isnan(v)) return "-";
  char b[32];
  std::snprintf(b, sizeof(b), format, v);
  return b;
}

}  // namespace ldsm::bench
