// Synthetic saved maps (mapfile/map_data.h) of any size with realistic contents, for the map file
// tests, the fuzz seeds and bench_map_file: a camera moving along a loop, data keyframes with
// points, corners, depths, descriptors and links, the point cloud, covisibility and pose graph.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mapfile/map_data.h"

namespace ldsm::test {

struct SyntheticMapSize {
  int keyframes = 10;
  int data_every = 1;  ///< every n-th keyframe keeps data (the others are poses only)
  int points_per_keyframe = 20;
  int corners_per_keyframe = 15;
  int links_per_keyframe = 4;
  int loop_edges = 2;
  std::size_t vocabulary_bytes = 64;
};

/// Deterministic on every platform (SplitMix64 and explicit arithmetic).
class MapRandom {
 public:
  explicit MapRandom(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0);
  }
  float uniformf(double lo, double hi) { return static_cast<float>(uniform(lo, hi)); }

 private:
  std::uint64_t s_;
};

inline MapData syntheticMap(const SyntheticMapSize& size, std::uint64_t seed = 1) {
  MapRandom rng(seed);
  MapData map;
  map.calibration.camera = PinholeIntrinsics{458.5, 457.25, 367.2, 248.4, 752, 480};
  map.calibration.radial_k = -0.0125;
  map.calibration.has_response = true;
  map.calibration.has_vignette = true;
  map.calibration.photometric_hash = 0x1234567890ABCDEFull;

  const double kTwoPi = 6.283185307179586;
  for (int i = 0; i < size.keyframes; ++i) {
    KeyframeRecord kf;
    kf.id = 2 * i;  // ids need not be contiguous
    kf.frame_index = 5 * i + 3;
    kf.timestamp = 1403636579.76 + 0.25 * i;
    const double a = kTwoPi * i / std::max(1, size.keyframes);
    Eigen::Matrix<double, 6, 1> x;
    x << 4.0 * std::cos(a), 1.5 * std::sin(a), 0.1 * rng.uniform(-1, 1), 0.05 * rng.uniform(-1, 1),
        a, 0.05 * rng.uniform(-1, 1);
    kf.T_w_c = SE3d(SO3d::exp(x.tail<3>()), x.head<3>());
    kf.scale = i % 7 == 3 ? 1.0 + 0.01 * rng.uniform(-1, 1) : 1.0;
    map.keyframes.push_back(kf);
  }

  for (int i = 0; i < size.keyframes; i += std::max(1, size.data_every)) {
    const KeyframeRecord& pose = map.keyframes[static_cast<std::size_t>(i)];
    MarginalizedKeyframe kf;
    kf.id = pose.id;
    kf.frame_index = pose.frame_index;
    kf.timestamp = pose.timestamp;
    kf.exposure = rng.uniform(5.0, 20.0);
    kf.aff = {rng.uniform(-0.3, 0.3), rng.uniform(-5, 5)};
    kf.T_w_c = pose.T_w_c;
    kf.radial_k = static_cast<float>(map.calibration.radial_k);
    kf.culled = i % 11 == 10;
    kf.map_points_in_view = static_cast<int>(rng.next() % 50);
    kf.path_length = 0.3 * i;
    kf.newest_when_left =
        map.keyframes[static_cast<std::size_t>(std::min(size.keyframes - 1, i + 6))].id;
    for (int j = 0; j < size.points_per_keyframe; ++j) {
      PatchPoint p;
      p.u = rng.uniformf(4, 748);
      p.v = rng.uniformf(4, 476);
      p.idepth = rng.uniformf(0.1, 2.0);
      p.idepth_hessian = rng.uniformf(0, 5000);
      for (float& c : p.colors) c = rng.uniformf(0, 255);
      for (float& g : p.grad_weights) g = rng.uniformf(0.05, 1);
      p.observations = static_cast<int>(rng.next() % 40);
      p.is_corner = rng.next() % 4 == 0;
      kf.points.push_back(p);
      HostedPoint h;
      const Eigen::Vector3d ray((p.u - 367.2) / 458.5, (p.v - 248.4) / 457.25, 1.0);
      h.position = (pose.T_w_c * (ray / static_cast<double>(p.idepth))).cast<float>();
      h.intensity = p.colors[4];
      h.is_corner = p.is_corner;
      h.host = kf.id;
      map.points.push_back(h);
    }
    for (int j = 0; j < size.corners_per_keyframe; ++j) {
      kf.corners.emplace_back(rng.uniformf(16, 736), rng.uniformf(16, 464));
      kf.corner_idepth.push_back(j % 3 == 0 ? std::numeric_limits<float>::quiet_NaN()
                                            : rng.uniformf(0.1, 2.0));
      kf.descriptors.push_back({rng.next(), rng.next(), rng.next(), rng.next()});
    }
    for (int k = 1; k <= size.links_per_keyframe && i - k >= 0; ++k) {
      const KeyframeRecord& other = map.keyframes[static_cast<std::size_t>(i - k)];
      KeyframeLink l;
      l.other = other.id;
      l.T_this_other = pose.T_w_c.inverse() * other.T_w_c;
      l.shared_points = static_cast<int>(rng.next() % 300);
      l.map_keyframe = k == 3;
      kf.links.push_back(l);
    }
    map.data.push_back(kf);
  }
  // A point without a host (a keyframe that was culled): allowed.
  if (!map.points.empty()) map.points.back().host = -1;

  for (int i = 1; i < size.keyframes; ++i) {
    const KeyframeRecord& a = map.keyframes[static_cast<std::size_t>(i - 1)];
    const KeyframeRecord& b = map.keyframes[static_cast<std::size_t>(i)];
    map.covisibility.push_back({a.id, b.id, 1 + static_cast<int>(rng.next() % 200)});
    MapGraphEdge e;
    e.from_id = a.id;
    e.to_id = b.id;
    e.kind = 0;
    e.S_from_to = Sim3d(a.T_w_c.inverse() * b.T_w_c);
    e.information.diagonal().setConstant(rng.uniform(1, 10));
    map.graph.push_back(e);
  }
  for (int l = 0; l < size.loop_edges && size.keyframes > 4; ++l) {
    const auto i =
        static_cast<std::size_t>(rng.next() % static_cast<std::uint64_t>(size.keyframes));
    const std::size_t j = (i + static_cast<std::size_t>(size.keyframes) / 2) %
                          static_cast<std::size_t>(size.keyframes);
    MapGraphEdge e;
    e.from_id = map.keyframes[i].id;
    e.to_id = map.keyframes[j].id;
    e.kind = 1 + l % 2;
    e.S_from_to =
        Sim3d(SO3d::exp(Eigen::Vector3d(0.01, -0.02, 0.03)),
              Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), 0.5), rng.uniform(0.9, 1.1));
    e.information = 100.0 * Eigen::Matrix<double, 7, 7>::Identity();
    e.information(0, 1) = e.information(1, 0) = 0.5;
    map.graph.push_back(e);
    map.covisibility.push_back({e.from_id, e.to_id, 30});
  }
  for (std::size_t b = 0; b < size.vocabulary_bytes; ++b)
    map.vocabulary.push_back(static_cast<std::uint8_t>(rng.next()));
  return map;
}

}  // namespace ldsm::test
