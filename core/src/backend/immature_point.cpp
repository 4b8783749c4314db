#include "backend/immature_point.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include "image/interpolation.h"
#include "kernels/pattern_energy.h"
#include "ldsm/error.h"

namespace ldsm {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// The pattern compared at positions of the target image: offsets already mapped into the
/// target, host intensities already mapped through the affine brightness transfer.
struct PatternMatcher {
  ImageView<const GradientPixel> image;
  float ox[kPatternSize], oy[kPatternSize];
  float expected[kPatternSize];
  const float* weights;
  float huber;
  simd::PatternEnergyParams simd;  ///< the above as the energy kernel takes them

  /// Sum of w_k * 2 huber(r_k) (r^2 inside the threshold k, 2k|r| - k^2 beyond).
  float energy(float x, float y) const { return simd::patternEnergy<simd::Vec4>(simd, x, y); }

  /// Energy and the 1-D Gauss-Newton terms (IRLS weights) for a shift along (dx, dy).
  void linearize(float x, float y, float dx, float dy, float& e, float& gradient,
                 float& hessian) const {
    e = gradient = hessian = 0.f;
    for (int k = 0; k < kPatternSize; ++k) {
      const GradientPixel p = interpolateBilinear(image, x + ox[k], y + oy[k]);
      const float r = p.intensity - expected[k];
      const float a = std::abs(r);
      const float j = p.dx * dx + p.dy * dy;
      const float hw = a <= huber ? 1.f : huber / a;
      e += weights[k] * (a <= huber ? r * r : huber * (2.f * a - huber));
      gradient += weights[k] * hw * r * j;
      hessian += weights[k] * hw * j * j;
    }
  }
};

/// Clips the parameter range [s0, s1] of the line p + s d to lo <= coordinate <= hi.
inline void clipAxis(float p, float d, float lo, float hi, float& s0, float& s1) {
  if (d == 0.f) {
    if (p < lo || p > hi) s1 = s0 - 1.f;  // empty
    return;
  }
  float a = (lo - p) / d;
  float b = (hi - p) / d;
  if (a > b) std::swap(a, b);
  s0 = std::max(s0, a);
  s1 = std::min(s1, b);
}

/// The pattern matcher for a host point seen through the local linear map J of the rotation-only
/// homography (identity unless settings.rotate_pattern): offsets, expected intensities (affine
/// transfer (scale, offset) of the host colours) and the pattern's radius in target pixels.
PatternMatcher orientedMatcher(ImageView<const GradientPixel> target, const Eigen::Matrix2f& J,
                               const float* weights, const float* colors,
                               const Eigen::Vector2f& affine, float huber, float* radius) {
  PatternMatcher m;
  m.image = target;
  m.weights = weights;
  m.huber = huber;
  *radius = 0.f;
  for (int k = 0; k < kPatternSize; ++k) {
    const Eigen::Vector2f o = J * Eigen::Vector2f(static_cast<float>(kPatternOffsets[k][0]),
                                                  static_cast<float>(kPatternOffsets[k][1]));
    m.ox[k] = o.x();
    m.oy[k] = o.y();
    *radius = std::max({*radius, std::abs(o.x()), std::abs(o.y())});
    m.expected[k] = affine.x() * colors[k] + affine.y();
    m.simd.ox[k] = m.ox[k];
    m.simd.oy[k] = m.oy[k];
    m.simd.expected[k] = m.expected[k];
    m.simd.weights[k] = weights[k];
  }
  m.simd.image = target;
  m.simd.huber = huber;
  return m;
}

/// The best match of the pattern on the line a + s dir, s in [s0, s1].
struct LineMatch {
  float s = 0.f;
  float energy = 0.f;
  float second = kInf;      ///< the lowest other local minimum (kInf: none)
  float best_energy = 0.f;  ///< of the 1-pixel walk, before refinement
};

/// Exhaustive 1-pixel walk (best and second best outside the best's neighbourhood), then
/// sub-pixel Gauss-Newton refinement along the line with steps of at most half a pixel.
LineMatch matchAlongLine(const PatternMatcher& m, const Eigen::Vector2f& a,
                         const Eigen::Vector2f& dir, float s0, float s1,
                         const TraceSettings& settings) {
  const int steps = static_cast<int>(s1 - s0) + 1;
  std::array<float, ImmaturePoint::kMaxSearchLength + 1> energies{};
  int best = 0;
  for (int i = 0; i < steps; ++i) {
    const float s = s0 + static_cast<float>(i);
    energies[i] = m.energy(a.x() + s * dir.x(), a.y() + s * dir.y());
    if (energies[i] < energies[best]) best = i;
  }
  LineMatch out;
  // The second best is the lowest other local minimum, so that the flanks of a broad best basin
  // do not count as ambiguity.
  for (int i = 0; i < steps; ++i) {
    if (std::abs(i - best) <= settings.second_best_radius || energies[i] >= out.second) continue;
    const bool left_ok = i == 0 || energies[i] <= energies[i - 1];
    const bool right_ok = i == steps - 1 || energies[i] <= energies[i + 1];
    if (left_ok && right_ok) out.second = energies[i];
  }
  out.best_energy = energies[best];
  float s = s0 + static_cast<float>(best);
  float e = energies[best];
  for (int it = 0; it < settings.refine_iterations; ++it) {
    float e_lin, g, h;
    m.linearize(a.x() + s * dir.x(), a.y() + s * dir.y(), dir.x(), dir.y(), e_lin, g, h);
    if (!(h > 0.f)) break;
    const float step = std::clamp(-g / h, -0.5f, 0.5f);
    const float s_new = std::clamp(s + step, s0, s1);
    const float e_new = m.energy(a.x() + s_new * dir.x(), a.y() + s_new * dir.y());
    if (!(e_new < e)) break;
    s = s_new;
    e = e_new;
    if (std::abs(step) < 1e-3f) break;
  }
  out.s = s;
  out.energy = e;
  return out;
}

/// Pattern orientation in the target: the local linear map of the rotation-only homography
/// KRKi at the host pixel (pr = KRKi (u, v, 1)); identity when not rotated or degenerate.
Eigen::Matrix2f patternOrientation(const Eigen::Matrix3f& KRKi, const Eigen::Vector3f& pr,
                                   bool rotate) {
  Eigen::Matrix2f J = Eigen::Matrix2f::Identity();
  if (rotate && pr.z() > 0.f) {
    const float iz = 1.f / pr.z();
    for (int r = 0; r < 2; ++r) {
      for (int c = 0; c < 2; ++c) J(r, c) = (KRKi(r, c) - pr[r] * iz * KRKi(2, c)) * iz;
    }
    if (!(std::abs(J.determinant()) > 1e-3f)) J.setIdentity();
  }
  return J;
}

/// Error bound along the epipolar line (pixels, into `error_px`) for the host pattern's gradient
/// moments G oriented by J: the target-image derivative of the pattern along a target direction
/// l is g_host^T J^-1 l, so a = sum (g^T J^-1 l)^2 and b the same across the line. kGood, or why
/// a search over the projected interval of `length` pixels would not narrow it.
TraceStatus lineErrorBound(const Eigen::Matrix2f& J, const Eigen::Matrix2f& G,
                           const Eigen::Vector2f& dir, float length, const TraceSettings& settings,
                           float& error_px) {
  const Eigen::Matrix2f J_inv = J.inverse();
  const Eigen::Vector2f l_host = J_inv * dir;
  const Eigen::Vector2f n_host = J_inv * Eigen::Vector2f(-dir.y(), dir.x());
  const float along = l_host.dot(G * l_host);
  const float across = n_host.dot(G * n_host);
  const float best_case = settings.matching_error + settings.epipolar_error;
  if (2.f * best_case * settings.min_improvement > length) {
    return TraceStatus::kSkipped;  // as converged as the matching accuracy allows
  }
  if (!(along > 0.f)) return TraceStatus::kBadCondition;
  error_px =
      settings.matching_error + settings.epipolar_error * std::sqrt((along + across) / along);
  if (!(2.f * error_px * settings.min_improvement <=
        std::min(length, settings.max_search_length))) {
    return TraceStatus::kBadCondition;
  }
  return TraceStatus::kGood;
}

/// The new inverse-depth interval: the inverse depths whose projections are s -+ error_px on the
/// line a_px + t dir, solved from the better conditioned image coordinate of
/// q = (pr + rho Kt).xy / (pr + rho Kt).z; [0, inf) where that leaves the valid range.
std::pair<float, float> idepthInterval(const Eigen::Vector3f& pr, const Eigen::Vector3f& Kt,
                                       const Eigen::Vector2f& a_px, const Eigen::Vector2f& dir,
                                       float s, float error_px) {
  const int c = std::abs(dir.x()) >= std::abs(dir.y()) ? 0 : 1;
  auto idepthAt = [&](float t) {
    const float q = a_px[c] + t * dir[c];
    return (pr[c] - q * pr.z()) / (q * Kt.z() - Kt[c]);
  };
  float new_min = idepthAt(s - error_px);
  float new_max = idepthAt(s + error_px);
  if (!(new_min >= 0.f) || !std::isfinite(new_min)) new_min = 0.f;
  if (!(new_max >= new_min) || !std::isfinite(new_max)) new_max = kInf;  // past the epipole
  return {new_min, new_max};
}

}  // namespace

const char* traceStatusName(TraceStatus status) {
  switch (status) {
    case TraceStatus::kUntraced:
      return "UNTRACED";
    case TraceStatus::kGood:
      return "GOOD";
    case TraceStatus::kOob:
      return "OOB";
    case TraceStatus::kOutlier:
      return "OUTLIER";
    case TraceStatus::kSkipped:
      return "SKIPPED";
    case TraceStatus::kBadCondition:
      return "BADCONDITION";
  }
  return "?";
}

ImmaturePoint::ImmaturePoint(ImageView<const GradientPixel> host, float u, float v,
                             float idepth_min, float idepth_max, float gradient_weight_c)
    : u_(u), v_(v), idepth_min_(idepth_min), idepth_max_(idepth_max) {
  // Built only when a check fails: this constructor runs for every selected pixel of a keyframe.
  const auto where = [u, v] {
    return "ImmaturePoint at (" + std::to_string(u) + ", " + std::to_string(v) + ")";
  };
  if (!(idepth_min >= 0.f) || !std::isfinite(idepth_min) || !(idepth_max >= idepth_min)) {
    throw InputError(where() + ": bad inverse depth interval [" + std::to_string(idepth_min) +
                     ", " + std::to_string(idepth_max) + "]");
  }
  if (!(gradient_weight_c > 0.f)) {
    throw InputError(where() + ": gradient weight constant must be > 0");
  }
  const float c2 = gradient_weight_c * gradient_weight_c;
  for (int k = 0; k < kPatternSize; ++k) {
    const float x = u + static_cast<float>(kPatternOffsets[k][0]);
    const float y = v + static_cast<float>(kPatternOffsets[k][1]);
    if (!isInsideForBilinear(host, x, y)) {
      throw InputError(where() + ": the pattern leaves the " + std::to_string(host.width) + "x" +
                       std::to_string(host.height) + " host image");
    }
    const GradientPixel p = interpolateBilinear(host, x, y);
    if (!std::isfinite(p.intensity) || !std::isfinite(p.dx) || !std::isfinite(p.dy)) {
      throw InputError(where() + ": non-finite host intensity or gradient");
    }
    colors_[k] = p.intensity;
    weights_[k] = c2 / (c2 + p.dx * p.dx + p.dy * p.dy);
    grad_xx_ += p.dx * p.dx;
    grad_xy_ += p.dx * p.dy;
    grad_yy_ += p.dy * p.dy;
  }
}

float ImmaturePoint::idepthEstimate() const {
  return std::isfinite(idepth_max_) ? 0.5f * (idepth_min_ + idepth_max_) : idepth_min_;
}

bool ImmaturePoint::isConverged(float max_relative_width, float min_quality) const {
  if (status_ == TraceStatus::kUntraced || status_ == TraceStatus::kOob ||
      status_ == TraceStatus::kOutlier) {
    return false;
  }
  if (!std::isfinite(idepth_max_)) return false;
  const float estimate = idepthEstimate();
  return estimate > 0.f && idepth_max_ - idepth_min_ <= max_relative_width * estimate &&
         quality_ >= min_quality;
}

TraceStatus ImmaturePoint::trace(ImageView<const GradientPixel> target, const LevelCamera& camera,
                                 const SE3f& T_target_host, const Eigen::Vector2f& affine,
                                 const TraceSettings& settings) {
  // A host point of inverse depth rho projects to the target pixel h(rho) = pr + rho Kt
  // (homogeneous), pr = K R K^-1 (u, v, 1), Kt = K t; its depth is positive iff h(rho).z > 0.
  const Eigen::Matrix3f K = camera.K();
  Eigen::Matrix3f K_inv;
  K_inv << camera.fxi, 0.f, camera.cxi, 0.f, camera.fyi, camera.cyi, 0.f, 0.f, 1.f;
  const Eigen::Matrix3f KRKi = K * T_target_host.rotationMatrix() * K_inv;
  const Eigen::Vector3f Kt = K * T_target_host.translation();
  const Eigen::Vector3f pr = KRKi * Eigen::Vector3f(u_, v_, 1.f);

  float rho_hi = idepth_max_;
  bool hi_unbounded = std::isinf(rho_hi);
  if (Kt.z() < 0.f) {  // depth reaches 0 at rho = -pr.z / Kt.z: the line goes to infinity there
    const float rho_zero = -pr.z() / Kt.z();
    if (rho_hi >= rho_zero) hi_unbounded = true;
  }
  const Eigen::Vector3f h_lo = pr + idepth_min_ * Kt;
  if (!(h_lo.z() > 0.f)) return status_ = TraceStatus::kOob;
  const Eigen::Vector2f a_px = h_lo.head<2>() / h_lo.z();
  if (!a_px.allFinite()) return status_ = TraceStatus::kOob;

  const Eigen::Matrix2f J = patternOrientation(KRKi, pr, settings.rotate_pattern);
  float radius = 0.f;
  const PatternMatcher m = orientedMatcher(target, J, weights_.data(), colors_.data(), affine,
                                           settings.huber_threshold, &radius);
  // Pattern samples stay inside the image, where bilinear interpolation reads valid pixels.
  const float margin = radius + 1.f;
  const float x_max = static_cast<float>(target.width - 1) - margin - 1e-3f;
  const float y_max = static_cast<float>(target.height - 1) - margin - 1e-3f;

  // Direction in which the projection moves as the inverse depth grows.
  Eigen::Vector2f dir = Kt.head<2>() - Kt.z() * a_px;
  const float dir_norm = dir.norm();
  if (!(dir_norm > 0.f) || !std::isfinite(dir_norm)) {  // no parallax (zero translation)
    last_pixel_interval_ = 0.f;
    const bool inside =
        a_px.x() >= margin && a_px.y() >= margin && a_px.x() <= x_max && a_px.y() <= y_max;
    return status_ = inside ? TraceStatus::kSkipped : TraceStatus::kOob;
  }
  dir /= dir_norm;

  float length = kInf;  // of the interval's projection
  if (!hi_unbounded) {
    const Eigen::Vector3f h_hi = pr + rho_hi * Kt;
    length = std::max((h_hi.head<2>() / h_hi.z() - a_px).dot(dir), 0.f);
  } else if (Kt.z() > 0.f && std::isinf(rho_hi)) {
    length = std::max((Kt.head<2>() / Kt.z() - a_px).dot(dir), 0.f);  // up to the epipole
  }
  last_pixel_interval_ = length;

  // Walkable part of the segment (from the idepth_min end, capped in length).
  float s0 = 0.f;
  float s1 = std::min({length, settings.max_search_length, static_cast<float>(kMaxSearchLength)});
  constexpr float kClipTolerance = 0.01f;  // clip a little inside, so the ends pass the check
  clipAxis(a_px.x(), dir.x(), margin + kClipTolerance, x_max - kClipTolerance, s0, s1);
  clipAxis(a_px.y(), dir.y(), margin + kClipTolerance, y_max - kClipTolerance, s0, s1);
  // The rectangle is convex, so both ends inside means the whole walk is inside; checking them
  // also guards against precision loss far outside the image.
  auto inside = [&](float t) {
    const Eigen::Vector2f q = a_px + t * dir;
    return q.x() >= margin && q.y() >= margin && q.x() <= x_max && q.y() <= y_max;
  };
  if (!(s0 <= s1) || !inside(s0) || !inside(s1)) return status_ = TraceStatus::kOob;
  if (!(length >= settings.min_search_length)) return status_ = TraceStatus::kSkipped;

  Eigen::Matrix2f G;
  G << grad_xx_, grad_xy_, grad_xy_, grad_yy_;
  float error_px = 0.f;
  const TraceStatus bound = lineErrorBound(J, G, dir, length, settings, error_px);
  if (bound != TraceStatus::kGood) return status_ = bound;

  const LineMatch match = matchAlongLine(m, a_px, dir, s0, s1, settings);
  if (std::isfinite(match.second)) quality_ = match.second / std::max(match.best_energy, 1e-3f);
  const float s = match.s;
  const float e = match.energy;
  last_match_ = a_px + s * dir;
  last_energy_ = e;
  const float max_energy =
      static_cast<float>(kPatternSize) * settings.outlier_threshold * settings.outlier_threshold;
  if (!(e <= max_energy)) {
    ++outlier_count_;
    return status_ = TraceStatus::kOutlier;
  }

  std::tie(idepth_min_, idepth_max_) = idepthInterval(pr, Kt, a_px, dir, s, error_px);
  return status_ = TraceStatus::kGood;
}

}  // namespace ldsm
