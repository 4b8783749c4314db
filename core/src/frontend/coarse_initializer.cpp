#include "frontend/coarse_initializer.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "image/interpolation.h"
#include "ldsm/error.h"

namespace ldsm {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw ConfigError("coarse initializer: " + what);
}

bool finitePose(const SE3d& T) {
  return T.translation().allFinite() && T.quaternion().coeffs().allFinite();
}

}  // namespace

void CoarseInitializerSettings::validate() const {
  require(max_levels >= 1 && max_levels <= kMaxPyramidLevels,
          "max_levels must be in [1, " + std::to_string(kMaxPyramidLevels) + "]");
  require(min_coarsest_size >= 2 * kPatternPadding + 4, "min_coarsest_size too small");
  for (int l = 0; l < kMaxPyramidLevels; ++l) {
    require(cell_size[l] >= 1 && cell_size[l] <= 64, "cell_size must be in [1, 64]");
    require(max_iterations[l] >= 0 && max_iterations[l] <= 1000,
            "max_iterations must be in [0, 1000]");
  }
  require(min_gradient >= 0.f && std::isfinite(min_gradient), "min_gradient must be >= 0");
  require(selector_density > 0.f && std::isfinite(selector_density),
          "selector_density must be > 0");
  require(neighbours >= 1 && neighbours <= kMaxNeighbours,
          "neighbours must be in [1, " + std::to_string(kMaxNeighbours) + "]");
  require(initial_lambda > 0 && initial_lambda < 1e6, "initial_lambda must be in (0, 1e6)");
  require(convergence_energy_fraction >= 0 && convergence_energy_fraction < 1,
          "convergence_energy_fraction must be in [0, 1)");
  require(huber_threshold > 0.f && std::isfinite(huber_threshold), "huber_threshold must be > 0");
  require(gradient_weight_c >= 0.f && std::isfinite(gradient_weight_c),
          "gradient_weight_c must be >= 0");
  require(outlier_rms > 0.f && std::isfinite(outlier_rms), "outlier_rms must be > 0");
  require(smoothness_weight >= 0.f && std::isfinite(smoothness_weight) &&
              smoothness_weight_parallax >= 0.f && std::isfinite(smoothness_weight_parallax),
          "smoothness weights must be >= 0");
  require(idepth_prior_weight > 0.f && std::isfinite(idepth_prior_weight),
          "idepth_prior_weight must be > 0");
  require(affine_prior_weight_a >= 0.f && affine_prior_weight_b >= 0.f &&
              std::isfinite(affine_prior_weight_a) && std::isfinite(affine_prior_weight_b),
          "affine prior weights must be >= 0");
  require(min_parallax_flow > 0.f && std::isfinite(min_parallax_flow),
          "min_parallax_flow must be > 0");
  require(min_rotation_free_parallax >= 0.f && min_rotation_free_parallax <= min_parallax_flow,
          "min_rotation_free_parallax must be in [0, min_parallax_flow]");
  require(max_snap_rms > 0.f && fail_rms >= max_snap_rms, "need 0 < max_snap_rms <= fail_rms");
  require(min_snap_good_fraction >= 0.f && min_snap_good_fraction <= 1.f &&
              min_good_fraction >= 0.f && min_good_fraction <= min_snap_good_fraction,
          "need 0 <= min_good_fraction <= min_snap_good_fraction <= 1");
  require(confirm_frames >= 0 && confirm_frames <= 1000, "confirm_frames must be in [0, 1000]");
  require(max_nonpositive_fraction >= 0.f && max_nonpositive_fraction <= 1.f,
          "max_nonpositive_fraction must be in [0, 1]");
  require(max_idepth_spread > 1.f, "max_idepth_spread must be > 1");
  require(min_points >= 1, "min_points must be >= 1");
  require(max_residual_growth > 1.f && std::isfinite(max_residual_growth),
          "max_residual_growth must be > 1");
  require(residual_growth_floor >= 0.f && std::isfinite(residual_growth_floor),
          "residual_growth_floor must be >= 0");
}

const char* toString(InitStatus status) {
  switch (status) {
    case InitStatus::kNoReference:
      return "no reference";
    case InitStatus::kWaitingForParallax:
      return "waiting for parallax";
    case InitStatus::kConfirming:
      return "confirming";
    case InitStatus::kComplete:
      return "complete";
    case InitStatus::kFailed:
      return "failed";
  }
  return "?";
}

const char* toString(InitFailure failure) {
  switch (failure) {
    case InitFailure::kNone:
      return "none";
    case InitFailure::kTooFewPoints:
      return "too few textured points in the reference";
    case InitFailure::kLostTrack:
      return "too few points tracked";
    case InitFailure::kResidualTooLarge:
      return "photometric residual too large";
    case InitFailure::kNotFinite:
      return "estimate not finite";
    case InitFailure::kDegenerateDepths:
      return "degenerate inverse-depth distribution";
  }
  return "?";
}

CoarseInitializer::CoarseInitializer(const PyramidCamera& camera,
                                     const CoarseInitializerSettings& settings)
    : settings_(settings), camera_(camera) {
  settings_.validate();
  if (camera.levels() < 1 || camera[0].width <= 0 || camera[0].height <= 0) {
    throw InputError("coarse initializer: the camera has no levels or a non-positive size");
  }
  width_ = camera[0].width;
  height_ = camera[0].height;
}

void CoarseInitializer::reset() {
  status_ = InitStatus::kNoReference;
  failure_ = InitFailure::kNone;
  frames_ = 0;
  snapped_frames_ = 0;
  lowest_rms_ = 0;
  stats_ = InitFrameStats{};
}

void CoarseInitializer::checkFrame(const ImagePyramid& pyramid, double exposure) const {
  if (pyramid.levels() < 1 || pyramid.width(0) != width_ || pyramid.height(0) != height_) {
    throw InputError("coarse initializer: frame is " +
                     (pyramid.levels() < 1 ? std::string("empty")
                                           : std::to_string(pyramid.width(0)) + "x" +
                                                 std::to_string(pyramid.height(0))) +
                     ", the camera is " + std::to_string(width_) + "x" + std::to_string(height_));
  }
  const bool tracking = status_ == InitStatus::kWaitingForParallax ||
                        status_ == InitStatus::kConfirming || status_ == InitStatus::kComplete;
  if (tracking && pyramid.levels() < levels_) {
    throw InputError("coarse initializer: frame pyramid has " + std::to_string(pyramid.levels()) +
                     " levels, the reference had " + std::to_string(levels_));
  }
  if (!(exposure > 0.0) || !std::isfinite(exposure)) {
    throw InputError("coarse initializer: exposure must be a positive finite number (got " +
                     std::to_string(exposure) + ")");
  }
}

bool CoarseInitializer::addFrame(const ImagePyramid& pyramid, double exposure) {
  checkFrame(pyramid, exposure);
  if (status_ != InitStatus::kWaitingForParallax && status_ != InitStatus::kConfirming &&
      status_ != InitStatus::kComplete) {
    setReference(pyramid, exposure);
    return false;
  }
  trackFrame(pyramid, exposure);
  ++frames_;
  decide();
  return status_ == InitStatus::kComplete;
}

bool CoarseInitializer::continueMotion(double scale) {
  if (status_ != InitStatus::kConfirming || !std::isfinite(scale) || !(scale > 1.0)) return false;
  const SE3d guess = interpolateGeodesic(SE3d(), T_, scale);
  if (!finitePose(guess)) return false;
  T_ = guess;
  return true;
}

void CoarseInitializer::releaseMemory() {
  reset();
  for (Level& L : levels_data_) L = Level{};
  levels_ = 0;
  std::vector<float>().swap(sort_scratch_);
  selector_.reset();
  std::vector<SelectedPixel>().swap(selected_);
  std::vector<InitializedPoint>().swap(result_.points);
}

void CoarseInitializer::adoptReference(const CoarseInitializer& primary,
                                       const Eigen::Vector3d& seed) {
  if (&primary == this) return;
  if (primary.width_ != width_ || primary.height_ != height_ || primary.frames_ != 0 ||
      primary.status_ != InitStatus::kWaitingForParallax || !seed.allFinite()) {
    throw InputError("coarse initializer: can only adopt a fresh reference of the same size");
  }
  reset();
  levels_ = primary.levels_;
  for (int lvl = 0; lvl < levels_; ++lvl) levels_data_[lvl] = primary.levels_data_[lvl];
  exposure_ref_ = primary.exposure_ref_;
  T_ = SE3d(SO3d(), seed);
  affine_ = AffineLight{};
  sort_scratch_.reserve(levels_data_[0].u.size());
  result_.points.reserve(levels_data_[0].u.size());
  status_ = InitStatus::kWaitingForParallax;
}

void CoarseInitializer::resetEstimates(Level& L) {
  const std::size_t n = L.u.size();
  const PointLinearization zero{Eigen::Matrix<float, 8, 1>::Zero(), 0.f, 0.f, 0.f, 0.f};
  L.idepth.assign(n, 1.f);
  L.idepth_trial.assign(n, 1.f);
  L.ir.assign(n, 1.f);
  L.ir_trial.assign(n, 1.f);
  L.lin.assign(n, zero);
  L.lin_trial.assign(n, zero);
  L.good.assign(n, 0);
  L.good_trial.assign(n, 0);
  L.accum_w.assign(n, 0.f);
  L.accum_wd.assign(n, 0.f);
}

void CoarseInitializer::restartFrom(const CoarseInitializer& source, const SE3d& start) {
  if (&source == this) return;
  const bool tracking = source.status_ == InitStatus::kWaitingForParallax ||
                        source.status_ == InitStatus::kConfirming ||
                        source.status_ == InitStatus::kComplete;
  if (source.width_ != width_ || source.height_ != height_ || !tracking || !finitePose(start)) {
    throw InputError(
        "coarse initializer: can only restart from a tracked reference of the same "
        "size, with a finite motion guess");
  }
  reset();
  levels_ = source.levels_;
  for (int lvl = 0; lvl < levels_; ++lvl) {
    levels_data_[lvl] = source.levels_data_[lvl];
    resetEstimates(levels_data_[lvl]);
  }
  exposure_ref_ = source.exposure_ref_;
  T_ = start;
  affine_ = source.affine_;
  sort_scratch_.reserve(levels_data_[0].u.size());
  result_.points.reserve(levels_data_[0].u.size());
  status_ = InitStatus::kWaitingForParallax;
}

void CoarseInitializer::fail(InitFailure failure) {
  status_ = InitStatus::kFailed;
  failure_ = failure;
}

void CoarseInitializer::setReference(const ImagePyramid& pyramid, double exposure) {
  reset();
  exposure_ref_ = exposure;
  T_ = SE3d();
  affine_ = AffineLight{};

  int levels = std::min({settings_.max_levels, camera_.levels(), pyramid.levels()});
  while (levels > 1 && (pyramid.width(levels - 1) < settings_.min_coarsest_size ||
                        pyramid.height(levels - 1) < settings_.min_coarsest_size)) {
    --levels;
  }
  levels_ = 0;
  std::array<float, kMaxPyramidLevels> bucket{};
  for (int lvl = 0; lvl < levels; ++lvl) {
    bucket[lvl] = selectPoints(pyramid, lvl);
    const int n = static_cast<int>(levels_data_[lvl].u.size());
    if (lvl == 0 && n < settings_.min_points) {
      fail(InitFailure::kTooFewPoints);
      return;
    }
    if (lvl > 0 && n < settings_.neighbours + 1) break;  // too coarse to be useful
    levels_ = lvl + 1;
  }

  const int k = settings_.neighbours;
  for (int lvl = 0; lvl < levels_; ++lvl) {
    Level& L = levels_data_[lvl];
    const std::size_t n = L.u.size();
    const ImageView<const GradientPixel> img = pyramid.gradients(lvl);
    L.ref.resize(n);
    L.neighbours.resize(n);
    L.neighbour_count.resize(n);
    L.parent.assign(n, -1);
    resetEstimates(L);
    for (std::size_t i = 0; i < n; ++i) {
      const float x = L.u[i].x();
      const float y = L.u[i].y();
      const bool integer = x == std::floor(x) && y == std::floor(y);
      for (int p = 0; p < kPatternSize; ++p) {
        const float px = x + static_cast<float>(kPatternOffsets[p][0]);
        const float py = y + static_cast<float>(kPatternOffsets[p][1]);
        L.ref[i][p] = integer ? img(static_cast<int>(px), static_cast<int>(py)).intensity
                              : interpolateIntensity(img, px, py);
      }
    }
    grid_.build(L.u, bucket[lvl], pyramid.width(lvl), pyramid.height(lvl));
    for (std::size_t i = 0; i < n; ++i) {
      const int found = grid_.nearest(L.u[i], k, static_cast<int>(i), nn_scratch_);
      L.neighbour_count[i] = found;
      for (int j = 0; j < found; ++j) L.neighbours[i][j] = nn_scratch_[j];
    }
  }
  // Parents: nearest point one level up, if within a few of that level's cells.
  for (int lvl = 0; lvl + 1 < levels_; ++lvl) {
    Level& L = levels_data_[lvl];
    const Level& P = levels_data_[lvl + 1];
    const float cell = bucket[lvl + 1];
    const float max_dist_sq = (3.f * cell + 2.f) * (3.f * cell + 2.f);
    grid_.build(P.u, cell, pyramid.width(lvl + 1), pyramid.height(lvl + 1));
    for (std::size_t i = 0; i < L.u.size(); ++i) {
      const Eigen::Vector2f up = (L.u[i].array() + 0.5f) * 0.5f - 0.5f;
      if (grid_.nearest(up, 1, -1, nn_scratch_) == 1 &&
          (P.u[nn_scratch_[0]] - up).squaredNorm() <= max_dist_sq) {
        L.parent[i] = nn_scratch_[0];
      }
    }
  }
  // What completion needs, so that no frame after the reference allocates.
  sort_scratch_.reserve(levels_data_[0].u.size());
  result_.points.reserve(levels_data_[0].u.size());
  status_ = InitStatus::kWaitingForParallax;
}

float CoarseInitializer::selectPoints(const ImagePyramid& pyramid, int lvl) {
  Level& L = levels_data_[lvl];
  if (lvl == 0 && settings_.use_pixel_selector) {
    // Made with the first reference after construction or releaseMemory() (about 9 MB of
    // selection and corner buffers at 1232x368).
    if (!selector_)
      selector_ = std::make_unique<PixelSelector>(width_, height_, settings_.selection);
    selector_->select(pyramid, settings_.selector_density, selected_);
    L.u.clear();
    L.is_corner.clear();
    // Keep the whole pattern at least one pixel inside the image (bilinear reads included).
    const float lo = static_cast<float>(kPatternPadding + 1);
    const float hi_x = static_cast<float>(pyramid.width(0) - kPatternPadding - 2);
    const float hi_y = static_cast<float>(pyramid.height(0) - kPatternPadding - 2);
    for (const SelectedPixel& s : selected_) {
      if (s.u < lo || s.v < lo || s.u > hi_x || s.v > hi_y) continue;
      L.u.emplace_back(s.u, s.v);
      L.is_corner.push_back(s.is_corner ? 1 : 0);
    }
    const float area = static_cast<float>(pyramid.width(0)) * static_cast<float>(pyramid.height(0));
    return std::max(2.f,
                    std::sqrt(area / static_cast<float>(std::max<std::size_t>(1, L.u.size()))));
  }
  // Whole pattern one pixel inside the image.
  selectBestGradientPerCell(pyramid.gradients(lvl), settings_.cell_size[lvl],
                            settings_.min_gradient, kPatternPadding + 1, L.u);
  L.is_corner.assign(L.u.size(), 0);
  return static_cast<float>(settings_.cell_size[lvl]);
}

void CoarseInitializer::trackFrame(const ImagePyramid& pyramid, double exposure) {
  frame_ = &pyramid;
  exposure_frame_ = exposure;
  exposure_ratio_ = static_cast<float>(exposure / exposure_ref_);
  const bool waiting = status_ == InitStatus::kWaitingForParallax;
  smoothness_weight_ = waiting ? settings_.smoothness_weight : settings_.smoothness_weight_parallax;
  // The previous frame's estimate is the initial guess (no constant-velocity extrapolation:
  // before the parallax is real, the estimated motion is mostly noise and would be amplified).
  stats_.iterations = 0;
  for (int lvl = levels_ - 1; lvl >= 0; --lvl) {
    if (lvl + 1 < levels_) propagateDown(lvl);
    stats_.iterations += optimiseLevel(lvl);
    normaliseScale(lvl);
  }
  propagateUp();
  frame_ = nullptr;
}

void CoarseInitializer::decide() {
  const Evaluation& e = eval_;  // level 0, the last optimised level
  const int n = pointCount(0);
  stats_.good_fraction = n > 0 ? static_cast<double>(e.good) / n : 0.0;
  stats_.rms_residual =
      e.good > 0 ? std::sqrt(2.0 * e.photo_good / (static_cast<double>(e.good) * kPatternSize))
                 : 0.0;
  stats_.flow_translation = e.good > 0 ? std::sqrt(e.flow_sq_sum / e.good) : 0.0;
  stats_.parallax = rotationFreeParallax();

  if (!e.finite || !finitePose(T_) || !std::isfinite(affine_.a) || !std::isfinite(affine_.b)) {
    fail(InitFailure::kNotFinite);
    return;
  }
  if (stats_.good_fraction < settings_.min_good_fraction) {
    fail(InitFailure::kLostTrack);
    return;
  }
  const bool grew = frames_ > 1 && stats_.rms_residual > settings_.residual_growth_floor &&
                    stats_.rms_residual > settings_.max_residual_growth * lowest_rms_;
  if (stats_.rms_residual > settings_.fail_rms || grew) {
    fail(InitFailure::kResidualTooLarge);
    return;
  }
  lowest_rms_ = frames_ > 1 ? std::min(lowest_rms_, stats_.rms_residual) : stats_.rms_residual;
  const bool parallax = stats_.flow_translation > settings_.min_parallax_flow &&
                        stats_.parallax > settings_.min_rotation_free_parallax &&
                        stats_.rms_residual <= settings_.max_snap_rms &&
                        stats_.good_fraction >= settings_.min_snap_good_fraction;
  if (!parallax) {
    status_ = InitStatus::kWaitingForParallax;
    snapped_frames_ = 0;
    return;
  }
  if (status_ == InitStatus::kWaitingForParallax) {
    status_ = InitStatus::kConfirming;
    snapped_frames_ = 0;
  } else {
    ++snapped_frames_;
  }
  // Fast motion (e.g. a car at 10 Hz) leaves the reference's view within a few frames; when the
  // parallax is already three times what is needed, one confirming frame is enough.
  const int needed = stats_.flow_translation >= 3.f * settings_.min_parallax_flow
                         ? std::min(settings_.confirm_frames, 1)
                         : settings_.confirm_frames;
  if (snapped_frames_ < needed) return;
  if (depthsDegenerate()) {
    fail(InitFailure::kDegenerateDepths);
    return;
  }
  publishResult();
  status_ = InitStatus::kComplete;
}

double CoarseInitializer::rotationFreeParallax() const {
  const Level& L = levels_data_[0];
  const LevelCamera& cam = camera_[0];
  const Eigen::Matrix3d R = T_.rotationMatrix();
  const Eigen::Vector3d t = T_.translation();
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double flow_sq = 0;
  int n = 0;
  for (std::size_t i = 0; i < L.u.size(); ++i) {
    if (!L.good[i]) continue;
    const Eigen::Vector3d a = R * cam.unproject(L.u[i].x(), L.u[i].y()).cast<double>();
    const Eigen::Vector3d q = a + t * static_cast<double>(L.idepth[i]);
    if (!(a.z() > 1e-6) || !(q.z() > 1e-6)) continue;
    const double x = a.x() / a.z(), y = a.y() / a.z();
    const Eigen::Vector2d f(cam.fx * (q.x() / q.z() - x), cam.fy * (q.y() / q.z() - y));
    Eigen::Matrix<double, 2, 3> J;
    J << -cam.fx * x * y, cam.fx * (1 + x * x), -cam.fx * y,  //
        -cam.fy * (1 + y * y), cam.fy * x * y, cam.fy * x;
    A.noalias() += J.transpose() * J;
    b.noalias() += J.transpose() * f;
    flow_sq += f.squaredNorm();
    ++n;
  }
  if (n < 3) return 0.0;
  const double explained = b.dot(A.ldlt().solve(b));
  return std::sqrt(std::max(0.0, flow_sq - explained) / n);
}

bool CoarseInitializer::depthsDegenerate() {
  const Level& L = levels_data_[0];
  sort_scratch_.clear();
  int nonpositive = 0;
  int count = 0;
  for (std::size_t i = 0; i < L.u.size(); ++i) {
    if (!L.good[i]) continue;
    ++count;
    if (L.idepth[i] > 0.f) {
      sort_scratch_.push_back(L.idepth[i]);
    } else {
      ++nonpositive;
    }
  }
  if (count == 0 || sort_scratch_.empty()) return true;
  if (static_cast<float>(nonpositive) > settings_.max_nonpositive_fraction * count) return true;
  const auto at = [&](double q) {
    const auto it = sort_scratch_.begin() +
                    static_cast<std::ptrdiff_t>(q * static_cast<double>(sort_scratch_.size() - 1));
    std::nth_element(sort_scratch_.begin(), it, sort_scratch_.end());
    return *it;
  };
  const float median = at(0.5);
  const float p95 = at(0.95);
  return !(median > 0.f) || p95 > settings_.max_idepth_spread * median;
}

void CoarseInitializer::publishResult() {
  const Level& L = levels_data_[0];
  double sum = 0;
  int count = 0;
  for (std::size_t i = 0; i < L.u.size(); ++i) {
    if (L.good[i]) {
      sum += L.idepth[i];
      ++count;
    }
  }
  const double mean = count > 0 && sum > 0 ? sum / count : 1.0;
  const float inv_mean = static_cast<float>(1.0 / mean);
  result_.points.resize(L.u.size());
  for (std::size_t i = 0; i < L.u.size(); ++i) {
    InitializedPoint& p = result_.points[i];
    p.u = L.u[i].x();
    p.v = L.u[i].y();
    p.idepth = L.idepth[i] * inv_mean;
    p.hessian = L.lin[i].hphoto * static_cast<float>(mean * mean);
    p.good = L.good[i] != 0;
    p.is_corner = L.is_corner[i] != 0;
  }
  result_.T_frame_ref = SE3d(T_.so3(), T_.translation() * mean);
  result_.affine_frame = affine_;
  result_.exposure_ref = exposure_ref_;
  result_.exposure_frame = exposure_frame_;
  result_.frames = frames_;
}

}  // namespace ldsm
