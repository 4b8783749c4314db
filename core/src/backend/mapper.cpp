#include "backend/mapper.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "backend/loop_description.h"

namespace ldsm {

Mapper::Mapper(const MapperSettings& settings, const PyramidCamera& camera, PyramidPool& pyramids)
    : settings_(settings),
      base_camera_(camera),
      camera_(camera),
      pyramids_(pyramids),
      optimizer_(settings.optimizer, camera[0]),
      calibration_(settings.calibration, settings.window.max_keyframes),
      selector_(camera[0].width, camera[0].height, settings.points) {
  trace_settings_.huber_threshold = settings.trace_huber_threshold;
  trace_settings_.outlier_threshold = settings.trace_outlier_threshold;
}

Mapper::~Mapper() = default;

std::vector<WindowKeyframe*> Mapper::windowView() const {
  std::vector<WindowKeyframe*> w = activeView();
  for (const auto& kf : reactivated_) w.push_back(kf.get());
  return w;
}

std::vector<WindowKeyframe*> Mapper::activeView() const {
  std::vector<WindowKeyframe*> w;
  w.reserve(window_.size() + reactivated_.size());
  for (const auto& kf : window_) w.push_back(kf.get());
  return w;
}

std::vector<Eigen::Vector2f> Mapper::newestDescribableCorners() {
  const WindowKeyframe& kf = *window_.back();
  std::vector<Eigen::Vector2f> out = kf.corners;
  appendLoopCorners(kf.loop_corners, out);
  return out;
}

std::size_t Mapper::windowImageBytes() const {
  std::size_t n = 0;
  for (const auto& kf : window_)
    if (kf->hasImage()) n += kf->pyramid().bytes();
  return n;
}

void Mapper::releaseLeavingPyramids() {
  for (std::unique_ptr<ImagePyramid>& p : leaving_pyramids_) pyramids_.release(std::move(p));
  leaving_pyramids_.clear();
}

WindowKeyframe& Mapper::insertKeyframe(std::unique_ptr<ImagePyramid> pyramid,
                                       const MapperFrame& info) {
  releaseLeavingPyramids();  // a caller that did not compact the newest keyframe
  auto kf = std::make_unique<WindowKeyframe>(next_keyframe_id_++, info.frame_index, info.timestamp,
                                             info.exposure, std::move(pyramid));
  kf->setInitialState(info.T_c_w, info.aff);
  // The keyframes before it are from now on only targets of residuals (level 0): the tracking
  // reference, the point selection and the reuse view are the newest keyframe's.
  for (auto& older : window_) older->compactPyramid(settings_.window.keyframe_images_16bit);
  if (!window_.empty()) {
    const WindowKeyframe& prev = *window_.back();
    kf->path_length =
        prev.path_length +
        (kf->T_c_w.inverse().translation() - prev.T_c_w.inverse().translation()).norm();
  }
  window_.push_back(std::move(kf));
  return *window_.back();
}

bool Mapper::initialize(const InitializationResult& result, const MapperFrame& reference,
                        std::unique_ptr<ImagePyramid> reference_pyramid, const MapperFrame& last,
                        std::unique_ptr<ImagePyramid> last_pyramid, KeyframeInsertion* insertion) {
  MapUpdate before = reset();
  WindowKeyframe& kf0 = insertKeyframe(std::move(reference_pyramid), reference);
  kf0.is_gauge_anchor = true;
  // kf0 takes its points from the initialiser, not from a selection: its loop corners alone.
  if (loop_corner_limits_.max_corners > 0) {
    selector_.detectCorners(kf0.pyramid(), loop_corner_limits_.max_corners,
                            loop_corner_limits_.min_score, loop_corner_scratch_);
    takeLoopCorners(kf0);
  }
  chain_start_id_ = kf0.id();
  // Keep about the configured number of active points, spread evenly over the result.
  std::vector<const InitializedPoint*> usable;
  for (const auto& p : result.points)
    if (p.good && p.idepth > 0.f && std::isfinite(p.idepth)) usable.push_back(&p);
  const double keep =
      std::min(1.0, settings_.window.active_points / std::max<double>(1, usable.size()));
  double acc = 0.0;
  const float c = optimizer_.settings().residual.gradient_weight_c;
  for (const InitializedPoint* ip : usable) {
    acc += keep;
    if (acc < 1.0) continue;
    acc -= 1.0;
    auto p = std::make_unique<ActivePoint>();
    if (!initActivePoint(*p, kf0, ip->u, ip->v, ip->idepth, c)) continue;
    p->id = next_point_id_++;
    p->is_corner = ip->is_corner;
    kf0.points.push_back(std::move(p));
    ++kf0.points_created;
  }
  if (kf0.points.size() < 50) {
    spdlog::warn("initialisation left only {} usable points; starting over", kf0.points.size());
    const MapUpdate dropped = reset();
    before.keyframes.insert(before.keyframes.end(), dropped.keyframes.begin(),
                            dropped.keyframes.end());
    if (insertion) insertion->map = std::move(before);
    pyramids_.release(std::move(last_pyramid));
    return false;
  }
  KeyframeInsertion ins = addKeyframe(std::move(last_pyramid), last);
  ins.map.keyframes.insert(ins.map.keyframes.begin(), before.keyframes.begin(),
                           before.keyframes.end());
  if (insertion) *insertion = std::move(ins);
  return true;
}

void Mapper::traceFrame(const ImagePyramid& frame, const MapperFrame& info) {
  const ImageView<const GradientPixel> target = frame.gradients(0);
  // Each keyframe's candidates are traced and filtered on their own: one task per keyframe.
  const auto traceKeyframe = [&](int k) {
    WindowKeyframe& kf = *window_[static_cast<size_t>(k)];
    if (kf.immature.empty()) return;
    const SE3f T_th = (info.T_c_w * kf.T_c_w.inverse()).cast<float>();
    const Eigen::Vector2f aff =
        affineTransfer(kf.exposure(), info.exposure, kf.aff, info.aff).cast<float>();
    auto& cands = kf.immature;
    size_t out = 0;
    for (size_t i = 0; i < cands.size(); ++i) {
      const TraceStatus st = cands[i].point.trace(target, camera_[0], T_th, aff, trace_settings_);
      const bool drop = st == TraceStatus::kOob || cands[i].point.outlierCount() > 2;
      if (!drop) {
        if (out != i) cands[out] = std::move(cands[i]);
        ++out;
      }
    }
    cands.erase(cands.begin() + static_cast<std::ptrdiff_t>(out), cands.end());
  };
  const int n = static_cast<int>(window_.size());
  concurrency::runTasks(tasks_, n, traceKeyframe);
}

void Mapper::startCalibrationAt(double focal_log_scale, double cx_shift, double cy_shift) {
  calibration_.startAt(focal_log_scale, cx_shift, cy_shift);
  useAppliedCalibration();
}

void Mapper::useAppliedCalibration() {
  const CalibVector& c = calibration_.applied();
  camera_ = PyramidCamera(correctedIntrinsics(base_camera_.intrinsics(), c), base_camera_.levels());
  optimizer_.setCamera(camera_[0], c[kCalibRadial]);
}

void Mapper::refineCalibration(const WindowOptimizationResult& opt) {
  // Only full windows: the first keyframes' short baselines say little about the calibration.
  if (static_cast<int>(window_.size()) <= settings_.window.max_keyframes) return;
  if (!opt.calibration_valid) {
    spdlog::debug("calibration: no step from this window (curvature not positive definite)");
    return;
  }
  std::array<bool, kCalibParams> was_engaged{};
  for (int p = 0; p < kCalibParams; ++p)
    was_engaged[static_cast<size_t>(p)] = calibration_.engaged(p);
  calibration_.addWindowStep(opt.calibration_step, opt.calibration_curvature);
  useAppliedCalibration();
  static constexpr const char* kNames[kCalibParams] = {"radial k", "focal scale", "cx", "cy"};
  const CalibVector& e = calibration_.estimate();
  for (int p = 0; p < kCalibParams; ++p)
    if (calibration_.engaged(p) != was_engaged[static_cast<size_t>(p)])
      spdlog::info("calibration: {} correction {} ({:.4f} after {} windows)", kNames[p],
                   calibration_.engaged(p) ? "applied" : "dropped", e[p], calibration_.windows());
  const CalibMatrix& C = opt.calibration_curvature;
  spdlog::debug(
      "calibration: step [{:.5f} {:.5f} {:.3f} {:.3f}], curvature [{:.4g} {:.4g} {:.4g} "
      "{:.4g}], rmse {:.2f}, estimate [{:.5f} {:.5f} {:.3f} {:.3f}]",
      opt.calibration_step[0], opt.calibration_step[1], opt.calibration_step[2],
      opt.calibration_step[3], C(0, 0), C(1, 1), C(2, 2), C(3, 3), opt.rmse, e[0], e[1], e[2],
      e[3]);
}

void Mapper::addResidualsToNewest() {
  WindowKeyframe* newest = window_.back().get();
  for (size_t i = 0; i + 1 < window_.size(); ++i)
    for (auto& p : window_[i]->points) p->residuals.push_back({newest});
  for (auto& kf : reactivated_)
    for (auto& p : kf->points) p->residuals.push_back({newest});
}

KeyframeInsertion Mapper::addKeyframe(std::unique_ptr<ImagePyramid> pyramid,
                                      const MapperFrame& info) {
  KeyframeInsertion ins;
  update_ = MapUpdate();
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  WindowKeyframe& kf = insertKeyframe(std::move(pyramid), info);
  ins.keyframe_id = kf.id();
  addResidualsToNewest();
  ins.activated_points = activatePoints();
  const auto t1 = Clock::now();
  ins.optimization = optimizer_.optimize(windowView(), prior_);
  refineCalibration(ins.optimization);
  adaptOutlierThreshold(*window_.back());
  reactivated_fit_ = measureReactivatedFit();
  for (auto& host : reactivated_)
    for (auto& p : host->points) {
      p->verified = false;
      for (const PointResidual& r : p->residuals)
        if (r.target == window_.back().get()) p->verified = r.state == ResidualState::Inlier;
    }
  for (const ReactivatedFit& f : reactivated_fit_) ins.map_points_in_view += f.inliers;
  window_.back()->map_points_in_view = ins.map_points_in_view;
  const auto t2 = Clock::now();
  ins.retired_points = retireLostPoints();
  removeBadResiduals();
  ins.marginalized_frames = marginalizeFrames();
  const auto t3 = Clock::now();
  makeImmaturePoints(*window_.back());
  for (KeyframeRecord& r : windowPoses()) update_.keyframes.push_back(r);
  ins.map = std::move(update_);
  update_ = MapUpdate();
  const auto t4 = Clock::now();
  auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  spdlog::debug(
      "mapping: activate {:.1f} ms, optimise {:.1f} ms ({} it), marginalise {:.1f} ms, "
      "select {:.1f} ms",
      ms(t0, t1), ms(t1, t2), ins.optimization.iterations, ms(t2, t3), ms(t3, t4));
  ins.active_points = activePointCount();
  for (const auto& k : window_) ins.immature_points += static_cast<int>(k->immature.size());
  return ins;
}

void Mapper::adaptOutlierThreshold(WindowKeyframe& kf) {
  if (!settings_.window.adaptive_outlier_threshold) return;
  energies_.clear();
  for (const auto& host : window_)
    for (const auto& p : host->points)
      for (const PointResidual& r : p->residuals)
        if (r.target == &kf && r.state != ResidualState::OutOfBounds) energies_.push_back(r.energy);
  const float th = adaptiveOutlierEnergy(energies_);
  if (th > 0.f) kf.outlier_energy = th;
}

void Mapper::removeBadResiduals() {
  for (auto* kf : windowView()) {
    auto& pts = kf->points;
    for (auto& p : pts) {
      auto& rs = p->residuals;
      rs.erase(
          std::remove_if(rs.begin(), rs.end(),
                         [](const PointResidual& r) { return r.state != ResidualState::Inlier; }),
          rs.end());
    }
    pts.erase(std::remove_if(pts.begin(), pts.end(),
                             [](const std::unique_ptr<ActivePoint>& p) {
                               return p->residuals.empty() || !(p->idepth > 0.f);
                             }),
              pts.end());
  }
}

std::vector<int> Mapper::framesToMarginalize() const {
  std::vector<int> out;
  const int n = static_cast<int>(window_.size());
  const WindowKeyframe& newest = *window_.back();
  int remaining = n;
  // Keyframes that lost most of their points or whose brightness changed too much.
  for (int i = 0; i + 2 < n && remaining > settings_.window.min_keyframes; ++i) {
    const WindowKeyframe& kf = *window_[i];
    const double in_fraction =
        kf.points_created > 0 ? static_cast<double>(kf.points.size()) / kf.points_created : 1.0;
    const double log_scale =
        std::log(affineTransfer(kf.exposure(), newest.exposure(), kf.aff, newest.aff)[0]);
    if (in_fraction < 0.05 || std::fabs(log_scale) > 0.7) {
      out.push_back(i);
      --remaining;
    }
  }
  // Still too many: drop the keyframe that is closest to the others and far from the newest.
  while (remaining > settings_.window.max_keyframes) {
    int best = -1;
    double best_score = -1.0;
    const Eigen::Vector3d c_new = newest.T_c_w.inverse().translation();
    for (int i = 0; i + 2 < n; ++i) {
      if (std::find(out.begin(), out.end(), i) != out.end()) continue;
      const Eigen::Vector3d ci = window_[i]->T_c_w.inverse().translation();
      double sum = 0.0;
      for (int j = 0; j + 1 < n; ++j) {
        if (j == i || std::find(out.begin(), out.end(), j) != out.end()) continue;
        sum += 1.0 / ((window_[j]->T_c_w.inverse().translation() - ci).norm() + 1e-5);
      }
      const double score = std::sqrt((c_new - ci).norm()) * sum;
      if (score > best_score) {
        best_score = score;
        best = i;
      }
    }
    if (best < 0) break;
    out.push_back(best);
    --remaining;
  }
  std::sort(out.begin(), out.end());
  return out;
}

int Mapper::marginalizeFrames() {
  const std::vector<int> idx = framesToMarginalize();
  for (auto it = idx.rbegin(); it != idx.rend(); ++it) marginalizeFrame(*it);
  return static_cast<int>(idx.size());
}

void Mapper::marginalizeFrame(int window_index) {
  const auto view = windowView();
  WindowKeyframe& f = *window_[window_index];
  std::vector<HostedPoint> finished;
  std::vector<const ActivePoint*> to_prior;
  std::vector<PatchPoint> kept = std::move(f.retired_points);
  for (auto& p : f.points) {
    recordCornerDepth(*p);
    if (p->inlier_residuals >= 1 && p->hessian_idepth > 0.f) {
      to_prior.push_back(p.get());
      finished.push_back({worldPoint(*p), p->host->id()});
      kept.push_back(toPatchPoint(*p));
    }
  }
  MarginalizedKeyframe leaving = describeLeavingKeyframe(f, std::move(kept));
  optimizer_.marginalizePoints(view, to_prior, prior_);
  f.points.clear();
  f.immature.clear();
  f.dormant.clear();
  for (auto& kf : window_) {
    if (kf.get() == &f) continue;
    for (auto& p : kf->points) {
      auto& rs = p->residuals;
      rs.erase(std::remove_if(rs.begin(), rs.end(),
                              [&](const PointResidual& r) { return r.target == &f; }),
               rs.end());
    }
    auto& pts = kf->points;
    for (auto& p : pts)
      if (p->residuals.empty()) {
        finished.push_back({worldPoint(*p), kf->id()});
      }
    pts.erase(
        std::remove_if(pts.begin(), pts.end(),
                       [](const std::unique_ptr<ActivePoint>& p) { return p->residuals.empty(); }),
        pts.end());
  }
  for (auto& kf : reactivated_) {
    auto& pts = kf->points;
    for (auto& p : pts) {
      auto& rs = p->residuals;
      rs.erase(std::remove_if(rs.begin(), rs.end(),
                              [&](const PointResidual& r) { return r.target == &f; }),
               rs.end());
    }
    pts.erase(
        std::remove_if(pts.begin(), pts.end(),
                       [](const std::unique_ptr<ActivePoint>& p) { return p->residuals.empty(); }),
        pts.end());
  }
  optimizer_.marginalizeFrame(view, f, prior_);
  update_.keyframes.push_back({f.id(), f.frameIndex(), f.timestamp(), f.T_c_w.inverse()});
  leaving.T_w_c = f.T_c_w.inverse();
  // Nothing samples the keyframe any more: its image goes with its description (moved, not
  // copied, from a compacted pyramid).
  if (describe_leaving_) f.takeImage(leaving.image);
  update_.left.push_back(std::move(leaving));
  update_.points.insert(update_.points.end(), finished.begin(), finished.end());
  leaving_pyramids_.push_back(f.releasePyramid());
  window_.erase(window_.begin() + window_index);
}

MarginalizedKeyframe Mapper::describeLeavingKeyframe(WindowKeyframe& f,
                                                     std::vector<PatchPoint> points) {
  MarginalizedKeyframe out;
  out.id = f.id();
  out.frame_index = f.frameIndex();
  out.timestamp = f.timestamp();
  out.exposure = f.exposure();
  out.aff = f.aff;
  out.T_w_c = f.T_c_w.inverse();
  out.radial_k = radialK();
  out.points = std::move(points);
  out.map_points_in_view = f.map_points_in_view;
  out.newest_when_left = window_.back()->id();
  out.path_length = f.path_length;
  out.links = linksOf(f);
  if (describe_leaving_) describeForLoopClosure(f, window_, camera_[0], out);
  return out;
}

std::vector<KeyframeLink> Mapper::linksOf(const WindowKeyframe& f) const {
  std::vector<KeyframeLink> links;
  std::vector<int> shared;
  auto count = [&](const WindowKeyframe& host, const WindowKeyframe& target) {
    int n = 0;
    for (const auto& p : host.points)
      for (const PointResidual& r : p->residuals)
        if (r.target == &target && r.state == ResidualState::Inlier) ++n;
    return n;
  };
  auto add = [&](const WindowKeyframe& other, bool map_keyframe) {
    KeyframeLink l;
    l.other = other.id();
    l.T_this_other = f.T_c_w * other.T_c_w.inverse();
    l.shared_points = count(f, other) + count(other, f);
    l.map_keyframe = map_keyframe;
    links.push_back(l);
  };
  for (const auto& kf : window_)
    if (kf.get() != &f) add(*kf, false);
  for (const auto& kf : reactivated_) add(*kf, true);
  return links;
}

void Mapper::markMapCoverage(const WindowKeyframe& kf) {
  const int w = camera_[0].width, h = camera_[0].height;
  coverage_.assign(static_cast<std::size_t>(w) * h, 0);
  const int r = static_cast<int>(std::ceil(coverage_radius_));
  for (const auto& host : reactivated_)
    for (const auto& p : host->points)
      for (const PointResidual& res : p->residuals) {
        if (res.target != &kf || res.state != ResidualState::Inlier) continue;
        const int cx = static_cast<int>(std::lround(res.projection.x()));
        const int cy = static_cast<int>(std::lround(res.projection.y()));
        for (int y = std::max(0, cy - r); y <= std::min(h - 1, cy + r); ++y)
          for (int x = std::max(0, cx - r); x <= std::min(w - 1, cx + r); ++x)
            coverage_[static_cast<std::size_t>(y) * w + x] = 1;
      }
}

void Mapper::takeLoopCorners(WindowKeyframe& kf) {
  kf.loop_corners.clear();
  kf.loop_corners.reserve(loop_corner_scratch_.size());
  for (const Corner& c : loop_corner_scratch_) kf.loop_corners.emplace_back(c.u, c.v);
}

void Mapper::makeImmaturePoints(WindowKeyframe& kf, bool use_coverage) {
  const bool loop_corners = loop_corner_limits_.max_corners > 0;
  selector_.select(kf.pyramid(), 1.f, selected_, loop_corner_limits_,
                   loop_corners ? &loop_corner_scratch_ : nullptr);
  if (loop_corners) takeLoopCorners(kf);
  kf.immature.clear();
  kf.dormant.clear();
  kf.immature.reserve(selected_.size());
  kf.corners.clear();
  // Where map points (reactivated keyframes) are seen, the map has points already.
  const bool covered = use_coverage && coverage_radius_ > 0.f && !reactivated_.empty();
  if (covered) markMapCoverage(kf);
  const int width = camera_[0].width;
  const ImageView<const GradientPixel> img = kf.pyramid().gradients(0);
  for (const SelectedPixel& s : selected_) {
    if (covered && !s.is_corner &&
        coverage_[static_cast<std::size_t>(std::lround(s.v)) * width +
                  static_cast<std::size_t>(std::lround(s.u))] != 0) {
      kf.dormant.push_back({ImmaturePoint(img, s.u, s.v), false});
      continue;
    }
    kf.immature.push_back({ImmaturePoint(img, s.u, s.v), s.is_corner});
    if (s.is_corner) kf.corners.emplace_back(s.u, s.v);
  }
  kf.corner_idepth.assign(kf.corners.size(), std::numeric_limits<float>::quiet_NaN());
}

void Mapper::recordCornerDepth(const ActivePoint& p) {
  if (!p.is_corner || p.host == nullptr || !(p.idepth > 0.f)) return;
  WindowKeyframe& host = *p.host;
  for (std::size_t i = 0; i < host.corners.size(); ++i)
    if (host.corners[i].x() == p.u && host.corners[i].y() == p.v) {
      host.corner_idepth[i] = p.idepth;
      return;
    }
}

std::vector<KeyframeRecord> Mapper::windowPoses() const {
  std::vector<KeyframeRecord> out;
  out.reserve(window_.size());
  for (const auto& kf : window_)
    out.push_back({kf->id(), kf->frameIndex(), kf->timestamp(), kf->T_c_w.inverse()});
  return out;
}

MapPoint Mapper::worldPoint(const ActivePoint& p) const {
  MapPoint m;
  const Eigen::Vector3f ray = radialRay(camera_[0], radialK(), p.u, p.v);
  m.position = p.host->T_c_w.inverse() * (ray.cast<double>() / static_cast<double>(p.idepth));
  m.intensity = p.colors[4];
  m.is_corner = p.is_corner;
  return m;
}

std::vector<MapPoint> Mapper::activeMapPoints() const {
  std::vector<MapPoint> out;
  for (const auto& kf : window_)
    for (const auto& p : kf->points) out.push_back(worldPoint(*p));
  return out;
}

TrackingReference Mapper::newestReference() const {
  const WindowKeyframe& kf = *window_.back();
  return {kf.id(), kf.frameIndex(), kf.T_c_w, kf.exposure(), kf.aff, &kf.pyramid()};
}

int Mapper::activePointCount() const {
  int n = 0;
  for (const auto& kf : window_) n += static_cast<int>(kf->points.size());
  return n;
}

void Mapper::trackingPoints(std::vector<DepthPoint>& out) const {
  out.clear();
  if (window_.empty()) return;
  const WindowKeyframe& newest = *window_.back();
  const LevelCamera& cam = camera_[0];
  for (const WindowKeyframe* kf : windowView()) {
    const SE3f T_nh = (newest.T_c_w * kf->T_c_w.inverse()).cast<float>();
    for (const auto& p : kf->points) {
      if (p->fixed && !p->verified) continue;
      const Eigen::Vector3f q = T_nh * (radialRay(cam, radialK(), p->u, p->v) / p->idepth);
      if (!(q.z() > 1e-3f)) continue;
      const Eigen::Vector2f px = radialProject(cam, radialK(), q);
      if (px.x() < 0 || px.y() < 0 || px.x() > cam.width - 1 || px.y() > cam.height - 1) continue;
      out.push_back({px.x(), px.y(), 1.f / q.z(), 1.f, kf->is_reactivated});
    }
  }
}

KeyframeInsertion Mapper::relocalize(std::unique_ptr<ImagePyramid> pyramid, const MapperFrame& info,
                                     const MarginalizedKeyframe& anchor, const SE3d& anchor_T_w_c,
                                     double anchor_scale) {
  KeyframeInsertion ins;
  ins.map = reset();
  WindowKeyframe& kf = insertKeyframe(std::move(pyramid), info);
  chain_start_id_ = kf.id();
  // Held near where relocalisation found it (the reactivated keyframe fixes the gauge; this keeps
  // it once that one leaves), not fixed: its pose is a measurement from one map keyframe, and the
  // window corrects it (on vamr_desk_loop by up to half a degree).
  kf.anchor_weight = kRelocalizationAnchorWeight;
  kf.anchor_affine_weight = settings_.optimizer.gauge_anchor_weight;
  ins.keyframe_id = kf.id();
  reactivate(anchor, anchor_T_w_c, anchor_scale);
  for (auto& p : reactivated_.back()->points) p->verified = true;  // relocalisation aligned them
  makeImmaturePoints(kf, /*use_coverage=*/false);
  for (KeyframeRecord& r : windowPoses()) ins.map.keyframes.push_back(r);
  for (const auto& host : reactivated_)
    ins.map_points_in_view += static_cast<int>(host->points.size());
  return ins;
}

std::vector<MarginalizedKeyframe> Mapper::describeWindow() {
  std::vector<MarginalizedKeyframe> out;
  for (auto& kf : window_) {
    std::vector<PatchPoint> points = kf->retired_points;
    for (const auto& p : kf->points)
      if (p->inlier_residuals >= 1 && p->hessian_idepth > 0.f) points.push_back(toPatchPoint(*p));
    out.push_back(describeLeavingKeyframe(*kf, std::move(points)));
    // The keyframe stays in the window: its image is copied.
    if (describe_leaving_) kf->pyramid().copyIntensity(0, out.back().image);
  }
  return out;
}

MapUpdate Mapper::reset() {
  MapUpdate out;
  out.keyframes = windowPoses();
  // The window's keyframes go to the map as if they had left it (reuse and relocalisation can
  // find them), with the points they host.
  if (describe_leaving_) out.left = describeWindow();
  for (auto& kf : window_) pyramids_.release(kf->releasePyramid());
  releaseLeavingPyramids();
  window_.clear();
  reactivated_.clear();
  reactivated_fit_.clear();
  prior_ = MarginalizationPrior();
  update_ = MapUpdate();
  return out;
}

}  // namespace ldsm
