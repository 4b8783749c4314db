#include "ldsm/calib/camera_calibration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "calibration_test_util.h"
#include "ldsm/calib/dso_camera_file.h"
#include "ldsm/calib/kalibr_yaml.h"

namespace ldsm::calib {
namespace {

struct Scenario {
  CameraIntrinsics truth;
  BoardType board;
  int views;
  double distance;
};

std::vector<BoardView> renderViews(const Scenario& s, const BoardSpec& spec) {
  const auto target = test::targetFor(spec);
  const auto camera = makeCameraModel(s.truth);
  const auto poses = test::boardPoses(target, *camera, s.views, s.distance);
  EXPECT_EQ(poses.size(), static_cast<std::size_t>(s.views));
  std::vector<BoardView> views;
  for (std::size_t i = 0; i < poses.size(); ++i)
    views.push_back(test::renderView(spec, target, *camera, poses[i], static_cast<int>(i)));
  return views;
}

/// How far the model's distortion moves the image of `ray` from where the pinhole part of the
/// same intrinsics would put it.
Eigen::Vector2d distortionShift(const CameraModel& model, const Eigen::Vector3d& ray) {
  Eigen::Vector2d px;
  EXPECT_TRUE(model.project(ray, &px));
  const auto& k = model.intrinsics();
  return px - Eigen::Vector2d(k.fx * ray.x() / ray.z() + k.cx, k.fy * ray.y() / ray.z() + k.cy);
}

/// Checks the recovered intrinsics: focal lengths within 0.5 %, principal point within 1 px, and
/// the distortion through what it does: over the part of the image the board's corners covered,
/// the shift it causes differs from the true one by less than `px_tolerance`.
void expectIntrinsics(const CameraCalibrationResult& r, const CameraIntrinsics& truth,
                      double px_tolerance) {
  const CameraIntrinsics& got = r.calibration.input;
  EXPECT_EQ(got.model, truth.model);
  EXPECT_NEAR(got.fx, truth.fx, 0.005 * truth.fx);
  EXPECT_NEAR(got.fy, truth.fy, 0.005 * truth.fy);
  EXPECT_NEAR(got.cx, truth.cx, 1.0);
  EXPECT_NEAR(got.cy, truth.cy, 1.0);
  ASSERT_EQ(got.distortion.size(), truth.distortion.size());
  Eigen::Vector2d lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const auto& c : r.corners) {
    lo = lo.cwiseMin(c);
    hi = hi.cwiseMax(c);
  }
  // The tests' views cover most of the image.
  EXPECT_LT(lo.x(), 0.2 * truth.width);
  EXPECT_GT(hi.x(), 0.8 * truth.width);
  EXPECT_LT(lo.y(), 0.2 * truth.height);
  EXPECT_GT(hi.y(), 0.8 * truth.height);
  const auto a = makeCameraModel(got), b = makeCameraModel(truth);
  double worst = 0;
  for (double y = lo.y(); y <= hi.y(); y += 10)
    for (double x = lo.x(); x <= hi.x(); x += 10) {
      Eigen::Vector3d ray;
      ASSERT_TRUE(b->unproject(Eigen::Vector2d(x, y), &ray));
      worst = std::max(worst, (distortionShift(*a, ray) - distortionShift(*b, ray)).norm());
    }
  EXPECT_LT(worst, px_tolerance) << "largest difference of the distortion's effect";
}

CameraCalibrationResult calibrate(const Scenario& s, const BoardSpec& spec,
                                  const std::vector<BoardView>& views) {
  CameraCalibrationOptions o;
  o.model = s.truth.model;
  auto r = calibrateCamera(views, test::kWidth, test::kHeight, o, "views");
  EXPECT_EQ(r.views.size(), views.size());
  (void)spec;
  return r;
}

TEST(CameraCalibration, RadTanFromChessboard) {
  const Scenario s{test::radTanCamera(), BoardType::Chessboard, 12, 0.45};
  const BoardSpec spec = test::boardSpec(s.board);
  const auto r = calibrate(s, spec, renderViews(s, spec));
  EXPECT_EQ(r.used_views, 12);
  EXPECT_LT(r.rms_px, 0.2);
  expectIntrinsics(r, s.truth, 0.5);
  EXPECT_EQ(r.calibration.output.mode, OutputMode::Crop);
  for (const auto& v : r.views) {
    EXPECT_EQ(v.status, ViewStatus::Used) << v.name << ": " << v.reason;
    EXPECT_LT(v.rms_px, 0.3) << v.name;
    EXPECT_EQ(v.corners, 40);
  }
  EXPECT_EQ(r.corners.size(), 12u * 40u);
}

TEST(CameraCalibration, PinholeFromChessboard) {
  const Scenario s{test::pinholeCamera(), BoardType::Chessboard, 8, 0.45};
  const BoardSpec spec = test::boardSpec(s.board);
  const auto r = calibrate(s, spec, renderViews(s, spec));
  EXPECT_EQ(r.used_views, 8);
  EXPECT_LT(r.rms_px, 0.2);
  expectIntrinsics(r, s.truth, 0.5);
  EXPECT_EQ(r.calibration.output.mode, OutputMode::None);
}

TEST(CameraCalibration, EquidistantFromChessboard) {
  const Scenario s{test::equidistantCamera(), BoardType::Chessboard, 12, 0.28};
  const BoardSpec spec = test::boardSpec(s.board);
  const auto r = calibrate(s, spec, renderViews(s, spec));
  EXPECT_GE(r.used_views, 10);
  EXPECT_LT(r.rms_px, 0.2);
  expectIntrinsics(r, s.truth, 0.5);
}

TEST(CameraCalibration, RadTanFromCharuco) {
  const Scenario s{test::radTanCamera(), BoardType::Charuco, 12, 0.5};
  const BoardSpec spec = test::boardSpec(s.board);
  const auto r = calibrate(s, spec, renderViews(s, spec));
  EXPECT_GE(r.used_views, 10);
  EXPECT_LT(r.rms_px, 0.25);
  expectIntrinsics(r, s.truth, 0.6);
}

TEST(CameraCalibration, WritesFilesThatReadBackToTheResult) {
  const Scenario s{test::radTanCamera(), BoardType::Chessboard, 8, 0.45};
  const BoardSpec spec = test::boardSpec(s.board);
  const auto r = calibrate(s, spec, renderViews(s, spec));
  const std::string dir = test::scratchDir("calibration_camera_files");
  writeDsoCameraFile(dir + "/camera.txt", r.calibration);
  writeKalibrCameraYaml(dir + "/camchain.yaml", r.calibration);
  for (const auto& back :
       {readDsoCameraFile(dir + "/camera.txt"), readKalibrCameraYaml(dir + "/camchain.yaml")}) {
    EXPECT_EQ(back.input.model, r.calibration.input.model);
    EXPECT_EQ(back.input.fx, r.calibration.input.fx);
    EXPECT_EQ(back.input.cy, r.calibration.input.cy);
    EXPECT_EQ(back.input.distortion, r.calibration.input.distortion);
    EXPECT_EQ(back.output.mode, OutputMode::Crop);
    EXPECT_EQ(back.output.width, test::kWidth);
  }
}

TEST(CameraCalibration, RejectsBlurredAndDuplicateViews) {
  const Scenario s{test::radTanCamera(), BoardType::Chessboard, 8, 0.45};
  const BoardSpec spec = test::boardSpec(s.board);
  const auto target = test::targetFor(spec);
  const auto camera = makeCameraModel(s.truth);
  auto views = renderViews(s, spec);
  const auto poses = test::boardPoses(target, *camera, 8, 0.45);
  // View 8: view 2 again with another noise pattern and the camera moved by 2 mm (duplicate).
  Pose moved = poses[2];
  moved.translation.x() += 0.002;
  views.push_back(test::renderView(spec, target, *camera, moved, 8));
  // View 9: view 5 blurred by 2.5 px (motion or focus blur), still detected.
  views.push_back(test::renderView(spec, target, *camera, poses[5], 9, 2.5));
  ASSERT_TRUE(views[8].observation && views[9].observation);
  // View 10: no board.
  views.push_back(BoardView{"empty.png", std::nullopt});

  const auto r = calibrate(s, spec, views);
  EXPECT_EQ(r.used_views, 8);
  // Of the two near-identical views the sharper one is kept; the other names it.
  const bool second_dropped = r.views[8].status == ViewStatus::Duplicate;
  const ViewReport& dropped = r.views[second_dropped ? 8 : 2];
  EXPECT_EQ(dropped.status, ViewStatus::Duplicate);
  EXPECT_EQ(r.views[second_dropped ? 2 : 8].status, ViewStatus::Used);
  EXPECT_NE(dropped.reason.find(second_dropped ? "view2.png" : "view8.png"), std::string::npos)
      << dropped.reason;
  EXPECT_EQ(r.views[9].status, ViewStatus::Blurred);
  EXPECT_NE(r.views[9].reason.find("edge blur"), std::string::npos) << r.views[9].reason;
  EXPECT_GT(r.views[9].blur_px, 2.0);
  EXPECT_EQ(r.views[10].status, ViewStatus::NoBoard);
  for (int i : {0, 1, 3, 4, 5, 6, 7})
    EXPECT_EQ(r.views[static_cast<std::size_t>(i)].status, ViewStatus::Used);
  expectIntrinsics(r, s.truth, 0.5);
}

TEST(CameraCalibration, DropsAViewWithWrongCorners) {
  const Scenario s{test::radTanCamera(), BoardType::Chessboard, 8, 0.45};
  const BoardSpec spec = test::boardSpec(s.board);
  auto views = renderViews(s, spec);
  // A mislabelled detection: corners shuffled within rows.
  auto& pts = views[3].observation->image_points;
  for (std::size_t k = 0; k + 1 < pts.size(); k += 2) std::swap(pts[k], pts[k + 1]);
  const auto r = calibrate(s, spec, views);
  EXPECT_EQ(r.views[3].status, ViewStatus::Outlier) << r.views[3].reason;
  EXPECT_EQ(r.used_views, 7);
  expectIntrinsics(r, s.truth, 0.5);
}

TEST(CameraCalibration, TooFewViewsSaysWhatToDo) {
  const Scenario s{test::radTanCamera(), BoardType::Chessboard, 3, 0.45};
  const BoardSpec spec = test::boardSpec(s.board);
  auto views = renderViews(s, spec);
  views.push_back(BoardView{"blank.png", std::nullopt});
  try {
    calibrate(s, spec, views);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("views: only 3 of 4 images are usable", 0), 0u) << what;
    EXPECT_NE(what.find("no board: 1"), std::string::npos) << what;
    EXPECT_NE(what.find("at least 5"), std::string::npos) << what;
    EXPECT_NE(what.find("take more pictures"), std::string::npos) << what;
  }
}

TEST(CameraCalibration, BoardNotFoundAnywhereSaysWhatToCheck) {
  std::vector<BoardView> views(6);
  for (std::size_t i = 0; i < views.size(); ++i) views[i].name = "img" + std::to_string(i);
  try {
    calibrateCamera(views, test::kWidth, test::kHeight, {}, "dir");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind("dir: the board was not found in any of the 6 images", 0), 0u) << what;
    EXPECT_NE(what.find("count squares (not inner corners)"), std::string::npos) << what;
  }
}

TEST(CameraCalibration, BadArguments) {
  std::vector<BoardView> views(1);
  CameraCalibrationOptions o;
  o.model = CameraModelType::Fov;
  EXPECT_THROW(calibrateCamera(views, 320, 240, o, "x"), ConfigError);
  EXPECT_THROW(calibrateCamera(views, 0, 240, {}, "x"), ConfigError);
  // An observation from an image of another size.
  const Scenario s{test::pinholeCamera(), BoardType::Chessboard, 1, 0.45};
  auto one = renderViews(s, test::boardSpec(s.board));
  EXPECT_THROW(calibrateCamera(one, 640, 480, {}, "x"), InputError);
}

}  // namespace
}  // namespace ldsm::calib
