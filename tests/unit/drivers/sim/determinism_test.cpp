// Determinism: golden checksums of small rendered frames (and of the ground truth) that must be
// identical on every machine and architecture (x86-64, aarch64, armhf), and repeated renders
// that give identical bytes.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include "ldsm/drivers/sim/sim_source.h"
#include "sim_test_support.h"

namespace ldsm::drivers::sim {
namespace {

// Options that exercise every stage: noise, exposure changes, vignette, S-curve, edge AA.
SimOptions goldenOptions() {
  SimOptions o;
  o.width = 96;
  o.height = 72;
  o.noise_sigma = 2.0;
  o.exposure_changes = true;
  o.vignette = 0.4;
  o.response = SimResponse::SCurve;
  o.seed = 7;
  return o;
}

struct Golden {
  const char* scene;
  std::uint64_t frames;      // FNV-1a of the 8-bit frames listed below, in order
  std::uint64_t irradiance;  // FNV-1a of the float bits of the irradiance of the first one
  std::uint64_t trajectory;  // FNV-1a of the ground-truth doubles (t, tx ty tz, qw qx qy qz)
};

// Frames 0, 1 and 47 of each scene.
constexpr Golden kGolden[] = {
    {"loop", 0x90bf677034c1deabull, 0xac7adb995f66d17eull, 0x88c6a804accaada8ull},
    {"forward", 0xe27dc29af1b84b20ull, 0x0f81cf75f92c1523ull, 0xf57f20ba4a0e6b2dull},
    {"rotation", 0x18e2db306c2c697dull, 0x1b03fd101a4b1269ull, 0x6169fdc43b7ae401ull},
    {"short", 0x772aeb83dfea6348ull, 0x9e7d7aa9717c6ea3ull, 0x605af630ce0996caull},
};

std::uint64_t trajectoryChecksum(const Trajectory& t) {
  std::uint64_t h = test::fnv1a(nullptr, 0);
  for (const StampedPose& p : t) {
    const double v[8] = {
        p.timestamp,         p.pose.translation.x(), p.pose.translation.y(), p.pose.translation.z(),
        p.pose.rotation.w(), p.pose.rotation.x(),    p.pose.rotation.y(),    p.pose.rotation.z()};
    h = test::fnv1a(v, sizeof v, h);
  }
  return h;
}

TEST(SimDeterminism, GoldenChecksums) {
  for (const Golden& g : kGolden) {
    SimSource src(test::sharedScene(g.scene), goldenOptions());
    std::uint64_t frames = test::fnv1a(nullptr, 0);
    Frame f;
    for (std::int64_t i : {0, 1, 47}) {
      src.renderFrame(i, f);
      frames = test::fnv1a(f.image, frames);
    }
    ImageF irr;
    src.renderer().renderIrradiance(src.groundTruth()[0].pose, irr);
    const std::uint64_t irradiance = test::fnv1a(irr);
    const std::uint64_t trajectory = trajectoryChecksum(src.groundTruth());
    if (frames != g.frames || irradiance != g.irradiance || trajectory != g.trajectory) {
      // The line to put into kGolden after an intended change of the renderer (check that
      // aarch64 and armhf builds print the same).
      std::printf("    {\"%s\", 0x%016llxull, 0x%016llxull, 0x%016llxull},\n", g.scene,
                  static_cast<unsigned long long>(frames),
                  static_cast<unsigned long long>(irradiance),
                  static_cast<unsigned long long>(trajectory));
    }
    EXPECT_EQ(trajectory, g.trajectory) << g.scene << ": ground truth differs";
    EXPECT_EQ(irradiance, g.irradiance) << g.scene << ": irradiance differs";
    EXPECT_EQ(frames, g.frames) << g.scene << ": 8-bit frames differ";
  }
}

TEST(SimDeterminism, RepeatedAndIndependentRendersAreIdentical) {
  const SimOptions o = goldenOptions();
  SimSource a("short", o);
  SimSource b(test::sharedScene("short"), o);
  Frame fa, fb, fc;
  for (std::int64_t i : {3, 40, 3}) {
    a.renderFrame(i, fa);
    b.renderFrame(i, fb);
    EXPECT_EQ(test::fnv1a(fa.image), test::fnv1a(fb.image)) << "frame " << i;
  }
  // next() walks the same frames as renderFrame().
  b.seek(40);
  ASSERT_TRUE(b.next(fc));
  EXPECT_EQ(fc.index, 40);
  a.renderFrame(40, fa);
  EXPECT_EQ(test::fnv1a(fa.image), test::fnv1a(fc.image));
  // A different seed changes the noise only.
  SimOptions other = o;
  other.seed = 8;
  SimSource c(test::sharedScene("short"), other);
  c.renderFrame(40, fc);
  EXPECT_NE(test::fnv1a(fa.image), test::fnv1a(fc.image));
}

}  // namespace
}  // namespace ldsm::drivers::sim
