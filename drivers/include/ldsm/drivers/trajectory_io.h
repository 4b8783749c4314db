// Trajectory files: TUM, EuRoC ground-truth CSV and KITTI odometry poses.
//
//  * TUM:   "t tx ty tz qx qy qz qw" per line, seconds, camera-to-world, '#' starts a comment.
//  * EuRoC: "#timestamp [ns], p_RS_R_x [m], p_RS_R_y, p_RS_R_z, q_RS_w [], q_RS_x, q_RS_y, q_RS_z"
//           comma-separated, nanoseconds, quaternion in w,x,y,z order; the 17-column
//           state_groundtruth_estimate0/data.csv (with velocity and biases) is accepted too.
//  * KITTI: 12 numbers per line, the row-major 3x4 matrix [R|t] of camera-to-world; no
//           timestamps (they come from a separate times.txt, or the pose index is used).
#pragma once

#include <string>
#include <vector>

#include "ldsm/types.h"

namespace ldsm::drivers {

enum class TrajectoryFormat { Auto, Tum, EurocCsv, Kitti };

/// "auto", "tum", "euroc", "kitti" -> format. Throws ldsm::ConfigError for anything else.
TrajectoryFormat parseTrajectoryFormat(const std::string& name);
/// The inverse of parseTrajectoryFormat().
const char* trajectoryFormatName(TrajectoryFormat format);

/// Detects the format from the first data line: commas -> EuRoC CSV, 8 columns -> TUM,
/// 12 columns -> KITTI. Throws ldsm::InputError (file:line) when none fits or the file is
/// unreadable or holds no data line.
TrajectoryFormat detectTrajectoryFormat(const std::string& path);

/// Reads a trajectory. Poses must have strictly increasing timestamps and unit quaternions
/// (within 1e-3; they are normalised) or, for KITTI, rotation matrices (orthonormal within 1e-3).
/// For KITTI, `kitti_times` (one per pose) gives the timestamps; without it pose i gets time i.
/// Throws ldsm::InputError "file:line: what" for a wrong column count, a non-numeric or
/// non-finite value, a non-unit quaternion, a non-increasing timestamp; "file: no poses" for a
/// file without data.
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format = TrajectoryFormat::Auto,
                          const std::vector<double>* kitti_times = nullptr);

/// Reads a list of timestamps [s], one per line: a single column (KITTI times.txt) or "id time
/// ..." (TUM-mono times.txt: the second column is used). '#' lines are comments.
std::vector<double> readTimestampList(const std::string& path);

/// Writes TUM format with a header comment, every number in shortest round-trip precision. Where
/// the poses' map changes (StampedPose::map), a comment line says which map the poses that
/// follow belong to (only maps not merged into the first one: their own frame and scale).
/// The file is replaced atomically (see writeFileAtomically()).
void writeTumTrajectory(const std::string& path, const Trajectory& trajectory);

/// Writes KITTI poses (row-major 3x4 [R|t] per line, no timestamps), replaced atomically.
void writeKittiPoses(const std::string& path, const Trajectory& trajectory);

}  // namespace ldsm::drivers
