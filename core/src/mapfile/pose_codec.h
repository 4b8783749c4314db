// Poses in the map file: a rotation quaternion (x, y, z, w) and a translation as float64, and for
// Sim(3) a scale. The quaternion written is one that SO3's constructor leaves unchanged, so that
// decoding and encoding again gives the same bytes (docs/map-file.md, "Determinism").
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "mapfile/byte_reader.h"
#include "mapfile/byte_writer.h"
#include "math/se3.h"
#include "math/sim3.h"

namespace ldsm::mapfile {

constexpr std::size_t kSE3Bytes = 7 * 8;
constexpr std::size_t kSim3Bytes = 8 * 8;

/// The unit quaternion nearest to q (to the last bits) that normalising leaves unchanged.
Eigen::Quaterniond canonicalQuaternion(const Eigen::Quaterniond& q);

void writeSE3(ByteWriter& w, const SE3d& T);
void writeSim3(ByteWriter& w, const Sim3d& S);
/// Reads a pose; `what` names it in errors ("pose", "link to keyframe 4"): a non-finite value or
/// a quaternion that is not of unit length is an error.
SE3d readSE3(ByteReader& r, const char* what);
/// Also fails on a scale that is not a finite positive number.
Sim3d readSim3(ByteReader& r, const char* what);

}  // namespace ldsm::mapfile
