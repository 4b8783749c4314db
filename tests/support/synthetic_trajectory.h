// Synthetic trajectories with known geometry for the evaluation tests.
#pragma once

#include <unistd.h>
#include <cmath>
#include <string>

#include <filesystem>

#include "ldsm/eval/alignment.h"
#include "ldsm/types.h"

namespace ldsm::eval::testing {

/// A smooth 3-D curve (no straight or planar stretch) with smoothly turning orientation.
inline Trajectory curvedTrajectory(std::size_t n, double dt = 0.1, double t0 = 0.0) {
  Trajectory traj;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = t0 + dt * static_cast<double>(i);
    StampedPose sp;
    sp.timestamp = t;
    sp.pose.translation =
        Eigen::Vector3d(2.0 * std::cos(0.5 * t) + 0.3 * t, 1.5 * std::sin(0.7 * t),
                        0.4 * std::sin(0.3 * t) + 0.1 * t);
    sp.pose.rotation = Eigen::AngleAxisd(0.4 * t, Eigen::Vector3d::UnitZ()) *
                       Eigen::AngleAxisd(0.2 * std::sin(t), Eigen::Vector3d::UnitX()) *
                       Eigen::AngleAxisd(0.1 * std::cos(0.5 * t), Eigen::Vector3d::UnitY());
    traj.push_back(sp);
  }
  return traj;
}

/// Moves every pose of `traj` by the similarity `a` (positions mapped, orientations rotated).
inline Trajectory transformed(const Trajectory& traj, const Alignment& a) {
  Trajectory out;
  for (const auto& sp : traj) out.push_back({sp.timestamp, a.apply(sp.pose)});
  return out;
}

/// A similarity with a generic rotation.
inline Alignment makeSim3(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& t,
                          double scale) {
  Alignment a;
  a.rotation = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  a.translation = t;
  a.scale = scale;
  return a;
}

/// A fresh scratch folder under LDSM_TEST_TMP for one test.
inline std::string scratchDir(const std::string& name) {
  const std::string dir =
      std::string(LDSM_TEST_TMP) + "/eval_" + name + "_" + std::to_string(::getpid());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace ldsm::eval::testing
