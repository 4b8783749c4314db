#include "reuse/redundancy.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "camera/radial_distortion.h"
#include "map/map_depth.h"
#include "math/constants.h"

namespace ldsm {
namespace {

constexpr float kBorder = 4.f;

}  // namespace

RedundancyCheck checkRedundancy(const MarginalizedKeyframe& keyframe, const KeyframeRecord& pose,
                                const MapStore& map, const LevelCamera& camera,
                                const ReuseConfig& config) {
  RedundancyCheck out;
  if (keyframe.points.empty()) return out;
  // Its points in the world, and its median depth.
  const std::optional<double> host_depth = medianHostDepth(keyframe.points);
  if (!host_depth) return out;
  std::vector<Eigen::Vector3d> world;
  world.reserve(keyframe.points.size());
  for (const PatchPoint& p : keyframe.points) {
    if (!(p.idepth > 0.f)) continue;
    const Eigen::Vector3d X = radialRay(camera, keyframe.radial_k, p.u, p.v).cast<double>() /
                              static_cast<double>(p.idepth);
    world.push_back(pose.T_w_c * (pose.scale * X));
  }
  const double median_depth = pose.scale * *host_depth;
  const Eigen::Vector3d centre = pose.T_w_c.translation();
  const Eigen::Vector3d axis = pose.T_w_c.so3() * Eigen::Vector3d::UnitZ();
  for (const int id : map.keyframesNear(centre, config.redundancy_distance * median_depth)) {
    if (id == keyframe.id) continue;
    const std::shared_ptr<const MarginalizedKeyframe> other = map.keyframeData(id);
    // Only an earlier visit covers it: its own neighbours in time are the odometry's.
    if (!other || other->newest_when_left > keyframe.id - config.min_keyframe_age) continue;
    const KeyframeRecord op = map.keyframe(id);
    if (op.id < 0) continue;
    const Eigen::Vector3d other_axis = op.T_w_c.so3() * Eigen::Vector3d::UnitZ();
    const double angle = degrees(std::acos(std::clamp(axis.dot(other_axis), -1.0, 1.0)));
    if (angle > config.redundancy_angle_deg) continue;
    const SE3d T_c_w = op.T_w_c.inverse();
    int seen = 0;
    for (const Eigen::Vector3d& X_w : world) {
      const Eigen::Vector3d X = T_c_w * X_w;
      if (!(X.z() > 1e-6)) continue;
      const Eigen::Vector2f px = radialProject(camera, other->radial_k, X.cast<float>());
      if (px.x() >= kBorder && px.y() >= kBorder &&
          px.x() <= static_cast<float>(camera.width) - 1.f - kBorder &&
          px.y() <= static_cast<float>(camera.height) - 1.f - kBorder)
        ++seen;
    }
    const double coverage = static_cast<double>(seen) / static_cast<double>(world.size());
    if (coverage > out.coverage) {
      out.coverage = coverage;
      out.covered_by = id;
    }
  }
  out.redundant = out.coverage >= config.redundancy_coverage;
  return out;
}

}  // namespace ldsm
