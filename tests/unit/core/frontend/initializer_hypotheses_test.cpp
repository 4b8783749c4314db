// InitializerHypotheses: several starting guesses on one reference, the lowest photometric
// energy wins. The case it exists for is the start of the synthetic corridor loop, where the
// initializer starting at rest settles on a translation about 30 degrees off with a yaw of the
// wrong sign (a rotation/translation ambiguity of small baselines), and it must still refuse a
// camera without parallax.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "frontend/initializer_hypotheses.h"
#include "init_test_util.h"
#include "ldsm/drivers/sim/sim_source.h"
#include "ldsm/error.h"
#include "test_paths.h"

namespace ldsm {
namespace {

constexpr double kRadToDeg = 57.29577951308232;

struct MotionError {
  double rotation_deg = 180.0;   ///< angle of R_est^-1 R_true
  double direction_deg = 180.0;  ///< angle between the translation directions
};

template <typename Initializer>
MotionError errorAgainstTruth(const Initializer& init, const SE3d& T_frame_ref_true) {
  const InitializationResult& r = init.result();
  MotionError e;
  e.rotation_deg =
      (r.T_frame_ref.so3().inverse() * T_frame_ref_true.so3()).log().norm() * kRadToDeg;
  const Eigen::Vector3d a = r.T_frame_ref.translation().normalized();
  const Eigen::Vector3d b = T_frame_ref_true.translation().normalized();
  e.direction_deg = std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * kRadToDeg;
  return e;
}

SE3d toSE3(const Pose& p) {
  return SE3d(p.rotation, p.translation);
}

/// Feeds the first frames of the "loop" scene (linear response, no vignette, so that the images
/// are irradiance up to a gain) until `init` completes; returns the error of its result against
/// the rendered motion, or nothing when it never completed.
template <typename Initializer>
std::optional<MotionError> initialiseOnLoopCorridor(Initializer& init, int* frames_used,
                                                    int start = 0) {
  drivers::sim::SimOptions o;
  o.frames = 20 + start;
  o.response = drivers::sim::SimResponse::Linear;
  o.vignette = 0.0;
  drivers::sim::SimSource source("loop", o);
  source.seek(start);
  const PinholeIntrinsics& K = source.intrinsics();
  ImagePyramid pyramid(K.width, K.height, 5);
  ImageF image(K.width, K.height);
  drivers::Frame frame;
  while (source.next(frame)) {
    for (int y = 0; y < K.height; ++y)
      for (int x = 0; x < K.width; ++x) image(x, y) = frame.image(x, y);
    pyramid.build(image.view());
    if (init.addFrame(pyramid, 1.0)) {
      *frames_used = static_cast<int>(frame.index);
      const Trajectory& gt = source.groundTruth();
      const SE3d T_w_ref = toSE3(gt[static_cast<std::size_t>(start)].pose);
      const SE3d T_w_frame = toSE3(gt[static_cast<std::size_t>(frame.index)].pose);
      return errorAgainstTruth(init, T_w_frame.inverse() * T_w_ref);
    }
  }
  return std::nullopt;
}

PyramidCamera loopCamera() {
  drivers::sim::SimOptions o;
  o.frames = 1;
  return PyramidCamera(drivers::sim::SimSource("loop", o).intrinsics(), 5);
}

TEST(InitializerHypotheses, CorridorStartFindsTheTrueMotion) {
  if (std::getenv("LDSM_TRACE")) spdlog::set_level(spdlog::level::trace);
  const PyramidCamera camera = loopCamera();
  const CoarseInitializerSettings settings;

  // Premise: starting at rest alone lands in the wrong basin here.
  CoarseInitializer single(camera, settings);
  int single_frames = 0;
  const std::optional<MotionError> at_rest = initialiseOnLoopCorridor(single, &single_frames);
  ASSERT_TRUE(at_rest.has_value());
  std::printf("at rest only: frame %d, rotation error %.3f deg, direction error %.2f deg\n",
              single_frames, at_rest->rotation_deg, at_rest->direction_deg);
  EXPECT_GT(at_rest->direction_deg, 10.0) << "premise: the single start no longer fails here";

  InitializerHypotheses multi(camera, settings, InitializerHypotheses::kMaxHypotheses);
  int multi_frames = 0;
  const std::optional<MotionError> chosen = initialiseOnLoopCorridor(multi, &multi_frames);
  ASSERT_TRUE(chosen.has_value());
  std::printf(
      "7 hypotheses: frame %d, leader %d, rotation error %.3f deg, direction error %.2f "
      "deg\n",
      multi_frames, multi.leader(), chosen->rotation_deg, chosen->direction_deg);
  EXPECT_NE(multi.leader(), 0);
  EXPECT_LT(chosen->rotation_deg, 0.1);
  EXPECT_LT(chosen->direction_deg, 2.0);
  EXPECT_LE(multi_frames, single_frames + 3);
}

// Started a few frames later, the first frame's parallax (about 3 px) can take every seed into
// the wrong basins: started at frame 3 of the loop, the seven hypotheses end in two wrong ones
// after the first frame and the winner is 30 degrees off (a whole 300-frame run from there: ATE
// 0.45 m). The second chance restarts the dropped seeds once the leader sees real parallax, and
// the initialisation starts over when its leading hypothesis fails. Measured over starts 0-24:
// before, 4 of 25 starts (1, 2, 3, 5) completed 26-31 degrees off; without the second chance
// (but starting over when the leader fails) 3; with both none (largest errors 2.3 degrees in
// direction, 0.65 in rotation); starts 1-6 are the hard ones.
TEST(InitializerHypotheses, LaterStartsFindTheTrueMotionWithTheSecondChance) {
  if (std::getenv("LDSM_TRACE")) spdlog::set_level(spdlog::level::trace);
  const PyramidCamera camera = loopCamera();
  const CoarseInitializerSettings settings;
  {
    // Premise: without the second chance the start at frame 3 ends in a wrong basin.
    InitializerHypotheses multi(camera, settings, InitializerHypotheses::kMaxHypotheses);
    multi.setSecondChance(false);
    int frames = 0;
    const std::optional<MotionError> chosen = initialiseOnLoopCorridor(multi, &frames, 3);
    ASSERT_TRUE(chosen.has_value());
    EXPECT_GT(chosen->direction_deg, 10.0) << "premise: start 3 no longer fails without it";
  }
  for (int start = 1; start <= 6; ++start) {
    InitializerHypotheses multi(camera, settings, InitializerHypotheses::kMaxHypotheses);
    int frames = 0;
    const std::optional<MotionError> chosen = initialiseOnLoopCorridor(multi, &frames, start);
    ASSERT_TRUE(chosen.has_value()) << start;
    std::printf(
        "start %d: completed at frame %d, leader %d, rotation error %.3f deg, direction "
        "error %.2f deg\n",
        start, frames, multi.leader(), chosen->rotation_deg, chosen->direction_deg);
    EXPECT_LT(chosen->rotation_deg, 1.0) << "start " << start;
    EXPECT_LT(chosen->direction_deg, 5.0) << "start " << start;
  }
}

TEST(InitializerHypotheses, ParallelTasksGiveTheSameResultBitForBit) {
  // The hypotheses of a frame run as parallel tasks (system.parallel_threads): each touches only
  // its own state, so the result must equal the one-thread result exactly.
  const PyramidCamera camera = loopCamera();
  const CoarseInitializerSettings settings;
  InitializerHypotheses serial(camera, settings, InitializerHypotheses::kMaxHypotheses);
  int serial_frames = 0;
  ASSERT_TRUE(initialiseOnLoopCorridor(serial, &serial_frames).has_value());
  for (int threads : {2, 3}) {
    concurrency::ParallelTasks tasks(threads);
    InitializerHypotheses parallel(camera, settings, InitializerHypotheses::kMaxHypotheses);
    parallel.setParallelTasks(&tasks);
    int parallel_frames = 0;
    ASSERT_TRUE(initialiseOnLoopCorridor(parallel, &parallel_frames).has_value()) << threads;
    EXPECT_EQ(parallel_frames, serial_frames) << threads;
    EXPECT_EQ(parallel.leader(), serial.leader()) << threads;
    const InitializationResult& a = serial.result();
    const InitializationResult& b = parallel.result();
    EXPECT_EQ(b.T_frame_ref.matrix(), a.T_frame_ref.matrix()) << threads;
    ASSERT_EQ(b.points.size(), a.points.size()) << threads;
    for (std::size_t i = 0; i < a.points.size(); ++i) {
      ASSERT_EQ(b.points[i].u, a.points[i].u) << i;
      ASSERT_EQ(b.points[i].v, a.points[i].v) << i;
      ASSERT_EQ(b.points[i].idepth, a.points[i].idepth) << i;
      ASSERT_EQ(b.points[i].hessian, a.points[i].hessian) << i;
    }
  }
}

TEST(InitializerHypotheses, SeedsAreRestAndSignedAxes) {
  EXPECT_EQ(InitializerHypotheses::seed(0), Eigen::Vector3d::Zero());
  for (int i = 1; i < InitializerHypotheses::kMaxHypotheses; ++i) {
    const Eigen::Vector3d s = InitializerHypotheses::seed(i);
    EXPECT_NEAR(s.norm(), InitializerHypotheses::kSeedLength, 1e-15) << i;
    EXPECT_EQ((s.array() != 0.0).count(), 1) << i;
    for (int j = 1; j < i; ++j) EXPECT_NE(s, InitializerHypotheses::seed(j)) << i << " " << j;
  }
}

TEST(InitializerHypotheses, InvalidCountIsAConfigError) {
  const PinholeIntrinsics K = init_test::makeIntrinsics(160, 120, 120);
  EXPECT_THROW(InitializerHypotheses(PyramidCamera(K, 4), {}, 0), ConfigError);
  EXPECT_THROW(InitializerHypotheses(PyramidCamera(K, 4), {}, 8), ConfigError);
  EXPECT_NO_THROW(InitializerHypotheses(PyramidCamera(K, 4), {}, 1));
}

/// The synthetic wall-and-floor scene with an initializer of all seven hypotheses for it.
struct WallAndFloorStart {
  PinholeIntrinsics K = init_test::makeIntrinsics(320, 240, 250);
  init_test::InitScene scene = init_test::wallAndFloorScene();
  InitializerHypotheses init{PyramidCamera(K, 5), {}, InitializerHypotheses::kMaxHypotheses};
  ImagePyramid pyramid{K.width, K.height, 5};
};

/// A static, vibrating camera: no hypothesis may complete or even snap.
TEST(InitializerHypotheses, StaticCameraNeverInitialises) {
  WallAndFloorStart s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-1.0, 1.0);
  for (int i = 0; i < 60; ++i) {
    const Eigen::Vector3d w(jitter(rng), jitter(rng), jitter(rng));
    const Eigen::Vector3d t(jitter(rng), jitter(rng), jitter(rng));
    const SE3d pose(SO3d::exp(w * (0.05 / kRadToDeg)), t * 0.001);
    s.pyramid.build(s.scene.render(pose, s.K, 1, 2.f, &rng).view());
    EXPECT_FALSE(s.init.addFrame(s.pyramid, 1.0)) << i;
    EXPECT_FALSE(s.init.failed()) << i;
    EXPECT_NE(s.init.status(), InitStatus::kConfirming) << i;
  }
  EXPECT_EQ(s.init.framesTracked(), 59);
}

/// Pure rotation: no hypothesis finds rotation-free parallax.
TEST(InitializerHypotheses, PanningCameraNeverInitialises) {
  WallAndFloorStart s;
  std::mt19937 rng(3);
  for (int i = 0; i < 60; ++i) {
    const SE3d pose(SO3d::exp(Eigen::Vector3d(0.1 * i, 0.4 * i, 0) / kRadToDeg),
                    Eigen::Vector3d::Zero());
    s.pyramid.build(s.scene.render(pose, s.K, 1, 1.5f, &rng).view());
    EXPECT_FALSE(s.init.addFrame(s.pyramid, 1.0)) << i;
  }
}

TEST(InitializerHypotheses, EurocDroneStandingStillNeverInitialises) {
  const std::vector<std::string> files = init_test::eurocStandingStillFrames();
  if (files.empty()) GTEST_SKIP() << "../shared/data absent: euroc_v101_static95 not available";
  ASSERT_GE(files.size(), 90u);
  const PinholeIntrinsics K = init_test::eurocCam0();
  InitializerHypotheses init(PyramidCamera(K, 5), {}, InitializerHypotheses::kMaxHypotheses);
  ImagePyramid pyramid(K.width, K.height, 5);
  ImageF image(K.width, K.height);
  int snaps = 0;
  for (const std::string& f : files) {
    ASSERT_TRUE(init_test::readGrey(f, image)) << f;
    pyramid.build(image.view());
    EXPECT_FALSE(init.addFrame(pyramid, 1.0)) << f;
    if (init.status() == InitStatus::kConfirming) ++snaps;
  }
  EXPECT_EQ(snaps, 0);
}

/// An unrelated image after the reference makes every hypothesis fail; the next frame is a new
/// reference.
TEST(InitializerHypotheses, AllFailingReportsFailureAndRestarts) {
  WallAndFloorStart s;
  std::mt19937 rng(5);
  s.pyramid.build(s.scene.render(SE3d(), s.K, 1, 1.f, &rng).view());
  EXPECT_FALSE(s.init.addFrame(s.pyramid, 1.0));
  EXPECT_EQ(s.init.alive(), InitializerHypotheses::kMaxHypotheses);
  s.pyramid.build(s.scene.render(SE3d(SO3d(), {0.01, 0, 0}), s.K, 1, 1.f, &rng).view());
  EXPECT_FALSE(s.init.addFrame(s.pyramid, 1.0));
  EXPECT_FALSE(s.init.failed());
  // A different scene: most points cannot be matched by any hypothesis.
  init_test::InitScene other;
  other.addPlane({0, 0, 2.0}, {0, 0, -1}, 99U);
  s.pyramid.build(other.render(SE3d(), s.K, 1, 1.f, &rng).view());
  EXPECT_FALSE(s.init.addFrame(s.pyramid, 1.0));
  EXPECT_TRUE(s.init.failed());
  EXPECT_NE(s.init.failure(), InitFailure::kNone);
  EXPECT_EQ(s.init.alive(), 0);
  s.pyramid.build(other.render(SE3d(), s.K, 1, 1.f, &rng).view());
  EXPECT_FALSE(s.init.addFrame(s.pyramid, 1.0));
  EXPECT_EQ(s.init.framesTracked(), 0);
  EXPECT_EQ(s.init.alive(), InitializerHypotheses::kMaxHypotheses);
}

/// Feeds frames `indices` of the "forward" scene (the first is the reference) to `init` as a
/// busy live initializer sees them, each with its timestamp and, when `tell`, whether frames
/// were skipped before it; returns the error of the result against the rendered motion, or
/// nothing when it never completed.
std::optional<MotionError> initialiseOnForwardDrive(InitializerHypotheses& init,
                                                    const std::vector<int>& indices, bool tell,
                                                    int* completed_at,
                                                    const std::vector<int>& shown = {}) {
  drivers::sim::SimOptions o;
  o.frames = indices.back() + 1;
  o.response = drivers::sim::SimResponse::Linear;
  o.vignette = 0.0;
  drivers::sim::SimSource source("forward", o);
  const PinholeIntrinsics& K = source.intrinsics();
  std::vector<drivers::Frame> frames;
  for (drivers::Frame f; source.next(f);) frames.push_back(std::move(f));
  ImagePyramid pyramid(K.width, K.height, 5);
  ImageF image(K.width, K.height);
  const Trajectory& gt = source.groundTruth();
  for (std::size_t k = 0; k < indices.size(); ++k) {
    const auto i = static_cast<std::size_t>(shown.empty() ? indices[k] : shown[k]);
    const auto when = static_cast<std::size_t>(indices[k]);
    for (int y = 0; y < K.height; ++y)
      for (int x = 0; x < K.width; ++x) image(x, y) = frames[i].image(x, y);
    pyramid.build(image.view());
    const bool skipped = k > 0 && indices[k] > indices[k - 1] + 1;
    if (init.addFrame(pyramid, 1.0, frames[when].timestamp, tell && skipped)) {
      *completed_at = indices[k];
      const auto ref = static_cast<std::size_t>(indices[0]);
      return errorAgainstTruth(init, toSE3(gt[i].pose).inverse() * toSE3(gt[ref].pose));
    }
  }
  return std::nullopt;
}

// A live initializer busy with one frame while the camera takes the next ones sees frames far
// apart (CI's slow machine: about every twentieth of a 30 Hz drive). From its last estimate alone
// a frame six or eight frames of forward driving on is beyond its reach: measured on these four
// frame patterns over 100 frames, it completed only 37-74 frames in, 80-107 degrees off in
// translation direction and 6-24 degrees in rotation. Told that frames went by, the hypotheses
// that see real parallax continue their motion for the time that passed, and the initialisation
// is right within a few frames (0.01 degrees, 0.02-0.09 degrees).
TEST(InitializerHypotheses, FramesFarApartAreBridgedByContinuingTheMotion) {
  drivers::sim::SimOptions o;
  o.frames = 1;
  const PyramidCamera camera(drivers::sim::SimSource("forward", o).intrinsics(), 5);
  const CoarseInitializerSettings settings;
  for (const auto& [first, gap] :
       {std::pair{1, 6}, std::pair{2, 6}, std::pair{2, 8}, std::pair{3, 8}}) {
    std::vector<int> indices{0, first};
    for (int k = 1; k <= 4; ++k) indices.push_back(first + k * gap);
    InitializerHypotheses blind(camera, settings, InitializerHypotheses::kMaxHypotheses);
    int blind_at = -1;
    const std::optional<MotionError> e_blind =
        initialiseOnForwardDrive(blind, indices, /*tell=*/false, &blind_at);
    EXPECT_TRUE(!e_blind || e_blind->direction_deg > 10.0)
        << "premise: frames " << gap << " apart no longer defeat it (first " << first << ")";
    InitializerHypotheses told(camera, settings, InitializerHypotheses::kMaxHypotheses);
    int told_at = -1;
    const std::optional<MotionError> e_told =
        initialiseOnForwardDrive(told, indices, /*tell=*/true, &told_at);
    ASSERT_TRUE(e_told.has_value()) << first << " " << gap;
    std::printf(
        "first %d, then every %d: told, complete at frame %d, %.2f / %.2f deg rotation / "
        "direction error\n",
        first, gap, told_at, e_told->rotation_deg, e_told->direction_deg);
    EXPECT_LT(e_told->rotation_deg, 1.0) << first << " " << gap;
    EXPECT_LT(e_told->direction_deg, 2.0) << first << " " << gap;
  }
}

// The other side of continuing the motion: the camera stops while the initializer is busy, and
// the continued guess overshoots. Measured (forward drive stopping at frame 4, 6, 8 or 10, the
// initializer seeing every 2nd, 4th or 6th frame): every initialisation that completed was right
// (under 0.1 degrees of rotation, 0.6 of direction); one (stop 6, every 6th) did not initialise
// at all (the hypotheses failed on the overshoot, and a stopped camera gives a new reference no
// parallax), where without the continuation it completed right at frame 12.
TEST(InitializerHypotheses, ACameraThatStopsIsNeverInitialisedWrong) {
  drivers::sim::SimOptions o;
  o.frames = 1;
  const PyramidCamera camera(drivers::sim::SimSource("forward", o).intrinsics(), 5);
  int completed = 0;
  for (const auto& [stop, gap] : {std::pair{4, 4}, std::pair{6, 6}, std::pair{8, 4}}) {
    std::vector<int> when{0}, shown{0};
    for (int t = gap; t <= 36; t += gap) {
      when.push_back(t);
      shown.push_back(std::min(t, stop));  // the images stop changing at `stop`
    }
    InitializerHypotheses init(camera, CoarseInitializerSettings(),
                               InitializerHypotheses::kMaxHypotheses);
    int at = -1;
    const std::optional<MotionError> e =
        initialiseOnForwardDrive(init, when, /*tell=*/true, &at, shown);
    if (!e) continue;  // not initialised: no harm
    ++completed;
    EXPECT_LT(e->rotation_deg, 1.0) << "stop " << stop << ", every " << gap << ", at " << at;
    EXPECT_LT(e->direction_deg, 2.0) << "stop " << stop << ", every " << gap << ", at " << at;
  }
  // Stopping after real parallax (frames 4 and 8, every 4th frame seen) still initialises.
  EXPECT_GE(completed, 2);
}

}  // namespace
}  // namespace ldsm
