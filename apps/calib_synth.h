// `ldsm calib synth`: synthetic input for the calibration tools, rendered by ldsm's simulator
// with a known camera, response and vignette, so that the tools can be tried (and checked)
// without a camera.
#pragma once

#include <string>

#include "ldsm/calib/board_detection.h"
#include "ldsm/camera/calibration.h"
#include "ldsm/drivers/sim/sim_options.h"

namespace ldsm::app {

struct CalibSynthOptions {
  std::string kind;  ///< "board", "sweep" or "flat"
  std::string out;
  calib::BoardSpec board;
  CameraModelType model = CameraModelType::RadTan;
  int views = 20;
  int blurred = 2;                  ///< extra board views blurred by 2.5 px
  int duplicates = 1;               ///< extra board views nearly identical to others
  bool auto_gain = false;           ///< sweep: simulate a camera whose auto-gain was left on
  drivers::sim::SimOptions render;  ///< size, response, vignette, noise
};

/// The camera `synth` renders board views with: a focal length of about 0.82 times the width,
/// the principal point near the centre, and moderate distortion of the given model.
CameraIntrinsics synthCamera(CameraModelType model, int width, int height);

/// Renders the data into options.out and prints what was written:
///  board: images/view_000.png ... and true_camera.txt (the camera used);
///  sweep: a static scene at 40 exposures from 0.05 to 400 ms as images/ + times.txt, and the
///         true true_pcalib.txt (with auto_gain: a gain of up to 16x holds the brightness of the
///         shorter exposures, while times.txt still lists the exposure times);
///  flat:  8 images of a flat, evenly lit surface as images/ + times.txt, true_pcalib.txt and
///         true_vignette.png.
/// Throws ldsm::ConfigError on bad options, ldsm::Error when files cannot be written.
void runCalibSynth(const CalibSynthOptions& options);

}  // namespace ldsm::app
