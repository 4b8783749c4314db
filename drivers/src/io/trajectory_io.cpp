#include "ldsm/drivers/trajectory_io.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "io/number_text.h"
#include "ldsm/drivers/atomic_file.h"
#include "ldsm/error.h"

namespace ldsm::drivers {

namespace {

using number_text::formatDouble;
using number_text::parseDouble;

constexpr double kUnitTolerance = 1e-3;

struct DataLine {
  int number = 0;  // 1-based line number in the file
  std::string text;
};

// The non-empty, non-comment lines of a file, trimmed.
std::vector<DataLine> readDataLines(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
  std::vector<DataLine> lines;
  std::string raw;
  int number = 0;
  while (std::getline(in, raw)) {
    ++number;
    const std::string_view t = number_text::trim(raw);
    if (t.empty() || t.front() == '#') continue;
    lines.push_back({number, std::string(t)});
  }
  if (in.bad()) throw InputError(path + ": read error");
  return lines;
}

TrajectoryFormat detectFromLine(const std::string& path, const DataLine& line) {
  if (line.text.find(',') != std::string::npos) return TrajectoryFormat::EurocCsv;
  const std::size_t n = number_text::splitWhitespace(line.text).size();
  if (n == 8) return TrajectoryFormat::Tum;
  if (n == 12) return TrajectoryFormat::Kitti;
  throw InputError(atLine(path, line.number,
                          "cannot detect the trajectory format: " + std::to_string(n) +
                              " columns (TUM has 8, KITTI 12; EuRoC CSV is comma-separated)"));
}

// Context of one line being parsed: produces "file:line: ..." errors.
struct LineParser {
  const std::string& path;
  int line;

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(atLine(path, line, what));
  }

  double number(std::string_view token, std::size_t column) const {
    double v = 0.0;
    if (!parseDouble(token, v)) {
      fail("column " + std::to_string(column + 1) + " ('" + std::string(token) +
           "') is not a number");
    }
    if (!std::isfinite(v)) {
      fail("column " + std::to_string(column + 1) + " ('" + std::string(token) +
           "') is not finite");
    }
    return v;
  }

  void columns(std::size_t got, std::size_t expected, const char* layout) const {
    if (got != expected) {
      fail("expected " + std::to_string(expected) + " columns (" + layout + "), got " +
           std::to_string(got));
    }
  }

  Eigen::Quaterniond quaternion(double w, double x, double y, double z) const {
    const Eigen::Quaterniond q(w, x, y, z);
    const double norm = q.norm();
    if (!(std::abs(norm - 1.0) <= kUnitTolerance)) {
      fail("quaternion (w " + formatDouble(w) + ", x " + formatDouble(x) + ", y " +
           formatDouble(y) + ", z " + formatDouble(z) + ") has norm " + formatDouble(norm) +
           ", expected 1 (within 1e-3)");
    }
    return q.normalized();
  }
};

// Appends a pose, checking that time increases.
class TrajectoryBuilder {
 public:
  explicit TrajectoryBuilder(const std::string& path) : path_(path) {}

  void add(const LineParser& p, double timestamp, const Pose& pose) {
    if (!traj_.empty() && !(timestamp > traj_.back().timestamp)) {
      p.fail("timestamp " + formatDouble(timestamp) + " is not greater than the previous one (" +
             formatDouble(traj_.back().timestamp) + " at line " + std::to_string(prev_line_) + ")");
    }
    traj_.push_back({timestamp, pose});
    prev_line_ = p.line;
  }

  Trajectory finish() {
    if (traj_.empty()) throw InputError(path_ + ": no poses");
    return std::move(traj_);
  }

 private:
  const std::string& path_;
  Trajectory traj_;
  int prev_line_ = 0;
};

Trajectory readTum(const std::string& path, const std::vector<DataLine>& lines) {
  TrajectoryBuilder b(path);
  for (const DataLine& l : lines) {
    const LineParser p{path, l.number};
    const auto tok = number_text::splitWhitespace(l.text);
    p.columns(tok.size(), 8, "t tx ty tz qx qy qz qw");
    double v[8];
    for (std::size_t i = 0; i < 8; ++i) v[i] = p.number(tok[i], i);
    Pose pose;
    pose.translation = Eigen::Vector3d(v[1], v[2], v[3]);
    pose.rotation = p.quaternion(v[7], v[4], v[5], v[6]);
    b.add(p, v[0], pose);
  }
  return b.finish();
}

// EuRoC timestamps are integer nanoseconds; keep the precision by splitting off whole seconds.
double nanosecondsToSeconds(const LineParser& p, std::string_view token) {
  std::int64_t ns = 0;
  if (number_text::parseInt64(token, ns)) {
    return static_cast<double>(ns / 1000000000) + static_cast<double>(ns % 1000000000) * 1e-9;
  }
  return p.number(token, 0) * 1e-9;
}

Trajectory readEuroc(const std::string& path, const std::vector<DataLine>& lines) {
  TrajectoryBuilder b(path);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const LineParser p{path, lines[k].number};
    const auto tok = number_text::splitCommas(lines[k].text);
    double ignored = 0.0;
    if (k == 0 && !tok.empty() && !parseDouble(tok[0], ignored)) continue;  // header without '#'
    if (tok.size() != 8 && tok.size() != 17) {
      p.fail(
          "expected 8 or 17 comma-separated columns (timestamp [ns], p_RS_R_x, p_RS_R_y, "
          "p_RS_R_z, q_RS_w, q_RS_x, q_RS_y, q_RS_z[, velocity, gyro bias, accel bias]), got " +
          std::to_string(tok.size()));
    }
    const double t = nanosecondsToSeconds(p, tok[0]);
    double v[8];
    for (std::size_t i = 1; i < tok.size(); ++i) {
      const double x = p.number(tok[i], i);
      if (i < 8) v[i] = x;
    }
    Pose pose;
    pose.translation = Eigen::Vector3d(v[1], v[2], v[3]);
    pose.rotation = p.quaternion(v[4], v[5], v[6], v[7]);
    b.add(p, t, pose);
  }
  return b.finish();
}

Trajectory readKitti(const std::string& path, const std::vector<DataLine>& lines,
                     const std::vector<double>* times) {
  if (times != nullptr && times->size() != lines.size()) {
    throw InputError(path + ": " + std::to_string(lines.size()) + " poses but " +
                     std::to_string(times->size()) + " timestamps");
  }
  TrajectoryBuilder b(path);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const LineParser p{path, lines[k].number};
    const auto tok = number_text::splitWhitespace(lines[k].text);
    p.columns(tok.size(), 12, "row-major 3x4 [R|t]");
    Eigen::Matrix<double, 3, 4> m;
    for (std::size_t i = 0; i < 12; ++i) {
      m(static_cast<Eigen::Index>(i / 4), static_cast<Eigen::Index>(i % 4)) = p.number(tok[i], i);
    }
    const Eigen::Matrix3d r = m.leftCols<3>();
    const double orth = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (!(orth <= kUnitTolerance) || r.determinant() <= 0.0) {
      p.fail("the 3x3 part is not a rotation matrix (|R^T R - I| = " + formatDouble(orth) +
             ", det = " + formatDouble(r.determinant()) + ")");
    }
    Pose pose;
    pose.rotation = Eigen::Quaterniond(r).normalized();
    pose.translation = m.col(3);
    const double t = times != nullptr ? (*times)[k] : static_cast<double>(k);
    if (!std::isfinite(t)) p.fail("its timestamp from the times list is not finite");
    b.add(p, t, pose);
  }
  return b.finish();
}

}  // namespace

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  if (name == "auto") return TrajectoryFormat::Auto;
  if (name == "tum") return TrajectoryFormat::Tum;
  if (name == "euroc") return TrajectoryFormat::EurocCsv;
  if (name == "kitti") return TrajectoryFormat::Kitti;
  throw ConfigError("trajectory format must be auto, tum, euroc or kitti, got '" + name + "'");
}

const char* trajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::Tum:
      return "tum";
    case TrajectoryFormat::EurocCsv:
      return "euroc";
    case TrajectoryFormat::Kitti:
      return "kitti";
    case TrajectoryFormat::Auto:
      break;
  }
  return "auto";
}

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  const std::vector<DataLine> lines = readDataLines(path);
  if (lines.empty()) throw InputError(path + ": no poses");
  return detectFromLine(path, lines.front());
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format,
                          const std::vector<double>* kitti_times) {
  const std::vector<DataLine> lines = readDataLines(path);
  if (lines.empty()) throw InputError(path + ": no poses");
  if (format == TrajectoryFormat::Auto) format = detectFromLine(path, lines.front());
  switch (format) {
    case TrajectoryFormat::Tum:
      return readTum(path, lines);
    case TrajectoryFormat::EurocCsv:
      return readEuroc(path, lines);
    case TrajectoryFormat::Kitti:
      return readKitti(path, lines, kitti_times);
    case TrajectoryFormat::Auto:
      break;
  }
  throw InputError(path + ": unknown trajectory format");
}

std::vector<double> readTimestampList(const std::string& path) {
  std::vector<double> times;
  for (const DataLine& l : readDataLines(path)) {
    const LineParser p{path, l.number};
    const auto tok = number_text::splitWhitespace(l.text);
    const std::size_t column = tok.size() >= 2 ? 1 : 0;
    const double t = p.number(tok[column], column);
    if (!times.empty() && !(t > times.back())) {
      p.fail("timestamp " + formatDouble(t) + " is not greater than the previous one (" +
             formatDouble(times.back()) + ")");
    }
    times.push_back(t);
  }
  if (times.empty()) throw InputError(path + ": no timestamps");
  return times;
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  std::string out = "# timestamp tx ty tz qx qy qz qw (camera-to-world)\n";
  int map = 0;
  for (const StampedPose& sp : trajectory) {
    if (sp.map != map) {
      // Poses of a map not (yet) merged into the first one: another frame and scale.
      map = sp.map;
      out += map == 0 ? std::string("# map 0: the map's frame\n")
                      : "# map " + std::to_string(map) +
                            ": a map started after tracking was lost, not merged into map 0; "
                            "poses in its own frame and scale\n";
    }
    const Eigen::Vector3d& t = sp.pose.translation;
    const Eigen::Quaterniond q = sp.pose.rotation.normalized();
    for (double v : {sp.timestamp, t.x(), t.y(), t.z(), q.x(), q.y(), q.z()}) {
      out += formatDouble(v);
      out += ' ';
    }
    out += formatDouble(q.w());
    out += '\n';
  }
  writeFileAtomically(path, out);
}

void writeKittiPoses(const std::string& path, const Trajectory& trajectory) {
  std::string out;
  for (const StampedPose& sp : trajectory) {
    const Eigen::Matrix3d r = sp.pose.rotation.normalized().toRotationMatrix();
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 4; ++col) {
        out += formatDouble(col < 3 ? r(row, col) : sp.pose.translation(row));
        out += (row == 2 && col == 3) ? '\n' : ' ';
      }
    }
  }
  writeFileAtomically(path, out);
}

}  // namespace ldsm::drivers
