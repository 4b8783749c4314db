#include "ldsm/drivers/dataset_calibration.h"

#include <sstream>

#include "ldsm/calib/calibration_loader.h"
#include "ldsm/calib/kitti_calib.h"
#include "ldsm/calib/photometric_files.h"
#include "ldsm/calib/pinhole_guess.h"
#include "ldsm/error.h"

namespace ldsm::drivers {

DatasetCalibration loadDatasetCalibration(const DatasetDescription& dataset,
                                          const std::string& calib_file, double guess_fov_deg) {
  DatasetCalibration out;
  const std::string file = calib_file.empty() ? dataset.calibration_file : calib_file;
  if (guess_fov_deg != 0.0) {
    if (!calib_file.empty()) throw ConfigError("give either --calib FILE or --fov DEG, not both");
    out.geometric = calib::pinholeFromFieldOfView(dataset.width, dataset.height, guess_fov_deg);
    std::ostringstream source;
    source << "a pinhole guess of " << guess_fov_deg << " degrees (--fov)";
    out.geometric_source = source.str();
  } else if (file.empty()) {
    throw InputError(dataset.root +
                     ": no calibration found (looked for camera.txt, sensor.yaml, calib.txt); "
                     "give one with --calib FILE, or start from a guess of the horizontal field "
                     "of view with --fov DEG and let the camera calibrate itself");
  } else if (calib_file.empty() && dataset.calibration_kind == CalibrationFileKind::KittiCalib) {
    out.geometric =
        calib::readKittiCalib(file, dataset.calibration_camera, dataset.width, dataset.height);
  } else {
    out.geometric = calib::loadGeometricCalibration(file, dataset.width, dataset.height);
  }
  if (out.geometric_source.empty()) out.geometric_source = file;
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
