#include "ldsm/drivers/dataset_calibration.h"

#include "ldsm/calib/calibration_loader.h"
#include "ldsm/calib/kitti_calib.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/error.h"

namespace ldsm::drivers {

DatasetCalibration loadDatasetCalibration(const DatasetDescription& dataset,
                                          const std::string& calib_file) {
  DatasetCalibration out;
  const std::string file = calib_file.empty() ? dataset.calibration_file : calib_file;
  if (file.empty())
    throw InputError(dataset.root +
                     ": no calibration found (looked for camera.txt, sensor.yaml, calib.txt); "
                     "give one with --calib FILE");
  if (calib_file.empty() && dataset.calibration_kind == CalibrationFileKind::KittiCalib)
    out.geometric =
        calib::readKittiCalib(file, dataset.calibration_camera, dataset.width, dataset.height);
  else
    out.geometric = calib::loadGeometricCalibration(file, dataset.width, dataset.height);
  out.geometric_source = file;
  const CameraIntrinsics& in = out.geometric.input;
  if (dataset.width > 0 && (in.width != dataset.width || in.height != dataset.height))
    throw InputError(file + ": calibration is for " + std::to_string(in.width) + "x" +
                     std::to_string(in.height) + " images but " + dataset.root + " has " +
                     std::to_string(dataset.width) + "x" + std::to_string(dataset.height));
  if (!dataset.photometric_response_file.empty() || !dataset.vignette_file.empty()) {
    out.photometric = calib::loadPhotometricCalibration(dataset.photometric_response_file,
                                                        dataset.vignette_file, in.width, in.height);
    out.photometric_source = dataset.photometric_response_file +
                             (dataset.vignette_file.empty() ? "" : " " + dataset.vignette_file);
  } else {
    out.photometric_source = "none";
  }
  return out;
}

}  // namespace ldsm::drivers
