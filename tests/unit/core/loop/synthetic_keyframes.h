// Synthetic keyframe pairs for the loop-verification tests: random 3D points seen by a candidate
// and a current keyframe related by a known Sim(3), with ORB-like descriptors (random bits, a few
// flipped per keyframe), pixel and depth noise, features with and without depth, and outliers
// (features with random descriptors, and matched descriptors at wrong pixels).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "loop/loop_types.h"
#include "math/sim3.h"

namespace ldsm::loop::test {

struct SceneOptions {
  int num_points = 300;                   ///< 3D points generated in the candidate's view
  double pixel_noise = 0.5;               ///< std. dev. [px]
  double idepth_noise = 0.01;             ///< relative std. dev. of the inverse depths
  double current_depth_fraction = 0.5;    ///< current features that have a depth
  double candidate_depth_fraction = 0.8;  ///< candidate features that have a depth
  int bit_flips = 8;                      ///< per descriptor and keyframe (max)
  int extra_outliers = 100;               ///< features with random descriptors in each keyframe
  double wrong_pixel_fraction = 0.1;  ///< current features of true points moved to random pixels
  Sim3d S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(0.05, -0.12, 0.08)), Eigen::Vector3d(0.4, -0.15, 0.3), 1.35);
  unsigned seed = 1;
};

struct KeyframePair {
  KeyframeFeatures current, candidate;
  Sim3d S_current_candidate;  ///< ground truth
  int num_true = 0;           ///< true correspondences with correct pixels
};

inline PinholeIntrinsics testCamera(double f) {
  PinholeIntrinsics c;
  c.fx = f;
  c.fy = f;
  c.cx = 319.5;
  c.cy = 239.5;
  c.width = 640;
  c.height = 480;
  return c;
}

class SceneRandom {
 public:
  explicit SceneRandom(unsigned seed) : rng_(seed) {}
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  double normal(double s) { return std::normal_distribution<double>(0.0, s)(rng_); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  OrbDescriptor descriptor() {
    OrbDescriptor d;
    for (auto& w : d) w = rng_();
    return d;
  }
  OrbDescriptor flipped(OrbDescriptor d, int max_flips) {
    const int n = std::uniform_int_distribution<int>(0, max_flips)(rng_);
    for (int k = 0; k < n; ++k) {
      const int bit = std::uniform_int_distribution<int>(0, 255)(rng_);
      d[bit / 64] ^= std::uint64_t{1} << (bit % 64);
    }
    return d;
  }

 private:
  std::mt19937_64 rng_;
};

inline void addFeature(KeyframeFeatures& kf, const Eigen::Vector2d& px, double idepth,
                       const OrbDescriptor& d) {
  kf.pixels.push_back(px.cast<float>());
  kf.idepth.push_back(static_cast<float>(idepth));
  kf.descriptors.push_back(d);
}

inline bool inImage(const PinholeIntrinsics& c, const Eigen::Vector2d& px) {
  return px.x() >= 0 && px.y() >= 0 && px.x() <= c.width - 1 && px.y() <= c.height - 1;
}

/// Builds a keyframe pair; the features of the current keyframe are in a shuffled order.
inline KeyframePair makeKeyframePair(const SceneOptions& o) {
  SceneRandom rnd(o.seed);
  KeyframePair pair;
  pair.S_current_candidate = o.S_current_candidate;
  pair.candidate.keyframe_id = 3;
  pair.candidate.camera = testCamera(500.0);
  pair.current.keyframe_id = 90;
  pair.current.camera = testCamera(520.0);  // a different camera: each side must use its own
  const PinholeIntrinsics& cc = pair.candidate.camera;
  const PinholeIntrinsics& cu = pair.current.camera;
  std::vector<std::pair<Eigen::Vector2d, double>> cur_px;
  std::vector<OrbDescriptor> cur_desc;
  for (int i = 0; i < o.num_points; ++i) {
    const Eigen::Vector2d u(rnd.uniform(0, cc.width - 1), rnd.uniform(0, cc.height - 1));
    const double z = rnd.uniform(2.0, 8.0);
    const Eigen::Vector3d p((u.x() - cc.cx) / cc.fx * z, (u.y() - cc.cy) / cc.fy * z, z);
    const Eigen::Vector3d q = o.S_current_candidate * p;
    if (q.z() < 0.1) continue;
    const Eigen::Vector2d v(cu.fx * q.x() / q.z() + cu.cx, cu.fy * q.y() / q.z() + cu.cy);
    if (!inImage(cu, v)) continue;
    const OrbDescriptor base = rnd.descriptor();
    const double id_cand =
        rnd.chance(o.candidate_depth_fraction) ? (1.0 + rnd.normal(o.idepth_noise)) / z : 0.0;
    addFeature(pair.candidate,
               u + Eigen::Vector2d(rnd.normal(o.pixel_noise), rnd.normal(o.pixel_noise)), id_cand,
               rnd.flipped(base, o.bit_flips));
    Eigen::Vector2d vn = v + Eigen::Vector2d(rnd.normal(o.pixel_noise), rnd.normal(o.pixel_noise));
    if (rnd.chance(o.wrong_pixel_fraction)) {
      vn = Eigen::Vector2d(rnd.uniform(0, cu.width - 1), rnd.uniform(0, cu.height - 1));
    } else if (id_cand > 0) {
      ++pair.num_true;
    }
    const double id_cur =
        rnd.chance(o.current_depth_fraction) ? (1.0 + rnd.normal(o.idepth_noise)) / q.z() : 0.0;
    cur_px.emplace_back(vn, id_cur);
    cur_desc.push_back(rnd.flipped(base, o.bit_flips));
  }
  for (int i = 0; i < o.extra_outliers; ++i) {
    addFeature(pair.candidate,
               Eigen::Vector2d(rnd.uniform(0, cc.width - 1), rnd.uniform(0, cc.height - 1)),
               1.0 / rnd.uniform(2.0, 8.0), rnd.descriptor());
    cur_px.emplace_back(
        Eigen::Vector2d(rnd.uniform(0, cu.width - 1), rnd.uniform(0, cu.height - 1)),
        rnd.chance(0.5) ? 1.0 / rnd.uniform(1.0, 8.0) : 0.0);
    cur_desc.push_back(rnd.descriptor());
  }
  // Shuffle the current keyframe's features (a fixed permutation from the same generator).
  std::vector<int> order(cur_px.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  for (std::size_t i = order.size(); i > 1; --i) {
    const auto j = static_cast<std::size_t>(rnd.uniform(0.0, static_cast<double>(i)));
    std::swap(order[i - 1], order[std::min(j, i - 1)]);
  }
  for (const int k : order)
    addFeature(pair.current, cur_px[k].first, cur_px[k].second, cur_desc[k]);
  return pair;
}

/// Angle of the rotation between two similarity transforms [rad].
inline double rotationError(const Sim3d& a, const Sim3d& b) {
  return (a.so3().inverse() * b.so3()).log().norm();
}

}  // namespace ldsm::loop::test
