// Which keyframes of the map see the same places: an undirected weighted graph over keyframe ids,
// with edges between consecutive keyframes (they shared the window), between a new keyframe and
// the map keyframes reactivated for it, and between the two ends of a loop. Map reuse searches
// its neighbourhood for keyframes to bring back. Not thread-safe (the MapStore guards it).
#pragma once

#include <array>
#include <map>
#include <vector>

namespace ldsm {

class CovisibilityGraph {
 public:
  /// Adds `weight` to the edge a - b (created when absent); a == b is ignored.
  void connect(int a, int b, int weight = 1);
  /// Removes a keyframe and its edges.
  void remove(int id);
  /// Keyframes at most `hops` edges from any of `start` (excluding `start` itself), nearest
  /// first, at most `max_count`.
  std::vector<int> neighbourhood(const std::vector<int>& start, int hops,
                                 std::size_t max_count) const;
  int weight(int a, int b) const;
  std::size_t edgeCount() const;
  /// Every edge once (a < b), with its weight, in increasing (a, b) order.
  std::vector<std::array<int, 3>> edges() const;

 private:
  std::map<int, std::map<int, int>> edges_;
};

}  // namespace ldsm
