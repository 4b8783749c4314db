// The map's median depth: per keyframe the median of its points' depths (inverse depths that are
// not positive left out), scaled by the keyframe's Sim(3) scale, and the median over keyframes.
#include "map/map_depth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>

namespace ldsm {
namespace {

PatchPoint pointAtDepth(float depth) {
  PatchPoint p;
  p.idepth = 1.f / depth;
  return p;
}

std::shared_ptr<const MarginalizedKeyframe> keyframeWithDepths(int id, std::vector<float> depths) {
  auto kf = std::make_shared<MarginalizedKeyframe>();
  kf->id = id;
  for (const float d : depths) kf->points.push_back(pointAtDepth(d));
  return kf;
}

KeyframeRecord record(int id, double scale) {
  KeyframeRecord r;
  r.id = id;
  r.scale = scale;
  return r;
}

TEST(MapDepth, AKeyframesMedianLeavesOutPointsWithoutAPositiveInverseDepth) {
  std::vector<PatchPoint> points = {pointAtDepth(2.f), pointAtDepth(8.f), pointAtDepth(4.f)};
  PatchPoint behind;
  behind.idepth = -0.5f;
  PatchPoint unknown;
  unknown.idepth = std::numeric_limits<float>::quiet_NaN();
  PatchPoint zero;
  points.push_back(behind);
  points.push_back(unknown);
  points.push_back(zero);
  const std::optional<double> d = medianHostDepth(points);
  ASSERT_TRUE(d.has_value());
  EXPECT_FLOAT_EQ(static_cast<float>(*d), 4.f);
  EXPECT_FALSE(medianHostDepth({behind, unknown, zero}).has_value());
  EXPECT_FALSE(medianHostDepth({}).has_value());
}

TEST(MapDepth, TheMapsMedianIsOverKeyframesInWorldUnits) {
  StoredMap map;
  // Keyframe 0 sees things 3 units away, 1 at 1 unit but scaled by 5 (a loop correction), 2 at
  // 10 units; 3 has no points, 4 no record: neither counts.
  map.keyframes = {record(0, 1.0), record(1, 5.0), record(2, 1.0), record(3, 1.0)};
  map.data = {keyframeWithDepths(0, {2.f, 3.f, 3.5f}), keyframeWithDepths(1, {0.5f, 1.f, 2.f}),
              keyframeWithDepths(2, {10.f}), keyframeWithDepths(3, {}),
              keyframeWithDepths(4, {0.01f, 0.01f, 0.01f})};
  const std::optional<double> d = medianKeyframeDepth(map);
  ASSERT_TRUE(d.has_value());
  // Per keyframe 3, 5 and 10: the median is 5 (without the scale it would be 3).
  EXPECT_NEAR(*d, 5.0, 1e-6);
  map.keyframes[1].scale = 1.0;
  EXPECT_NEAR(*medianKeyframeDepth(map), 3.0, 1e-6);
}

TEST(MapDepth, AMapWithoutPointsHasNoMedianDepth) {
  StoredMap map;
  EXPECT_FALSE(medianKeyframeDepth(map).has_value());
  map.keyframes = {record(0, 1.0)};
  map.data = {keyframeWithDepths(0, {})};
  EXPECT_FALSE(medianKeyframeDepth(map).has_value());
}

}  // namespace
}  // namespace ldsm
