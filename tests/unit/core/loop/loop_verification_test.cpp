// Loop verification on synthetic keyframe pairs with a known Sim(3): accuracy of the recovered
// transform, and a rejection (with its reason) for unrelated candidates, inconsistent geometry,
// too few inliers and missing depth.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "ldsm/error.h"
#include "loop/descriptor_matcher.h"
#include "loop/loop_verification.h"
#include "synthetic_keyframes.h"

namespace ldsm::loop {
namespace {

using test::KeyframePair;
using test::makeKeyframePair;
using test::rotationError;
using test::SceneOptions;

constexpr double kDeg = M_PI / 180.0;

void expectAccurate(const LoopVerification& v, const Sim3d& truth, double rot_tol_deg,
                    double trans_tol, double scale_tol) {
  ASSERT_TRUE(v.accepted) << v.reason;
  EXPECT_EQ(v.reason, "accepted");
  EXPECT_LT(rotationError(v.S_current_candidate, truth), rot_tol_deg * kDeg);
  EXPECT_LT((v.S_current_candidate.translation() - truth.translation()).norm(),
            trans_tol * truth.translation().norm());
  EXPECT_NEAR(v.S_current_candidate.scale() / truth.scale(), 1.0, scale_tol);
}

// How far the match's current pixel lies from where the candidate's feature, at its depth, lands
// under the true transform [px].
double trueReprojectionError(const KeyframePair& pair, const DescriptorMatch& m) {
  const Eigen::Vector2f& u = pair.candidate.pixels[m.train];
  const double z = 1.0 / pair.candidate.idepth[m.train];
  const PinholeIntrinsics& c = pair.candidate.camera;
  const Eigen::Vector3d p((u.x() - c.cx) / c.fx * z, (u.y() - c.cy) / c.fy * z, z);
  const Eigen::Vector3d q = pair.S_current_candidate * p;
  const PinholeIntrinsics& k = pair.current.camera;
  const Eigen::Vector2d px(k.fx * q.x() / q.z() + k.cx, k.fy * q.y() / q.z() + k.cy);
  return (px - pair.current.pixels[m.query].cast<double>()).norm();
}

TEST(LoopVerification, RecoversTheSim3WithNoiseAndOutliers) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SceneOptions o;
    o.seed = seed;
    const KeyframePair pair = makeKeyframePair(o);
    const LoopVerification v = verifyLoop(pair.current, pair.candidate, {});
    SCOPED_TRACE(seed);
    // 0.5 px noise, 1 % inverse-depth noise, 10 % wrong pixels, 100 unrelated features each.
    expectAccurate(v, pair.S_current_candidate, 0.15, 0.02, 0.005);
    EXPECT_EQ(v.current_id, 90);
    EXPECT_EQ(v.candidate_id, 3);
    EXPECT_GE(v.num_inliers, 0.8 * pair.num_true);
    EXPECT_LE(v.num_inliers, v.num_matches_with_depth);
    EXPECT_GE(v.num_inliers_3d, 30);
    EXPECT_LT(v.rms_reprojection_px, 1.5);
    EXPECT_EQ(static_cast<int>(v.inlier_matches.size()), v.num_inliers);
    // Every inlier is geometrically right: the candidate's true point lands near its pixel.
    for (const DescriptorMatch& m : v.inlier_matches)
      EXPECT_LT(trueReprojectionError(pair, m), 5.0);
  }
}

TEST(LoopVerification, ScaleBelowOneAndLargerRotation) {
  SceneOptions o;
  o.S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(-0.1, 0.25, -0.3)), Eigen::Vector3d(-0.2, 0.1, 0.15), 0.6);
  o.num_points = 500;
  const KeyframePair pair = makeKeyframePair(o);
  expectAccurate(verifyLoop(pair.current, pair.candidate, {}), pair.S_current_candidate, 0.15, 0.03,
                 0.005);
}

// LDSM's relative scale: with a long baseline the two PnP solutions' translations give it before
// any refinement; with a short one (here almost a pure rotation) the depth ratio does.
TEST(LoopVerification, ScaleFromPnpSolvedBothWays) {
  SceneOptions o;
  o.S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(0.02, -0.1, 0.05)), Eigen::Vector3d(0.9, -0.2, 0.6), 1.35);
  o.num_points = 500;
  const KeyframePair far = makeKeyframePair(o);
  const LoopVerification v = verifyLoop(far.current, far.candidate, {});
  ASSERT_TRUE(v.accepted) << v.reason;
  EXPECT_TRUE(v.scale_from_both_ways);
  EXPECT_NEAR(v.initial_scale, 1.35, 0.05 * 1.35);
  o.S_current_candidate =
      Sim3d(SO3d::exp(Eigen::Vector3d(0.02, -0.1, 0.05)), Eigen::Vector3d(0.01, 0.0, -0.01), 1.35);
  const KeyframePair near = makeKeyframePair(o);
  const LoopVerification w = verifyLoop(near.current, near.candidate, {});
  ASSERT_TRUE(w.accepted) << w.reason;
  EXPECT_FALSE(w.scale_from_both_ways);
  EXPECT_NEAR(w.initial_scale, 1.35, 0.05 * 1.35);
}

TEST(LoopVerification, NoisyDepthsWithLdsoSplitStillAccurate) {
  SceneOptions o;
  o.idepth_noise = 0.04;
  o.seed = 5;
  const KeyframePair pair = makeKeyframePair(o);
  LoopVerificationSettings s;
  s.refinement.reprojection_for_depth_matches = false;  // 3D only where the current has depth
  s.refinement.depth_relative_sigma = 0.08;
  const LoopVerification ldso = verifyLoop(pair.current, pair.candidate, s);
  expectAccurate(ldso, pair.S_current_candidate, 0.3, 0.05, 0.025);  // ~0.8 % scale std
  s.refinement.reprojection_for_depth_matches = true;
  const LoopVerification both = verifyLoop(pair.current, pair.candidate, s);
  expectAccurate(both, pair.S_current_candidate, 0.3, 0.05, 0.025);
}

TEST(LoopVerification, RejectsAnUnrelatedCandidate) {
  SceneOptions a, b;
  a.seed = 11;
  b.seed = 12;  // other points, other descriptors
  const KeyframePair pa = makeKeyframePair(a), pb = makeKeyframePair(b);
  const LoopVerification v = verifyLoop(pa.current, pb.candidate, {});
  EXPECT_FALSE(v.accepted);
  EXPECT_NE(v.reason.find("ORB matches"), std::string::npos) << v.reason;
  EXPECT_LT(v.num_matches, 10);
  EXPECT_TRUE(v.inlier_matches.empty());
}

TEST(LoopVerification, RejectsMatchingDescriptorsWithInconsistentGeometry) {
  // The same descriptors, but the candidate's pixels and depths are permuted: matches abound, no
  // transform explains them.
  SceneOptions o;
  o.seed = 13;
  KeyframePair pair = makeKeyframePair(o);
  auto& c = pair.candidate;
  const std::size_t n = c.pixels.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i * 97 + 31) % n;
    std::swap(c.pixels[i], c.pixels[j]);
    std::swap(c.idepth[i], c.idepth[j]);
  }
  const LoopVerification v = verifyLoop(pair.current, c, {});
  EXPECT_FALSE(v.accepted);
  EXPECT_GE(v.num_matches, 100);
  EXPECT_TRUE(v.reason.find("PnP") != std::string::npos ||
              v.reason.find("inliers") != std::string::npos)
      << v.reason;
}

// A repeating texture (a facade's windows, a tiled floor): most candidate features have a twin
// elsewhere in the image with the same descriptor, so the global matching's ratio test drops
// them, and of the matches left many are wrong (60 % of the current features moved): PnP finds
// too few inliers and, without the guided search, the place is rejected. From that PnP's pose
// each candidate point is looked for near its predicted pixel only, where its twin's match is
// not: the loop is accepted with nearly every true correspondence, accurately.
//
// The scene is random, and its draws (and so how many right matches the global matching keeps)
// change with the build: a sanitizer build drew other scenes from the same seeds. The test takes
// the first three seeds whose global matches hold 13-17 right ones with candidate depth: enough
// for the guided search to start from (12), too few to pass without it (20), in any build.
KeyframePair repeatingTexturePair(unsigned seed) {
  SceneOptions o;
  o.seed = seed;
  o.wrong_pixel_fraction = 0.6;
  KeyframePair pair = makeKeyframePair(o);
  test::SceneRandom rnd(99);
  KeyframeFeatures& cand = pair.candidate;
  const std::size_t n = cand.pixels.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!rnd.chance(0.85)) continue;
    const Eigen::Vector2d twin(rnd.uniform(0, cand.camera.width - 1),
                               rnd.uniform(0, cand.camera.height - 1));
    test::addFeature(cand, twin, 1.0 / rnd.uniform(2.0, 8.0), cand.descriptors[i]);
  }
  return pair;
}

// How many of the global matches are right and have a candidate depth (PnP's input).
int rightGlobalMatchesWithDepth(const KeyframePair& pair) {
  int right = 0;
  for (const DescriptorMatch& m :
       matchDescriptors(pair.current, pair.candidate, LoopVerificationSettings{}.matching))
    right += pair.candidate.idepth[m.train] > 0.0f && trueReprojectionError(pair, m) < 4.0;
  return right;
}

TEST(LoopVerification, AGuidedSearchFindsTheMatchesARepeatingTextureHides) {
  int tested = 0;
  for (unsigned seed = 1; seed <= 40 && tested < 3; ++seed) {
    const KeyframePair pair = repeatingTexturePair(seed);
    const int right = rightGlobalMatchesWithDepth(pair);
    if (right < 13 || right > 17) continue;
    ++tested;
    SCOPED_TRACE(seed);
    LoopVerificationSettings unguided;
    unguided.guided_min_inliers = 0;
    const LoopVerification without = verifyLoop(pair.current, pair.candidate, unguided);
    const LoopVerification with = verifyLoop(pair.current, pair.candidate, {});
    std::printf(
        "seed %u: %d global matches (%d right with depth), %d PnP inliers (%s); with %d guided "
        "matches %d inliers of %d true correspondences\n",
        seed, without.num_matches, right, without.num_pnp_inliers, without.reason.c_str(),
        with.num_guided_matches, with.num_inliers, pair.num_true);
    EXPECT_FALSE(without.accepted);
    EXPECT_NE(without.reason.find("PnP"), std::string::npos) << without.reason;
    // PnP found the right matches' pose (not a chance fit), which the guided search starts from.
    EXPECT_GE(without.num_pnp_inliers, right - 1);
    // About 40 inliers with depth on both sides (half of RecoversTheSim3's): over the 56 scenes
    // of seeds 1-120 that qualify, rms errors 0.043 deg, 0.95 % of the translation and 0.26 % in
    // scale (at most 0.08 deg, 1.8 %, 0.52 %). The bounds are about 4 of those deviations, so that
    // another build's scenes pass too; a wrong pose misses them by far.
    expectAccurate(with, pair.S_current_candidate, 0.15, 0.04, 0.01);
    EXPECT_GT(with.num_guided_matches, 2 * without.num_pnp_inliers);
    EXPECT_GE(with.num_inliers, 0.8 * pair.num_true);
  }
  EXPECT_EQ(tested, 3);
}

TEST(LoopVerification, RejectsTooFewInliers) {
  SceneOptions o;
  o.seed = 14;
  o.num_points = 60;
  o.wrong_pixel_fraction = 0.5;  // about 20 true correspondences among ~45 with depth
  const KeyframePair pair = makeKeyframePair(o);
  ASSERT_LT(pair.num_true, 25);
  ASSERT_GT(pair.num_true, 12);
  // Asking for clearly more inliers than there are true correspondences must reject. Not the
  // default threshold (20): natively PnP keeps the 19 true ones and stops there, under
  // qemu-aarch64 RANSAC kept at least 20 (wrong matches fitting by chance): accepted.
  LoopVerificationSettings strict;
  strict.pnp.min_inliers = pair.num_true + 5;
  strict.min_inliers = pair.num_true + 5;
  const LoopVerification v = verifyLoop(pair.current, pair.candidate, strict);
  EXPECT_FALSE(v.accepted);
  EXPECT_NE(v.reason.find("inliers"), std::string::npos) << v.reason;
  // With a low enough threshold the same pair is accepted (the thresholds are what decides).
  LoopVerificationSettings s;
  s.pnp.min_inliers = 8;
  s.min_inliers = 8;
  s.min_inliers_3d = 4;
  const LoopVerification low = verifyLoop(pair.current, pair.candidate, s);
  EXPECT_TRUE(low.accepted) << low.reason;
}

TEST(LoopVerification, RejectsWhenTheCurrentKeyframeHasNoDepth) {
  SceneOptions o;
  o.current_depth_fraction = 0.0;
  o.extra_outliers = 0;
  KeyframePair pair = makeKeyframePair(o);
  const LoopVerification v = verifyLoop(pair.current, pair.candidate, {});
  EXPECT_FALSE(v.accepted);
  EXPECT_NE(v.reason.find("scale"), std::string::npos) << v.reason;
  EXPECT_GE(v.num_pnp_inliers, 100);  // the pose alone was found
}

TEST(LoopVerification, RejectsWithoutCandidateDepth) {
  SceneOptions o;
  o.candidate_depth_fraction = 0.0;
  o.extra_outliers = 0;
  const KeyframePair pair = makeKeyframePair(o);
  const LoopVerification v = verifyLoop(pair.current, pair.candidate, {});
  EXPECT_FALSE(v.accepted);
  EXPECT_NE(v.reason.find("candidate depth"), std::string::npos) << v.reason;
}

TEST(LoopVerification, BadInputThrows) {
  const KeyframePair pair = makeKeyframePair(SceneOptions{});
  KeyframeFeatures bad = pair.candidate;
  bad.descriptors.pop_back();
  EXPECT_THROW(verifyLoop(pair.current, bad, {}), InputError);
  bad = pair.current;
  bad.camera.fx = 0.0;
  EXPECT_THROW(verifyLoop(bad, pair.candidate, {}), InputError);
  bad = pair.candidate;
  bad.camera.cy = std::nan("");
  EXPECT_THROW(verifyLoop(pair.current, bad, {}), InputError);
  for (const double radius : {0.0, -1.0, std::nan("")}) {
    LoopVerificationSettings s;
    s.guided_radius_px = radius;
    EXPECT_THROW(verifyLoop(pair.current, pair.candidate, s), InputError) << radius;
  }
  LoopVerificationSettings negative;
  negative.guided_min_inliers = -1;
  EXPECT_THROW(verifyLoop(pair.current, pair.candidate, negative), InputError);
}

}  // namespace
}  // namespace ldsm::loop
