// The window's adaptive outlier threshold (DSO's rule): its value from the residual energies of a
// keyframe, and that the larger threshold of a pair's two keyframes decides inlier or outlier.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "backend/photometric_residual.h"

namespace ldsm {
namespace {

float patternEnergyOfRms(double rms) {
  return static_cast<float>(rms * rms * kPatternSize);
}

TEST(AdaptiveOutlierThreshold, FollowsTheSeventiethPercentile) {
  // Every residual at 10 grey levels RMS: th = (9.19 + 1.5 * 10) / 2 = 12.095.
  std::vector<float> flat(100, patternEnergyOfRms(10.0));
  EXPECT_NEAR(adaptiveOutlierEnergy(flat), patternEnergyOfRms(12.095), 1e-2);
  // RMS 0..99 in a random order: the 70th percentile is 69 whatever the order.
  std::vector<float> spread;
  for (int i = 0; i < 100; ++i) spread.push_back(patternEnergyOfRms(i));
  std::shuffle(spread.begin(), spread.end(), std::mt19937(3));
  EXPECT_NEAR(adaptiveOutlierEnergy(spread), patternEnergyOfRms(0.5 * (9.19 + 1.5 * 69)), 1e-1);
  // Noisier images (twice the residuals) get a higher threshold, sharp ones a lower one.
  std::vector<float> noisy(100, patternEnergyOfRms(20.0));
  std::vector<float> clean(100, patternEnergyOfRms(2.0));
  EXPECT_GT(adaptiveOutlierEnergy(noisy), patternEnergyOfRms(19.0));
  EXPECT_LT(adaptiveOutlierEnergy(clean), patternEnergyOfRms(6.5));
}

TEST(AdaptiveOutlierThreshold, TooFewResidualsKeepTheFixedOne) {
  std::vector<float> few(19, patternEnergyOfRms(10.0));
  EXPECT_EQ(adaptiveOutlierEnergy(few), 0.f);
  std::vector<float> none;
  EXPECT_EQ(adaptiveOutlierEnergy(none), 0.f);
}

TEST(AdaptiveOutlierThreshold, ThePairTakesTheLargerKeyframeThreshold) {
  ResidualSettings settings;
  FramePairPrecalc pair;
  EXPECT_EQ(outlierEnergy(pair, settings), settings.outlier_energy);  // nothing adapted yet
  pair.outlier_energy = 500.f;
  EXPECT_EQ(outlierEnergy(pair, settings), 500.f);
}

}  // namespace
}  // namespace ldsm
