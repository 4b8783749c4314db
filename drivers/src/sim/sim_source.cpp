#include "ldsm/drivers/sim/sim_source.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "ldsm/drivers/sim/det_math.h"
#include "ldsm/error.h"

namespace ldsm::drivers::sim {
namespace {

Pose toPose(const RigidPose& r) {
  const Quat q = quatFromMatrix(r.rotation);
  Pose p;
  p.rotation = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
  p.translation = Eigen::Vector3d(r.translation.x, r.translation.y, r.translation.z);
  return p;
}

std::shared_ptr<const SimScene> buildScene(const std::string& name, const SimOptions& options) {
  return std::make_shared<const SimScene>(makeSimScene(name, options));
}

RenderSettings renderSettings(const SimOptions& o) {
  RenderSettings s;
  s.antialias_edges = o.antialias_edges;
  s.supersampling = o.supersampling;
  return s;
}

const SimOptions& validated(const SimOptions& o) {
  validate(o);
  return o;
}

}  // namespace

PinholeIntrinsics simIntrinsics(const SimOptions& o) {
  PinholeIntrinsics c;
  c.fx = c.fy = focalLengthPx(o);
  c.cx = 0.5 * (o.width - 1);
  c.cy = 0.5 * (o.height - 1);
  c.width = o.width;
  c.height = o.height;
  return c;
}

double pathLength(const Trajectory& trajectory) {
  double len = 0.0;
  for (std::size_t i = 1; i < trajectory.size(); ++i)
    len += (trajectory[i].pose.translation - trajectory[i - 1].pose.translation).norm();
  return len;
}

SimSource::SimSource(const std::string& scene_name, const SimOptions& options)
    : SimSource(buildScene(scene_name, options), options) {}

SimSource::SimSource(std::shared_ptr<const SimScene> scene, const SimOptions& options)
    : scene_(std::move(scene)),
      options_(validated(options)),
      frame_count_(simFrameCount(*scene_, options_)),
      intrinsics_(simIntrinsics(options_)),
      renderer_(scene_, intrinsics_, renderSettings(options_)),
      formation_(options_, intrinsics_) {
  geometric_.input.model = CameraModelType::Pinhole;
  geometric_.input.fx = intrinsics_.fx;
  geometric_.input.fy = intrinsics_.fy;
  geometric_.input.cx = intrinsics_.cx;
  geometric_.input.cy = intrinsics_.cy;
  geometric_.input.width = intrinsics_.width;
  geometric_.input.height = intrinsics_.height;
  geometric_.output.mode = OutputMode::None;
  geometric_.output.width = intrinsics_.width;
  geometric_.output.height = intrinsics_.height;

  photometric_.has_response = true;
  photometric_.inverse_response = formation_.inverseResponse();
  photometric_.vignette = formation_.vignette();

  ground_truth_.reserve(static_cast<std::size_t>(frame_count_));
  for (std::int64_t i = 0; i < frame_count_; ++i) {
    const double t = timestamp(i);
    ground_truth_.push_back({t, toPose(evaluatePath(scene_->path, t))});
  }
}

SourceInfo SimSource::info() const {
  SourceInfo s;
  s.name = "sim:" + scene_->name;
  s.width = intrinsics_.width;
  s.height = intrinsics_.height;
  s.frame_count = frame_count_;
  s.nominal_fps = options_.fps;
  return s;
}

double SimSource::timestamp(std::int64_t index) const {
  // Whole nanoseconds, so the value prints the same in every file (shortest round trip).
  return std::round(static_cast<double>(index) * (1e9 / options_.fps)) / 1e9;
}

double SimSource::exposureMs(std::int64_t index) const {
  return simExposureMs(options_, timestamp(index));
}

bool SimSource::next(Frame& frame) {
  if (position_ >= frame_count_) return false;
  renderFrame(position_, frame);
  ++position_;
  return true;
}

void SimSource::seek(std::int64_t index) {
  position_ = std::clamp<std::int64_t>(index, 0, frame_count_);
}

void SimSource::renderFrame(std::int64_t index, Frame& frame) {
  if (index < 0 || index >= frame_count_)
    throw InputError("sim:" + scene_->name + ": frame " + std::to_string(index) +
                     " is outside [0, " + std::to_string(frame_count_) + ")");
  const double exposure = exposureMs(index);
  const int m = options_.motion_blur_samples;
  if (m <= 1) {
    renderer_.renderIrradiance(ground_truth_[static_cast<std::size_t>(index)].pose, irradiance_);
  } else {
    // Average over poses spread across the exposure interval centred on the frame time.
    const double t = timestamp(index), dt = exposure * 1e-3;
    const double limit = scene_->path.duration();
    for (int j = 0; j < m; ++j) {
      const double tj = std::clamp(t + dt * ((j + 0.5) / m - 0.5), 0.0, limit);
      renderer_.renderIrradiance(evaluatePath(scene_->path, tj),
                                 j == 0 ? irradiance_ : blur_sample_);
      if (j > 0) {
        float* a = irradiance_.data();
        const float* b = blur_sample_.data();
        for (std::size_t i = 0, n = irradiance_.size(); i < n; ++i) a[i] += b[i];
      }
    }
    const float inv = 1.0f / static_cast<float>(m);
    float* a = irradiance_.data();
    for (std::size_t i = 0, n = irradiance_.size(); i < n; ++i) a[i] *= inv;
  }
  const std::uint32_t key = hash32(options_.seed, static_cast<std::uint32_t>(index));
  formation_.apply(irradiance_, exposure, key, frame.image);
  frame.index = index;
  frame.timestamp = timestamp(index);
  frame.exposure_ms = exposure;
}

}  // namespace ldsm::drivers::sim
