// Keyframe camera centres in a uniform hash grid, so that the keyframes near a position are found
// without looking at every keyframe of the map. The cell size is fixed at construction (map
// units; the monocular initialisation makes the first scene depth about 1). Not thread-safe (the
// MapStore guards it).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ldsm {

class SpatialIndex {
 public:
  explicit SpatialIndex(double cell_size = 0.5) : cell_(cell_size) {}

  /// Inserts or moves a keyframe.
  void set(int id, const Eigen::Vector3d& centre);
  void remove(int id);
  /// Keyframes whose centre lies within `radius` of `centre` (in no particular order).
  std::vector<int> near(const Eigen::Vector3d& centre, double radius) const;
  std::size_t size() const { return where_.size(); }

 private:
  using Key = std::int64_t;
  Key key(const Eigen::Vector3d& p) const;
  Key key(std::int64_t x, std::int64_t y, std::int64_t z) const;

  double cell_;
  std::unordered_map<Key, std::vector<int>> cells_;
  std::unordered_map<int, std::pair<Key, Eigen::Vector3d>> where_;
};

}  // namespace ldsm
