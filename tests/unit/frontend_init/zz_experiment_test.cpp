// TEMPORARY tuning harness (removed before hand-off).
#include <gtest/gtest.h>
#include <cstdlib>
#include <algorithm>
#include "init_test_util.h"
namespace ldsm {
namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
double envd(const char* n, double def) { const char* v = std::getenv(n); return v ? std::atof(v) : def; }
void applyEnv(CoarseInitializerSettings& s) {
  s.smoothness_weight = envd("SW", s.smoothness_weight); s.initial_lambda = envd("LAM", s.initial_lambda);
  s.smoothness_weight_parallax = envd("SWP", s.smoothness_weight_parallax);
  s.idepth_prior_weight = envd("WP", s.idepth_prior_weight);
  s.min_parallax_flow = envd("FLOW", s.min_parallax_flow);
  s.min_rotation_free_parallax = envd("PAR", s.min_rotation_free_parallax);
  s.confirm_frames = (int)envd("CONF", s.confirm_frames);
  s.convergence_energy_fraction = envd("CONV", s.convergence_energy_fraction);
  s.gradient_weight_c = (float)envd("GWC", s.gradient_weight_c);
  s.use_pixel_selector = envd("SEL", 1) > 0; s.selector_density = envd("DENS", s.selector_density);
  char n[8];
  for (int l = 0; l < 5; ++l) { snprintf(n, 8, "IT%d", l); s.max_iterations[l] = (int)envd(n, s.max_iterations[l]);
    snprintf(n, 8, "C%d", l); s.cell_size[l] = (int)envd(n, s.cell_size[l]); }
}
TEST(Experiment, DISABLED_Sweep) {
  const test::PlaneScene scene = test::wallAndFloorScene();
  const PinholeIntrinsics K = test::makeIntrinsics(320, 240, 250);
  struct C { const char* name; Eigen::Vector3d v; double yaw; };
  std::vector<C> cases = {{"side", {0.012,0,0}, 0}, {"sideturn", {-0.012,0.002,0}, 0.05}, {"fwd", {0,0,0.03},0}, {"diag", {0.008,-0.004,0.015}, -0.03}};
  for (auto& c : cases) {
    CoarseInitializerSettings s;
    applyEnv(s);
    std::vector<SE3d> poses;
    for (int i = 0; i < 40; ++i) poses.emplace_back(SO3d::exp(Eigen::Vector3d(0, c.yaw * kDeg * i, 0)), c.v * i);
    CoarseInitializer init(PyramidCamera(K, 5), s);
    auto run = test::runSequence(init, scene, poses, K, (float)envd("NOISE", 1.5), (unsigned)envd("SEED", 7), true, envd("VERB",0) > 0);
    if (run.completed_at < 0) { printf("%s: not done\n", c.name); continue; }
    const auto& r = init.result();
    SE3d Tt = poses[r.frames].inverse() * poses[0];
    std::vector<double> ratio, est, tru;
    for (auto& p : r.points) if (p.good) { double d = scene.inverseDepth(poses[0], K, p.u, p.v); ratio.push_back(d/p.idepth); est.push_back(p.idepth); tru.push_back(d);}
    auto rs = ratio; std::nth_element(rs.begin(), rs.begin()+rs.size()/2, rs.end()); double sc = rs[rs.size()/2];
    std::vector<double> err; for (size_t i=0;i<est.size();++i) err.push_back(std::abs(sc*est[i]-tru[i])/tru[i]);
    std::nth_element(err.begin(), err.begin()+err.size()/2, err.end());
    double ang = std::acos(std::clamp(Tt.translation().normalized().dot(r.T_frame_ref.translation().normalized()), -1.0, 1.0))/kDeg;
    double rot = (Tt.so3().inverse()*r.T_frame_ref.so3()).angle()/kDeg;
    printf("%-9s done@%2d pts %4zu deperr %5.2f%% tdir %5.2f rot %5.3f  %.1fms\n", c.name, run.completed_at, est.size(), 100*err[err.size()/2], ang, rot, run.ms_per_frame);
  }
}
}  // namespace
}  // namespace ldsm
namespace ldsm {
struct CoarseInitializerAccess {
  // Energy of level 0 at pose T after optimising depths only (pose fixed), `iters` GN steps.
  static double depthOnlyEnergy(CoarseInitializer& c, const ImagePyramid& frame, double exposure, SE3d T, int iters, bool reset_depths) {
    auto& L = c.levels_data_[0];
    c.frame_ = &frame;
    c.exposure_ratio_ = (float)(exposure / c.exposure_ref_);
    std::vector<float> d = L.idepth;
    if (reset_depths) std::fill(d.begin(), d.end(), 1.f);
    std::vector<float> ir(d.size());
    std::vector<CoarseInitializer::PointLinearization> lin(d.size());
    std::vector<std::uint8_t> good(d.size());
    CoarseInitializer::Evaluation ev;
    double E = 0;
    for (int it = 0; it < iters; ++it) {
      c.computeSmoothnessTargets(0, d.data(), ir.data());
      c.evaluate(0, T, c.affine_, d.data(), ir.data(), lin.data(), good.data(), ev);
      E = ev.energy;
      for (size_t i = 0; i < d.size(); ++i) d[i] -= lin[i].bd / (lin[i].hdd * 1.2f);
    }
    c.frame_ = nullptr;
    return E;
  }
  static double currentEnergy(CoarseInitializer& c, const ImagePyramid& frame, double exposure) {
    return depthOnlyEnergy(c, frame, exposure, c.T_, 1, false);
  }
};
namespace {
TEST(Experiment, DISABLED_EnergyAtTruth) {
  const test::PlaneScene scene = test::wallAndFloorScene();
  const PinholeIntrinsics K = test::makeIntrinsics(320, 240, 250);
  Eigen::Vector3d v(envd("VX", 0.012), envd("VY", 0), envd("VZ", 0));
  double yaw = envd("YAW", 0) * kDeg;
  CoarseInitializerSettings s;
  s.smoothness_weight = envd("SW", s.smoothness_weight); s.initial_lambda = envd("LAM", s.initial_lambda);
  s.confirm_frames = 100;
  CoarseInitializer init(PyramidCamera(K, 5), s);
  std::mt19937 rng(7);
  ImagePyramid pyr(K.width, K.height, 5);
  int N = (int)envd("N", 14);
  std::vector<SE3d> poses;
  for (int i = 0; i <= N; ++i) poses.emplace_back(SO3d::exp(Eigen::Vector3d(0, yaw * i, 0)), v * i);
  for (int i = 0; i <= N; ++i) {
    ImageF img = scene.render(poses[i], K, 2, (float)envd("NOISE", 0), &rng);
    pyr.build(img.view());
    init.addFrame(pyr, 1.0);
  }
  SE3d Tt = poses[N].inverse() * poses[0];
  SE3d Te = init.currentPose();
  // scale the true translation to the estimate's
  SE3d Tts(Tt.so3(), Tt.translation() * (Te.translation().norm() / Tt.translation().norm()));
  double e_cur = CoarseInitializerAccess::currentEnergy(init, pyr, 1.0);
  double e_cur_refit = CoarseInitializerAccess::depthOnlyEnergy(init, pyr, 1.0, Te, 30, false);
  double e_true = CoarseInitializerAccess::depthOnlyEnergy(init, pyr, 1.0, Tts, 30, false);
  double e_true_reset = CoarseInitializerAccess::depthOnlyEnergy(init, pyr, 1.0, Tts, 60, true);
  printf("est t=(%.4f %.4f %.4f) true t=(%.4f %.4f %.4f)\n", Te.translation().x(), Te.translation().y(), Te.translation().z(), Tts.translation().x(), Tts.translation().y(), Tts.translation().z());
  printf("E current %.1f, current refit %.1f, truth-pose refit %.1f, truth-pose from d=1 %.1f\n", e_cur, e_cur_refit, e_true, e_true_reset);
}
}  // namespace
}  // namespace ldsm
namespace ldsm { namespace {
TEST(Experiment, DISABLED_Timing640) {
  const test::PlaneScene scene = test::wallAndFloorScene();
  const PinholeIntrinsics K = test::makeIntrinsics(640, 480, 500);
  CoarseInitializerSettings s;
  applyEnv(s);
  s.confirm_frames = 100;
  std::vector<SE3d> poses;
  for (int i = 0; i < 12; ++i) poses.emplace_back(SO3d(), Eigen::Vector3d(0.01 * i, 0, 0));
  CoarseInitializer init(PyramidCamera(K, 5), s);
  auto run = test::runSequence(init, scene, poses, K, 1.5f, 7, true, envd("VERB", 0) > 0);
  for (int l = 0; l < init.levels(); ++l) printf("level %d: %d points\n", l, init.pointCount(l));
  printf("cpu %.2f ms per frame\n", run.ms_per_frame);
}
}}
