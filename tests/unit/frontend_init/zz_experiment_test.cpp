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
#include "init_access.h"
namespace ldsm { namespace {
TEST(Experiment, DISABLED_SinglePointGrad) {
  const PinholeIntrinsics K = test::makeIntrinsics(320, 240, 250);
  const test::PlaneScene scene = test::wallAndFloorScene();
  CoarseInitializerSettings s;
  s.affine_prior_weight_a = 0.f; s.affine_prior_weight_b = 0.f; s.outlier_rms = 1e4f;
  s.gradient_weight_c = (float)envd("GWC", 50); s.huber_threshold = (float)envd("HUB", 9);
  CoarseInitializer init(PyramidCamera(K, 5), s);
  std::mt19937 rng(1);
  ImagePyramid p0(K.width, K.height, 5), p1(K.width, K.height, 5);
  ImageF i0 = scene.render(SE3d(), K, 3, 0.f, &rng); p0.build(i0.view());
  init.addFrame(p0, 1.0);
  const SE3d T_w_f(SO3d::exp(Eigen::Vector3d(0.2, -0.3, 0.1) * kDeg), Eigen::Vector3d(0.05, 0.02, 0.03));
  ImageF i1 = scene.render(T_w_f, K, 3, 0.f, &rng); p1.build(i1.view());
  int level = (int)envd("LVL", 2);
  const auto& u = CoarseInitializerAccess::pixels(init, level);
  std::vector<float> d(u.size());
  const float s_l = (float)(1 << level);
  for (size_t i = 0; i < u.size(); ++i) d[i] = (float)(3.5 * scene.inverseDepth(SE3d(), K, (u[i].x()+0.5)*s_l-0.5, (u[i].y()+0.5)*s_l-0.5));
  SE3d T = T_w_f.inverse(); T.translation() /= 3.5;
  AffineLight aff{0,0};
  for (size_t i = 0; i < u.size(); i += u.size()/5) {
    std::vector<std::uint8_t> one(u.size(), 0); one[i] = 1;
    // analytic: evaluate with only this point? b includes all; so compute b with d for all but mask..., use difference trick: not available -> use numeric only vs b from one-point level? skip
    Eigen::Matrix<double,8,1> num;
    for (int j = 0; j < 6; ++j) { Eigen::Matrix<double,6,1> dl = Eigen::Matrix<double,6,1>::Zero(); dl(j) = 1e-4;
      num(j) = (CoarseInitializerAccess::energy(init, p1, level, SE3d::exp(dl)*T, aff, d, one, nullptr, nullptr, nullptr) - CoarseInitializerAccess::energy(init, p1, level, SE3d::exp(-dl)*T, aff, d, one, nullptr, nullptr, nullptr))/2e-4; }
    num(6)=num(7)=0;
    // analytic via removing all other points: set their depth to NaN-> invalid? set d huge negative so they're invalid
    std::vector<float> d1(d.size(), -1e6f); d1[i] = d[i];
    Eigen::Matrix<double,8,1> b; std::vector<std::uint8_t> inl;
    double e = CoarseInitializerAccess::energy(init, p1, level, T, aff, d1, one, &b, nullptr, &inl);
    printf("pt %zu (%.1f %.1f) good %d e %.2f\n num %s\n ana %s\n", i, u[i].x(), u[i].y(), inl[i], e, 
      ([&]{ char buf[200]; snprintf(buf, 200, "%9.1f %9.1f %9.1f %9.1f %9.1f %9.1f", num(0),num(1),num(2),num(3),num(4),num(5)); return std::string(buf);})().c_str(),
      ([&]{ char buf[200]; snprintf(buf, 200, "%9.1f %9.1f %9.1f %9.1f %9.1f %9.1f", b(0),b(1),b(2),b(3),b(4),b(5)); return std::string(buf);})().c_str());
  }
}
}}
#include "ldsm/image/interpolation.h"
namespace ldsm { namespace {
TEST(Experiment, DISABLED_ImageGrad) {
  const PinholeIntrinsics K = test::makeIntrinsics(320, 240, 250);
  const test::PlaneScene scene = test::wallAndFloorScene(envd("TS", 1));
  std::mt19937 rng(1);
  ImagePyramid p0(K.width, K.height, 5);
  ImageF i0 = scene.render(SE3d(), K, 3, 0.f, &rng); p0.build(i0.view());
  for (int lvl : {0, 2}) {
    auto g = p0.gradients(lvl); auto I = p0.intensity(lvl);
    double se = 0, sr = 0;
    for (float y = 5.3f; y < g.height - 5; y += 3.7f) for (float x = 5.1f; x < g.width - 5; x += 4.3f) {
      float h = 0.01f;
      float nx = (interpolateBilinear(I, x + h, y) - interpolateBilinear(I, x - h, y)) / (2*h);
      float ny = (interpolateBilinear(I, x, y + h) - interpolateBilinear(I, x, y - h)) / (2*h);
      auto gp = interpolateBilinear(g, x, y);
      se += (nx-gp.dx)*(nx-gp.dx) + (ny-gp.dy)*(ny-gp.dy); sr += nx*nx+ny*ny;
      if (std::getenv("PR") && lvl == 0 && ((int)x) % 40 == 5) printf("(%.1f %.1f) num %.3f %.3f  cd %.3f %.3f\n", x, y, nx, ny, gp.dx, gp.dy);
    }
    printf("level %d rel grad err %.3f\n", lvl, std::sqrt(se/sr));
  }
}
}}
namespace ldsm { namespace {
TEST(Experiment, DISABLED_Unrelated) {
  const PinholeIntrinsics K = test::makeIntrinsics(320, 240, 250);
  CoarseInitializerSettings s; applyEnv(s);
  CoarseInitializer init(PyramidCamera(K, 5), s);
  std::mt19937 rng(1);
  ImagePyramid p(K.width, K.height, 5);
  auto feed = [&](const test::PlaneScene& sc, const SE3d& T) { ImageF im = sc.render(T, K, 1, 1.f, &rng); p.build(im.view()); init.addFrame(p, 1.0);
    auto& st = init.lastFrameStats(); printf("%-20s flow %.2f par %.2f rms %.2f good %.2f fail %s\n", toString(init.status()), st.flow_translation, st.parallax, st.rms_residual, st.good_fraction, toString(init.failure())); };
  feed(test::wallAndFloorScene(), SE3d());
  feed(test::wallAndFloorScene(), SE3d(SO3d(), {0.01, 0, 0}));
  test::PlaneScene other; other.addPlane({0, 0, 2.0}, {0, 0, -1}, 99U);
  for (int i = 0; i < 4; ++i) feed(other, SE3d());
}
}}
