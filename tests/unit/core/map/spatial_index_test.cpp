// The spatial index of keyframe centres and the covisibility graph of the map.
#include "map/spatial_index.h"

#include <gtest/gtest.h>

#include <random>

#include "map/covisibility_graph.h"

namespace ldsm {
namespace {

TEST(SpatialIndex, FindsExactlyTheCentresWithinTheRadius) {
  SpatialIndex index(0.5);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-3.0, 3.0);
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i < 400; ++i) {
    c.emplace_back(U(rng), U(rng), U(rng));
    index.set(i, c.back());
  }
  for (int q = 0; q < 50; ++q) {
    const Eigen::Vector3d p(U(rng), U(rng), U(rng));
    // Up to radii of many cells (13 cells at 6.5, spanning the whole map): the centre's
    // neighbours are found whatever the radius.
    for (const double r : {0.1, 0.7, 1.3, 2.5, 4.5, 6.5}) {
      std::vector<int> expected;
      for (int i = 0; i < 400; ++i)
        if ((c[i] - p).norm() <= r) expected.push_back(i);
      EXPECT_EQ(index.near(p, r), expected) << "radius " << r;
    }
  }
}

// A sparse map (keyframes along a 60-cell line) searched with a radius of 30 cells around its
// middle: the keyframes at the centre are found (the search once visited only the first 16 cells
// of each axis from the low corner of the box, and found none of them).
TEST(SpatialIndex, ALargeRadiusFindsTheKeyframesAtTheCentre) {
  SpatialIndex index(0.5);
  for (int i = 0; i <= 60; ++i) index.set(i, {0.5 * i, 0.1, 0.1});
  std::vector<int> all(61);
  for (int i = 0; i <= 60; ++i) all[static_cast<std::size_t>(i)] = i;
  EXPECT_EQ(index.near({15.0, 0.0, 0.0}, 16.0), all);
  const std::vector<int> middle = index.near({15.0, 0.0, 0.0}, 9.0);
  ASSERT_EQ(middle.size(), 35u);  // x = 6.5 .. 23.5 (6 and 24 are 9.0011 away)
  EXPECT_EQ(middle.front(), 13);
  EXPECT_EQ(middle.back(), 47);
}

TEST(SpatialIndex, MovedAndRemovedKeyframesAreFoundWhereTheyAre) {
  SpatialIndex index(1.0);
  index.set(1, {0, 0, 0});
  index.set(2, {5, 5, 5});
  index.set(1, {5.2, 5, 5});  // moved (loop correction)
  EXPECT_EQ(index.near({0, 0, 0}, 1.0), std::vector<int>{});
  EXPECT_EQ(index.near({5, 5, 5}, 1.0), (std::vector<int>{1, 2}));
  index.remove(2);
  EXPECT_EQ(index.near({5, 5, 5}, 1.0), std::vector<int>{1});
  EXPECT_EQ(index.size(), 1u);
  index.set(3, {-4.2, -0.1, 7.9});  // negative cells
  EXPECT_EQ(index.near({-4.0, 0.0, 8.0}, 0.5), std::vector<int>{3});
}

TEST(CovisibilityGraph, NeighbourhoodByHopsNearestFirst) {
  CovisibilityGraph g;
  for (int i = 0; i < 10; ++i) g.connect(i, i + 1);  // a chain 0 - 1 - ... - 10
  g.connect(10, 50);
  EXPECT_EQ(g.neighbourhood({10}, 1, 100), (std::vector<int>{9, 50}));
  EXPECT_EQ(g.neighbourhood({10}, 3, 100), (std::vector<int>{9, 50, 8, 7}));
  EXPECT_EQ(g.neighbourhood({10}, 3, 2).size(), 2u);
  EXPECT_EQ(g.weight(3, 4), 1);
  g.connect(4, 3, 2);
  EXPECT_EQ(g.weight(3, 4), 3);
  g.remove(5);
  EXPECT_EQ(g.neighbourhood({10}, 100, 100).size(), 5u);  // 9, 50, 8, 7, 6 then the cut
  EXPECT_EQ(g.edgeCount(), 9u);
}

}  // namespace
}  // namespace ldsm
