#include "run_folder_source.h"

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "ldsm/drivers/ply_reader.h"
#include "ldsm/drivers/trajectory_io.h"
#include "ldsm/error.h"
#include "live_source.h"

namespace ldsm::viewer {
namespace fs = std::filesystem;
namespace {

template <typename T>
T number(const YAML::Node& node, const char* key, T fallback) {
  try {
    const YAML::Node v = node[key];
    return v && v.IsScalar() ? v.as<T>() : fallback;
  } catch (const YAML::Exception&) {
    return fallback;
  }
}

/// A trajectory file of a run; a run without poses writes only the header: no poses, no error.
Trajectory readRunTrajectory(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  bool data = false;
  while (!data && std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    data = first != std::string::npos && line[first] != '#';
  }
  if (!data) return {};
  return drivers::readTrajectory(path.string(), drivers::TrajectoryFormat::Tum);
}

void readStats(const std::string& path, ViewerSnapshot& s) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);  // JSON is YAML
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": not valid JSON: " + e.what());
  }
  if (!root.IsMap()) throw InputError(path + ": not a JSON object");
  ViewerFigures& f = s.figures;
  f.status = number<std::string>(root, "tracking_status", "");
  f.frames = number<std::int64_t>(root, "frames", 0);
  f.tracked_frames = number<std::int64_t>(root, "tracked_frames", 0);
  f.keyframes = number<std::int64_t>(root, "keyframes", 0);
  f.ms_per_frame = number<double>(root, "ms_per_frame", 0.0);
  f.rss_mb = number<double>(root, "peak_rss_mb", 0.0);
  if (const YAML::Node p = root["pipeline"]; p && p.IsMap()) {
    f.dropped_frames = number<std::int64_t>(p, "dropped_frames", 0);
    if (const YAML::Node lat = p["latency"]; lat && lat.IsMap())
      if (const YAML::Node t = lat["submit_to_tracked"]; t && t.IsMap()) {
        f.latency_mean_ms = number<double>(t, "mean_ms", 0.0);
        f.latency_p99_ms = number<double>(t, "p99_ms", 0.0);
      }
  }
  if (const YAML::Node r = root["reuse"]; r && r.IsMap())
    f.reactivations = number<std::int64_t>(r, "reactivations", 0);
  if (const YAML::Node m = root["map"]; m && m.IsMap())
    f.map_mb = number<double>(m, "bytes", 0.0) / (1024.0 * 1024.0);
  const int keyframes = static_cast<int>(s.keyframes.size() / kPoseStride);
  if (const YAML::Node loops = root["loops"]; loops && loops.IsSequence()) {
    for (const YAML::Node& l : loops) {
      if (!l.IsMap()) continue;
      ++f.loops;
      // keyframes.txt lists every keyframe in id order: the id is the index.
      const int a = number<int>(l, "keyframe", -1), b = number<int>(l, "matched_keyframe", -1);
      if (a >= 0 && b >= 0 && a < keyframes && b < keyframes) s.loops.push_back({a, b});
    }
  }
}

}  // namespace

RunFolderSource::RunFolderSource(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError("view: " + dir + " is not a folder");
  const fs::path base(dir);
  int found = 0;
  auto present = [&](const char* name) {
    const bool ok = fs::is_regular_file(base / name, ec);
    if (ok)
      ++found;
    else
      spdlog::warn("view: {} has no {}", dir, name);
    return ok;
  };
  ViewerSnapshot& s = snapshot_;
  if (present("trajectory.txt")) {
    const Trajectory t = readRunTrajectory(base / "trajectory.txt");
    for (const StampedPose& p : t) appendPose(p.pose, s.trajectory);
    if (!t.empty()) {
      std::vector<float> last;
      appendPose(t.back().pose, last);
      std::copy(last.begin(), last.end(), s.current.begin());
      s.has_current = true;
    }
  }
  if (present("keyframes.txt")) {
    const Trajectory k = readRunTrajectory(base / "keyframes.txt");
    for (const StampedPose& p : k) appendPose(p.pose, s.keyframes);
  }
  if (present("points.ply")) {
    const drivers::PlyPoints ply = drivers::readPly((base / "points.ply").string());
    s.points.reserve(ply.points.size() * kPointStride);
    for (std::size_t i = 0; i < ply.points.size(); ++i) {
      const Eigen::Vector3f& p = ply.points[i];
      if (!p.allFinite()) continue;
      float intensity = 128.f;
      bool corner = false;
      if (!ply.intensities.empty()) {
        intensity = ply.intensities[i];
      } else if (!ply.colours.empty()) {
        const auto& c = ply.colours[i];
        corner = c[0] != c[1] || c[1] != c[2];  // ldsm writes corners in colour, others grey
        intensity = c[1];
      }
      s.points.insert(s.points.end(), {p.x(), p.y(), p.z(), corner ? -1.f : intensity});
    }
  }
  if (present("stats.json")) readStats((base / "stats.json").string(), s);
  if (found == 0)
    throw InputError("view: " + dir +
                     " holds none of trajectory.txt, keyframes.txt, points.ply, stats.json");
  ViewerFigures& f = s.figures;
  f.source = dir;
  f.mode = "finished run";
  f.map_points = static_cast<std::int64_t>(s.points.size() / kPointStride);
  if (f.keyframes == 0) f.keyframes = static_cast<std::int64_t>(s.keyframes.size() / kPoseStride);
  f.finished = true;
}

ViewerSnapshot RunFolderSource::snapshot(bool) {
  return snapshot_;
}

}  // namespace ldsm::viewer
