// DistanceMap (the spacing test of point activation) against a breadth-first search over the
// 4-neighbour grid, the formulation it replaced.
#include "backend/distance_map.h"

#include <gtest/gtest.h>

#include <deque>
#include <random>
#include <utility>
#include <vector>

namespace ldsm {
namespace {

/// Breadth-first city-block distances from the marked level-1 cells.
std::vector<int> bfsDistances(int w, int h, const std::vector<std::pair<int, int>>& cells) {
  constexpr int kFar = 1 << 20;
  std::vector<int> d(static_cast<std::size_t>(w) * h, kFar);
  std::deque<int> queue;
  for (const auto& [x, y] : cells) {
    d[static_cast<std::size_t>(y) * w + x] = 0;
    queue.push_back(y * w + x);
  }
  while (!queue.empty()) {
    const int i = queue.front();
    queue.pop_front();
    const int x = i % w, y = i / w;
    const int nb[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
    for (const auto& n : nb) {
      if (n[0] < 0 || n[1] < 0 || n[0] >= w || n[1] >= h) continue;
      const int j = n[1] * w + n[0];
      if (d[j] > d[i] + 1) {
        d[j] = d[i] + 1;
        queue.push_back(j);
      }
    }
  }
  return d;
}

// One map reset for every size and round (as the mapper keeps one) gives what a new map gives.
TEST(DistanceMap, EqualsTheBreadthFirstSearchOfTheCityBlockDistance) {
  std::mt19937 rng(7);
  DistanceMap map;
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{1, 1}, {7, 3}, {61, 40}, {308, 92}, {20, 9}}) {
    for (int marks : {0, 1, 3, 50, 400}) {
      std::uniform_int_distribution<int> ux(0, w - 1), uy(0, h - 1);
      std::vector<std::pair<int, int>> cells;
      map.reset(w, h);
      for (int k = 0; k < marks; ++k) {
        const int x = ux(rng), y = uy(rng);
        cells.emplace_back(x, y);
        map.mark(2.f * static_cast<float>(x), 2.f * static_cast<float>(y));  // level-0 pixels
      }
      map.propagate();
      const std::vector<int> expected = bfsDistances(w, h, cells);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          ASSERT_EQ(map.at(2.f * static_cast<float>(x), 2.f * static_cast<float>(y)),
                    expected[static_cast<std::size_t>(y) * w + x])
              << w << "x" << h << ", " << marks << " marks, cell " << x << "," << y;
    }
  }
}

TEST(DistanceMap, LevelZeroPixelsRoundToTheNearestCellAndOutsideIsMinusOne) {
  DistanceMap map(10, 6);
  map.mark(7.2f, 4.9f);  // cell (4, 2)
  map.propagate();
  EXPECT_EQ(map.at(8.f, 4.f), 0);
  EXPECT_EQ(map.at(12.f, 4.f), 2);
  EXPECT_EQ(map.at(8.f, 10.f), 3);
  EXPECT_EQ(map.at(-4.f, 0.f), -1);
  EXPECT_EQ(map.at(0.f, 12.f), -1);
  // A later mark counts at once, without spreading.
  map.mark(0.f, 0.f);
  EXPECT_EQ(map.at(0.f, 0.f), 0);
  EXPECT_EQ(map.at(2.f, 0.f), 5);
  map.mark(-10.f, 3.f);  // outside: ignored
}

}  // namespace
}  // namespace ldsm
