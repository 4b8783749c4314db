#include "mapfile/map_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "mapfile/map_format.h"

namespace ldsm::mapfile {
namespace {

bool finite(const SE3d& T) {
  return T.quaternion().coeffs().allFinite() && T.translation().allFinite();
}

bool positive(double v) {
  return std::isfinite(v) && v > 0.0;
}

/// Collects the first problem; each check returns false once one is found.
class Checker {
 public:
  explicit Checker(const MapData& map) : map_(map) {
    ids_.reserve(map.keyframes.size());
    for (const KeyframeRecord& kf : map.keyframes) ids_.push_back(kf.id);
  }

  std::optional<MapProblem> run() {
    if (calibration() && keyframes() && data() && points() && covisibility() && graph())
      return std::nullopt;
    return problem_;
  }

 private:
  bool fail(std::uint32_t section, std::string what) {
    problem_ = MapProblem{section, std::move(what)};
    return false;
  }
  /// Keyframe ids are checked increasing first, so that a binary search finds them.
  bool known(int id) const { return std::binary_search(ids_.begin(), ids_.end(), id); }

  bool calibration() {
    const MapCalibration& c = map_.calibration;
    const auto bad = [&](const char* what, double v, const char* expected) {
      return fail(kCalibrationTag, std::string(what) + " " + numberText(v) + " is not " + expected);
    };
    if (c.camera.width <= 0 || c.camera.height <= 0)
      return fail(kCalibrationTag, "image size " + std::to_string(c.camera.width) + "x" +
                                       std::to_string(c.camera.height) + " is not positive");
    const char* kPositive = "a finite positive number";
    if (!positive(c.camera.fx)) return bad("fx", c.camera.fx, kPositive);
    if (!positive(c.camera.fy)) return bad("fy", c.camera.fy, kPositive);
    if (!std::isfinite(c.camera.cx)) return bad("cx", c.camera.cx, "finite");
    if (!std::isfinite(c.camera.cy)) return bad("cy", c.camera.cy, "finite");
    if (!std::isfinite(c.radial_k)) return bad("radial_k", c.radial_k, "finite");
    // The refinement's correction: a focal length within a factor e, a principal point within the
    // image (calibration.focal_max and principal_point_max are far inside these).
    const auto badRefinement = [&](const char* what, double v, const char* expected) {
      return fail(kRefinementTag, std::string(what) + " " + numberText(v) + " is not " + expected);
    };
    if (!(std::abs(c.focal_log_scale) <= 1.0))
      return badRefinement("focal_log_scale", c.focal_log_scale, "in [-1, 1]");
    if (!(std::abs(c.cx_shift) <= c.camera.width))
      return badRefinement("cx_shift", c.cx_shift, "within the image width");
    if (!(std::abs(c.cy_shift) <= c.camera.height))
      return badRefinement("cy_shift", c.cy_shift, "within the image height");
    return true;
  }

  bool keyframes() {
    for (std::size_t i = 0; i < map_.keyframes.size(); ++i) {
      const KeyframeRecord& kf = map_.keyframes[i];
      const std::string at = "keyframe " + std::to_string(kf.id) + ": ";
      if (kf.id < 0) return fail(kKeyframesTag, at + "negative id");
      if (i > 0 && kf.id <= map_.keyframes[i - 1].id)
        return fail(kKeyframesTag, at + "ids not increasing (after keyframe " +
                                       std::to_string(map_.keyframes[i - 1].id) + ")");
      if (!std::isfinite(kf.timestamp))
        return fail(kKeyframesTag, at + "timestamp " + numberText(kf.timestamp) + " is not finite");
      if (!finite(kf.T_w_c)) return fail(kKeyframesTag, at + "pose is not finite");
      if (!positive(kf.scale))
        return fail(kKeyframesTag,
                    at + "scale " + numberText(kf.scale) + " is not a finite positive number");
    }
    return true;
  }

  bool data() {
    for (std::size_t i = 0; i < map_.data.size(); ++i) {
      const MarginalizedKeyframe& kf = map_.data[i];
      const std::string at = "keyframe " + std::to_string(kf.id) + ": ";
      if (!known(kf.id)) return fail(kKeyframeDataTag, at + "not among the keyframes");
      if (i > 0 && kf.id <= map_.data[i - 1].id)
        return fail(kKeyframeDataTag, at + "ids not increasing (after keyframe " +
                                          std::to_string(map_.data[i - 1].id) + ")");
      if (!dataScalars(kf, at) || !patchPoints(kf, at) || !corners(kf, at) || !links(kf, at))
        return false;
    }
    return true;
  }

  bool dataScalars(const MarginalizedKeyframe& kf, const std::string& at) {
    if (!std::isfinite(kf.timestamp))
      return fail(kKeyframeDataTag,
                  at + "timestamp " + numberText(kf.timestamp) + " is not finite");
    if (!positive(kf.exposure))
      return fail(kKeyframeDataTag,
                  at + "exposure " + numberText(kf.exposure) + " is not a finite positive number");
    if (!std::isfinite(kf.aff.a) || !std::isfinite(kf.aff.b))
      return fail(kKeyframeDataTag, at + "affine brightness (" + numberText(kf.aff.a) + ", " +
                                        numberText(kf.aff.b) + ") is not finite");
    if (!finite(kf.T_w_c)) return fail(kKeyframeDataTag, at + "pose is not finite");
    if (!std::isfinite(kf.radial_k))
      return fail(kKeyframeDataTag, at + "radial_k " + numberText(kf.radial_k) + " is not finite");
    if (kf.map_points_in_view < 0)
      return fail(kKeyframeDataTag, at + "map_points_in_view " +
                                        std::to_string(kf.map_points_in_view) + " is negative");
    if (!std::isfinite(kf.path_length) || kf.path_length < 0.0)
      return fail(kKeyframeDataTag, at + "path length " + numberText(kf.path_length) +
                                        " is not a finite non-negative number");
    if (kf.newest_when_left < -1)
      return fail(kKeyframeDataTag,
                  at + "newest_when_left " + std::to_string(kf.newest_when_left) + " is not an id");
    return true;
  }

  bool patchPoints(const MarginalizedKeyframe& kf, const std::string& at) {
    for (std::size_t j = 0; j < kf.points.size(); ++j) {
      const PatchPoint& p = kf.points[j];
      const std::string pt = at + "point " + std::to_string(j) + ": ";
      if (!std::isfinite(p.u) || !std::isfinite(p.v))
        return fail(kKeyframeDataTag,
                    pt + "pixel (" + numberText(p.u) + ", " + numberText(p.v) + ") is not finite");
      if (!positive(p.idepth))
        return fail(kKeyframeDataTag, pt + "inverse depth " + numberText(p.idepth) +
                                          " is not a finite positive number");
      if (!std::isfinite(p.idepth_hessian) || p.idepth_hessian < 0.f)
        return fail(kKeyframeDataTag, pt + "inverse depth hessian " + numberText(p.idepth_hessian) +
                                          " is not a finite non-negative number");
      for (int k = 0; k < kPatternSize; ++k) {
        if (!std::isfinite(p.colors[k]) || !std::isfinite(p.grad_weights[k]))
          return fail(kKeyframeDataTag, pt + "pattern sample " + std::to_string(k) + " (colour " +
                                            numberText(p.colors[k]) + ", weight " +
                                            numberText(p.grad_weights[k]) + ") is not finite");
      }
      if (p.observations < 0)
        return fail(kKeyframeDataTag,
                    pt + "observations " + std::to_string(p.observations) + " is negative");
    }
    return true;
  }

  bool corners(const MarginalizedKeyframe& kf, const std::string& at) {
    for (std::size_t j = 0; j < kf.corners.size(); ++j) {
      if (!kf.corners[j].allFinite())
        return fail(kKeyframeDataTag, at + "corner " + std::to_string(j) + " is not finite");
    }
    for (std::size_t j = 0; j < kf.corner_idepth.size(); ++j) {
      // NaN: unknown depth; an infinity is no depth at all.
      if (std::isinf(kf.corner_idepth[j]))
        return fail(kKeyframeDataTag,
                    at + "corner " + std::to_string(j) + ": inverse depth is infinite");
    }
    return true;
  }

  bool links(const MarginalizedKeyframe& kf, const std::string& at) {
    for (const KeyframeLink& l : kf.links) {
      const std::string ln = at + "link to keyframe " + std::to_string(l.other) + ": ";
      if (!known(l.other)) return fail(kKeyframeDataTag, ln + "no such keyframe");
      if (!finite(l.T_this_other)) return fail(kKeyframeDataTag, ln + "pose is not finite");
      if (l.shared_points < 0)
        return fail(kKeyframeDataTag,
                    ln + "shared points " + std::to_string(l.shared_points) + " is negative");
    }
    return true;
  }

  bool points() {
    for (std::size_t j = 0; j < map_.points.size(); ++j) {
      const HostedPoint& p = map_.points[j];
      const std::string at = "point " + std::to_string(j) + ": ";
      if (!p.position.allFinite()) return fail(kPointsTag, at + "position is not finite");
      if (!std::isfinite(p.intensity))
        return fail(kPointsTag, at + "intensity " + numberText(p.intensity) + " is not finite");
      if (p.host != -1 && !known(p.host))
        return fail(kPointsTag, at + "host keyframe " + std::to_string(p.host) + " does not exist");
    }
    return true;
  }

  bool covisibility() {
    for (const MapCovisibility& e : map_.covisibility) {
      const std::string at = "edge " + std::to_string(e.a) + " - " + std::to_string(e.b) + ": ";
      if (!known(e.a) || !known(e.b))
        return fail(kCovisibilityTag,
                    at + "keyframe " + std::to_string(known(e.a) ? e.b : e.a) + " does not exist");
      if (e.a == e.b) return fail(kCovisibilityTag, at + "connects a keyframe to itself");
      if (e.weight <= 0)
        return fail(kCovisibilityTag,
                    at + "weight " + std::to_string(e.weight) + " is not positive");
    }
    return true;
  }

  bool graph() {
    for (const MapGraphEdge& e : map_.graph) {
      const std::string at =
          "edge " + std::to_string(e.from_id) + " -> " + std::to_string(e.to_id) + ": ";
      if (!known(e.from_id) || !known(e.to_id))
        return fail(kGraphTag, at + "keyframe " +
                                   std::to_string(known(e.from_id) ? e.to_id : e.from_id) +
                                   " does not exist");
      if (e.from_id == e.to_id) return fail(kGraphTag, at + "connects a keyframe to itself");
      if (e.kind < 0 || e.kind > 2)
        return fail(kGraphTag, at + "kind " + std::to_string(e.kind) +
                                   " is none of 0 (odometry), 1 (loop), 2 (reuse)");
      if (!e.S_from_to.quaternion().coeffs().allFinite() ||
          !e.S_from_to.translation().allFinite() || !positive(e.S_from_to.scale()))
        return fail(kGraphTag, at + "Sim(3) is not finite (or its scale not positive)");
      if (!e.information.allFinite()) return fail(kGraphTag, at + "information is not finite");
    }
    return true;
  }

  const MapData& map_;
  std::vector<int> ids_;
  MapProblem problem_;
};

}  // namespace

std::optional<MapProblem> findMapProblem(const MapData& map) {
  return Checker(map).run();
}

std::string numberText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

}  // namespace ldsm::mapfile
