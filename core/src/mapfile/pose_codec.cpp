#include "mapfile/pose_codec.h"

#include <cmath>
#include <limits>

#include "mapfile/map_checks.h"

namespace ldsm::mapfile {
namespace {

bool isFixedPoint(const Eigen::Quaterniond& q) {
  return SO3d(q).quaternion().coeffs() == q.coeffs();
}

void writeQuaternion(ByteWriter& w, const Eigen::Quaterniond& q) {
  const Eigen::Quaterniond c = canonicalQuaternion(q);
  w.f64(c.x());
  w.f64(c.y());
  w.f64(c.z());
  w.f64(c.w());
}

Eigen::Quaterniond readQuaternion(ByteReader& r, const char* what) {
  const double x = r.f64();
  const double y = r.f64();
  const double z = r.f64();
  const double w = r.f64();
  const Eigen::Quaterniond q(w, x, y, z);
  if (!q.coeffs().allFinite()) r.fail(std::string(what) + ": rotation is not finite");
  // Written normalised: anything but a unit quaternion is a corrupt (or forged) file.
  const double norm = q.norm();
  if (!(std::abs(norm - 1.0) <= 1e-6))
    r.fail(std::string(what) + ": rotation is not a unit quaternion (norm " + numberText(norm) +
           ")");
  return q;
}

Eigen::Vector3d readVector(ByteReader& r, const char* what) {
  Eigen::Vector3d t;
  for (int i = 0; i < 3; ++i) t[i] = r.f64();
  if (!t.allFinite()) r.fail(std::string(what) + ": translation is not finite");
  return t;
}

}  // namespace

Eigen::Quaterniond canonicalQuaternion(const Eigen::Quaterniond& q) {
  const Eigen::Quaterniond n = SO3d(q).quaternion();
  if (isFixedPoint(n)) return n;
  // Normalising again may alternate between neighbours; stepping the largest coefficient by a
  // few units in the last place finds one that stays (at most 4 steps on 2 million random
  // rotations).
  int big = 0;
  for (int k = 1; k < 4; ++k)
    if (std::abs(n.coeffs()[k]) > std::abs(n.coeffs()[big])) big = k;
  for (int steps = 1; steps <= 64; ++steps) {
    for (const double toward :
         {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()}) {
      Eigen::Quaterniond c = n;
      for (int s = 0; s < steps; ++s) c.coeffs()[big] = std::nextafter(c.coeffs()[big], toward);
      if (isFixedPoint(c)) return c;
    }
  }
  return n;  // not reached in practice; the file is still valid, only not byte-stable
}

void writeSE3(ByteWriter& w, const SE3d& T) {
  writeQuaternion(w, T.quaternion());
  for (int i = 0; i < 3; ++i) w.f64(T.translation()[i]);
}

void writeSim3(ByteWriter& w, const Sim3d& S) {
  writeQuaternion(w, S.quaternion());
  for (int i = 0; i < 3; ++i) w.f64(S.translation()[i]);
  w.f64(S.scale());
}

SE3d readSE3(ByteReader& r, const char* what) {
  const Eigen::Quaterniond q = readQuaternion(r, what);
  return SE3d(q, readVector(r, what));
}

Sim3d readSim3(ByteReader& r, const char* what) {
  const Eigen::Quaterniond q = readQuaternion(r, what);
  const Eigen::Vector3d t = readVector(r, what);
  const double s = r.f64();
  if (!(std::isfinite(s) && s > 0.0))
    r.fail(std::string(what) + ": scale " + numberText(s) + " is not a finite positive number");
  return Sim3d(q, t, s);
}

}  // namespace ldsm::mapfile
