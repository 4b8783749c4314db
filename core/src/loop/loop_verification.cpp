#include "loop/loop_verification.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <spdlog/spdlog.h>

#include "ldsm/error.h"

namespace ldsm::loop {
namespace {

bool hasDepth(float idepth) {
  return idepth > 0.0f && std::isfinite(idepth);
}

Eigen::Vector3d unproject(const PinholeIntrinsics& cam, const Eigen::Vector2f& px, float idepth) {
  return Eigen::Vector3d((px.x() - cam.cx) / cam.fx, (px.y() - cam.cy) / cam.fy, 1.0) /
         static_cast<double>(idepth);
}

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

/// Feature indices bucketed by pixel in square cells (compressed rows: each cell's indices in
/// increasing order).
class CellGrid {
 public:
  CellGrid(const std::vector<Eigen::Vector2f>& pixels, const std::vector<std::uint8_t>& skip,
           double cell, int width, int height)
      : cell_(std::max(cell, 1.0)),
        columns_(std::max(1, static_cast<int>(std::ceil(std::max(width, 1) / cell_)))),
        rows_(std::max(1, static_cast<int>(std::ceil(std::max(height, 1) / cell_)))),
        start_(static_cast<std::size_t>(columns_) * rows_ + 1, 0) {
    std::vector<int> cell_of(pixels.size(), -1);
    for (std::size_t i = 0; i < pixels.size(); ++i) {
      if (skip[i]) continue;
      cell_of[i] = cellIndex(column(pixels[i].x()), row(pixels[i].y()));
      ++start_[static_cast<std::size_t>(cell_of[i]) + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    items_.resize(start_.back());
    std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t i = 0; i < pixels.size(); ++i)
      if (cell_of[i] >= 0) items_[fill[static_cast<std::size_t>(cell_of[i])]++] = i;
  }

  /// Calls f(index) for the features of the 3 x 3 cells around pixel (u, v).
  template <class F>
  void forEachNear(double u, double v, F&& f) const {
    const int c0 = column(u), r0 = row(v);
    for (int r = std::max(0, r0 - 1); r <= std::min(rows_ - 1, r0 + 1); ++r)
      for (int c = std::max(0, c0 - 1); c <= std::min(columns_ - 1, c0 + 1); ++c) {
        const std::size_t k = static_cast<std::size_t>(cellIndex(c, r));
        for (std::size_t n = start_[k]; n < start_[k + 1]; ++n) f(items_[n]);
      }
  }

 private:
  // Clamped in double before the cast: any finite pixel, however far out, has a cell.
  int column(double u) const {
    return static_cast<int>(std::clamp(std::floor(u / cell_), 0.0, columns_ - 1.0));
  }
  int row(double v) const {
    return static_cast<int>(std::clamp(std::floor(v / cell_), 0.0, rows_ - 1.0));
  }
  int cellIndex(int c, int r) const { return r * columns_ + c; }

  double cell_;
  int columns_, rows_;
  std::vector<std::size_t> start_;
  std::vector<std::size_t> items_;
};

class Verifier {
 public:
  Verifier(const KeyframeFeatures& cur, const KeyframeFeatures& cand,
           const LoopVerificationSettings& s, LoopVerification& out)
      : cur_(cur), cand_(cand), s_(s), out_(out) {}

  // Runs the stages; returns false with out_.reason set (at the first failed test).
  bool run() {
    std::vector<DescriptorMatch> all = matchDescriptors(cur_, cand_, s_.matching);
    if (verify(all)) return true;
    // The guided search is the second chance of a candidate the global matches did not carry (a
    // clear loop passes without it, at no extra cost).
    if (s_.guided_min_inliers <= 0) return false;
    const int added = extendByProjection(all);
    if (added == 0) return false;
    const std::string first = out_.reason;
    LoopVerification fresh;
    fresh.current_id = out_.current_id;
    fresh.candidate_id = out_.candidate_id;
    out_ = fresh;
    matches_.clear();
    out_.num_guided_matches = added;
    if (verify(all)) return true;
    out_.reason +=
        " (with " + std::to_string(added) + " guided matches; without them: " + first + ")";
    return false;
  }

 private:
  // The tests from the matches on: returns false with out_.reason set at the first failed one.
  bool verify(const std::vector<DescriptorMatch>& all) {
    out_.num_matches = static_cast<int>(all.size());
    if (out_.num_matches < s_.min_matches) {
      return reject("only " + std::to_string(all.size()) + " ORB matches (need " +
                    std::to_string(s_.min_matches) + ")");
    }
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> pixels;
    for (const DescriptorMatch& m : all) {
      if (!hasDepth(cand_.idepth[m.train])) continue;
      matches_.push_back(m);
      points.push_back(unproject(cand_.camera, cand_.pixels[m.train], cand_.idepth[m.train]));
      pixels.push_back(cur_.pixels[m.query].cast<double>());
    }
    out_.num_matches_with_depth = static_cast<int>(matches_.size());
    if (out_.num_matches_with_depth < s_.min_matches_with_depth) {
      return reject("only " + std::to_string(matches_.size()) +
                    " matches with candidate depth (need " +
                    std::to_string(s_.min_matches_with_depth) + ")");
    }
    const PnpRansacResult pnp = solvePnpRansac(points, pixels, cur_.camera, s_.pnp);
    out_.num_pnp_inliers = static_cast<int>(pnp.inliers.size());
    if (pnp.has_pose) {
      pnp_pose_ = pnp.T_camera_points;
      pnp_pose_inliers_ = out_.num_pnp_inliers;
    }
    if (!pnp.success) {
      return reject("PnP RANSAC found " + std::to_string(pnp.inliers.size()) + " inliers (need " +
                    std::to_string(s_.pnp.min_inliers) + ")");
    }
    // Relative scale: median ratio of current depth to the PnP-predicted depth, or (a baseline
    // long enough) from PnP both ways.
    std::vector<double> ratios;
    for (const int i : pnp.inliers) {
      const float d = cur_.idepth[matches_[i].query];
      const double z = (pnp.T_camera_points * points[i]).z();
      if (hasDepth(d) && z > 0.0) ratios.push_back(1.0 / (static_cast<double>(d) * z));
    }
    if (static_cast<int>(ratios.size()) < s_.min_inliers_3d || ratios.empty()) {
      return reject("only " + std::to_string(ratios.size()) +
                    " PnP inliers with depth in the current keyframe to fix the scale (need " +
                    std::to_string(s_.min_inliers_3d) + ")");
    }
    double s0 = median(std::move(ratios));
    if (const double s_pnp = scaleFromPnpBothWays(pnp); s_pnp > 0.0) {
      s0 = s_pnp;
      out_.scale_from_both_ways = true;
    }
    out_.initial_scale = s0;
    const Sim3d initial(pnp.T_camera_points.so3(), s0 * pnp.T_camera_points.translation(), s0);
    std::vector<std::uint8_t> pnp_inlier(points.size(), 0);
    for (const int i : pnp.inliers) pnp_inlier[i] = 1;
    return refine(points, pixels, initial, pnp_inlier);
  }

  // LDSM: the relative scale from PnP solved both ways. Forward (the candidate's points, the
  // current pixels) gives the translation in the candidate's scale, t / s; backward (the current
  // keyframe's points, the candidate's pixels) gives it in the current scale, -R^T t. Their
  // lengths' ratio is s, when the two cameras are far enough apart for it to be measured (else
  // 0: the depth ratio stays).
  double scaleFromPnpBothWays(const PnpRansacResult& forward) const {
    std::vector<Eigen::Vector3d> points;
    std::vector<Eigen::Vector2d> pixels;
    double depth_sum = 0.0;
    for (const int i : forward.inliers) {
      const DescriptorMatch& m = matches_[static_cast<std::size_t>(i)];
      const float d = cur_.idepth[m.query];
      if (!hasDepth(d)) continue;
      points.push_back(unproject(cur_.camera, cur_.pixels[m.query], d));
      pixels.push_back(cand_.pixels[m.train].cast<double>());
      depth_sum += points.back().z();
    }
    if (static_cast<int>(points.size()) < s_.pnp.min_inliers) return 0.0;
    const PnpRansacResult backward = solvePnpRansac(points, pixels, cand_.camera, s_.pnp);
    if (!backward.success) return 0.0;
    const double t_forward = forward.T_camera_points.translation().norm();
    const double t_backward = backward.T_camera_points.translation().norm();
    const double mean_depth = depth_sum / static_cast<double>(points.size());
    if (!(t_backward > kMinBaselineForScale * mean_depth) || !(t_forward > 0.0)) return 0.0;
    return t_backward / t_forward;
  }
  /// Baseline (times the current points' mean depth) below which the two PnP translations are
  /// too short to give the scale.
  static constexpr double kMinBaselineForScale = 0.1;

  /// The guided search (file comment of loop_verification.h): adds to `all` (kept sorted by
  /// query) the matches found near the pixels a preliminary PnP predicts; returns how many.
  int extendByProjection(std::vector<DescriptorMatch>& all) const {
    // The preliminary pose: the one the verification's PnP found, also with too few inliers.
    // A candidate the verification stopped before PnP (too few global matches) gets no guided
    // search: a PnP of its own for each of those cost 15 ms per keyframe on vamr_desk_loop
    // (OpenCV's RANSAC, 300 EPnP iterations) and found no loop there that the rest did not.
    if (pnp_pose_inliers_ < s_.guided_min_inliers) return 0;  // -1: no pose (or no PnP)
    const SE3d& T_cur_cand = pnp_pose_;
    std::vector<std::uint8_t> cur_used(cur_.pixels.size(), 0), cand_used(cand_.pixels.size(), 0);
    for (const DescriptorMatch& m : all) {
      cur_used[m.query] = 1;
      cand_used[m.train] = 1;
    }
    // Per current feature, the best guided claim (a feature near two predictions goes to the
    // closer descriptor).
    std::vector<DescriptorMatch> claim(cur_.pixels.size(), DescriptorMatch{0, 0, -1});
    const double r = s_.guided_radius_px, r2 = r * r;
    const PinholeIntrinsics& cam = cur_.camera;
    // The unmatched current features in a grid of r x r cells (each cell's features in index
    // order), so that a prediction visits the 3 x 3 cells around it only.
    const CellGrid grid(cur_.pixels, cur_used, r, cam.width, cam.height);
    for (std::size_t j = 0; j < cand_.pixels.size(); ++j) {
      if (cand_used[j] || !hasDepth(cand_.idepth[j])) continue;
      const Eigen::Vector3d q =
          T_cur_cand * unproject(cand_.camera, cand_.pixels[j], cand_.idepth[j]);
      if (!(q.z() > 0.0)) continue;
      const double u = cam.fx * q.x() / q.z() + cam.cx, v = cam.fy * q.y() / q.z() + cam.cy;
      if (!(std::isfinite(u) && std::isfinite(v))) continue;
      // The two smallest distances (best the lowest index among equals: any visiting order
      // gives the same result).
      int best = 257, second = 257;
      std::size_t best_i = 0;
      grid.forEachNear(u, v, [&](std::size_t i) {
        const double du = cur_.pixels[i].x() - u, dv = cur_.pixels[i].y() - v;
        if (du * du + dv * dv > r2) return;
        const int d = hammingDistance(cur_.descriptors[i], cand_.descriptors[j]);
        if (d < best || (d == best && i < best_i)) {
          second = best;
          best = d;
          best_i = i;
        } else if (d < second) {
          second = d;
        }
      });
      if (best > s_.matching.max_distance) continue;
      if (s_.matching.ratio < 1.f && second <= 256 &&
          !(static_cast<float>(best) < s_.matching.ratio * second))
        continue;
      DescriptorMatch& c = claim[best_i];
      if (c.distance < 0 || best < c.distance)
        c = {static_cast<std::uint32_t>(best_i), static_cast<std::uint32_t>(j), best};
    }
    int added = 0;
    for (const DescriptorMatch& c : claim)
      if (c.distance >= 0) {
        all.push_back(c);
        ++added;
      }
    std::sort(all.begin(), all.end(),
              [](const DescriptorMatch& a, const DescriptorMatch& b) { return a.query < b.query; });
    return added;
  }

  bool refine(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector2d>& px,
              const Sim3d& initial, const std::vector<std::uint8_t>& pnp_inlier) {
    std::vector<Sim3Correspondence> corr(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const float d = cur_.idepth[matches_[i].query];
      corr[i] = {points[i], px[i], hasDepth(d) ? static_cast<double>(d) : 0.0};
    }
    const Sim3RefinementResult ref =
        refineSim3(corr, cur_.camera, initial, s_.refinement, &pnp_inlier);
    out_.S_current_candidate = ref.S_current_candidate;
    out_.num_inliers = ref.inliers_2d + ref.inliers_3d;
    out_.num_inliers_3d = ref.inliers_3d;
    out_.rms_reprojection_px = ref.rms_reprojection_px;
    out_.information = ref.information;
    for (std::size_t i = 0; i < corr.size(); ++i) {
      if (ref.inlier[i]) out_.inlier_matches.push_back(matches_[i]);
    }
    if (!ref.success) return reject("Sim(3) refinement failed (no consistent inliers)");
    if (out_.num_inliers < s_.min_inliers) {
      return reject("only " + std::to_string(out_.num_inliers) +
                    " inliers after Sim(3) refinement (need " + std::to_string(s_.min_inliers) +
                    ")");
    }
    if (out_.num_inliers_3d < s_.min_inliers_3d) {
      return reject("only " + std::to_string(out_.num_inliers_3d) +
                    " inliers with current depth after refinement (need " +
                    std::to_string(s_.min_inliers_3d) + ")");
    }
    const double scale = ref.S_current_candidate.scale();
    if (!(scale >= s_.min_scale && scale <= s_.max_scale)) {
      return reject("implausible relative scale " + std::to_string(scale));
    }
    return true;
  }

  bool reject(std::string reason) {
    out_.reason = std::move(reason);
    return false;
  }

  const KeyframeFeatures& cur_;
  const KeyframeFeatures& cand_;
  const LoopVerificationSettings& s_;
  LoopVerification& out_;
  std::vector<DescriptorMatch> matches_;  // matches whose candidate feature has depth
  // The first verification's PnP pose and its inliers (-1: no pose), the guided search's start.
  SE3d pnp_pose_;
  int pnp_pose_inliers_ = -1;
};

void checkCamera(const KeyframeFeatures& kf, const char* what) {
  const PinholeIntrinsics& c = kf.camera;
  if (!(c.fx > 0 && c.fy > 0 && std::isfinite(c.fx) && std::isfinite(c.fy) && std::isfinite(c.cx) &&
        std::isfinite(c.cy))) {
    throw InputError(std::string(what) + " " + std::to_string(kf.keyframe_id) +
                     ": invalid pinhole intrinsics (fx, fy must be finite and > 0)");
  }
}

}  // namespace

LoopVerification verifyLoop(const KeyframeFeatures& current, const KeyframeFeatures& candidate,
                            const LoopVerificationSettings& settings) {
  const auto t0 = std::chrono::steady_clock::now();
  validateKeyframeFeatures(current, "current keyframe");
  validateKeyframeFeatures(candidate, "candidate keyframe");
  checkCamera(current, "current keyframe");
  checkCamera(candidate, "candidate keyframe");
  if (settings.guided_min_inliers < 0 ||
      !(settings.guided_radius_px > 0.0 && std::isfinite(settings.guided_radius_px)))
    throw InputError("loop verification: guided_min_inliers must be >= 0 (got " +
                     std::to_string(settings.guided_min_inliers) +
                     ") and guided_radius_px finite and > 0 (got " +
                     std::to_string(settings.guided_radius_px) + ")");
  LoopVerification out;
  out.current_id = current.keyframe_id;
  out.candidate_id = candidate.keyframe_id;
  Verifier verifier(current, candidate, settings, out);
  out.accepted = verifier.run();
  if (out.accepted) {
    out.reason = "accepted";
  } else {
    out.inlier_matches.clear();
  }
  out.time_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (out.accepted) {
    spdlog::debug("loop {} -> {} accepted: {} inliers ({} with depth), scale {:.4f}, {:.1f} ms",
                  out.current_id, out.candidate_id, out.num_inliers, out.num_inliers_3d,
                  out.S_current_candidate.scale(), out.time_ms);
  } else {
    spdlog::debug("loop {} -> {} rejected: {}", out.current_id, out.candidate_id, out.reason);
  }
  return out;
}

}  // namespace ldsm::loop
