// A real sequence of ../shared/data opened as the system tests run it: its description, its
// calibration, its ground truth (by the sequence's own timestamps) and a frame source.
#pragma once

#include <memory>
#include <string>

#include "ldsm/drivers/dataset_calibration.h"
#include "ldsm/drivers/dataset_description.h"
#include "ldsm/drivers/dataset_source.h"
#include "ldsm/drivers/trajectory_io.h"

namespace ldsm::test {

struct RealSequence {
  drivers::DatasetDescription description;
  drivers::DatasetCalibration calibration;
  Trajectory ground_truth;
  std::unique_ptr<drivers::FrameSource> source;
};

inline RealSequence openRealSequence(const std::string& folder) {
  RealSequence s;
  s.description = drivers::describeDataset(folder);
  s.calibration = drivers::loadDatasetCalibration(s.description);
  s.ground_truth = drivers::readTrajectory(
      s.description.groundtruth_file, s.description.groundtruth_format, &s.description.timestamps);
  s.source = drivers::openDataset(s.description);
  return s;
}

}  // namespace ldsm::test
