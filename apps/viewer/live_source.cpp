#include "live_source.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <utility>

namespace ldsm::viewer {

double currentRssMb() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (f == nullptr) return 0.0;
  long pages_total = 0, pages_resident = 0;
  const int n = std::fscanf(f, "%ld %ld", &pages_total, &pages_resident);
  std::fclose(f);
  if (n != 2) return 0.0;
  return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) /
         (1024.0 * 1024.0);
}

void appendPose(const Pose& pose, std::vector<float>& out) {
  const Eigen::Quaterniond q = pose.rotation.normalized();
  const float v[kPoseStride] = {static_cast<float>(pose.translation.x()),
                                static_cast<float>(pose.translation.y()),
                                static_cast<float>(pose.translation.z()),
                                static_cast<float>(q.x()),
                                static_cast<float>(q.y()),
                                static_cast<float>(q.z()),
                                static_cast<float>(q.w())};
  out.insert(out.end(), v, v + kPoseStride);
}

LiveSource::LiveSource(const System& system, std::string source, std::string mode)
    : system_(system), source_(std::move(source)), mode_(std::move(mode)) {}

void LiveSource::onKeyframe(const KeyframeEvent& e) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframe_times_[e.keyframe_id] = e.timestamp;
}

void LiveSource::onReuse(const ReuseEvent& e) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int id : e.reactivated)
    if (reactivated_ids_.size() < 100000) reactivated_ids_.push_back(id);
}

int LiveSource::keyframeIndex(int id, const std::vector<double>& times) const {
  const auto it = keyframe_times_.find(id);
  if (it == keyframe_times_.end()) return -1;
  const auto pos = std::lower_bound(times.begin(), times.end(), it->second - 1e-9);
  if (pos == times.end() || *pos > it->second + 1e-9) return -1;
  return static_cast<int>(pos - times.begin());
}

ViewerSnapshot LiveSource::snapshot(bool with_points) {
  ViewerSnapshot s;
  const Trajectory traj = system_.trajectory();
  s.trajectory.reserve(traj.size() * kPoseStride);
  for (const StampedPose& p : traj) appendPose(p.pose, s.trajectory);
  const Trajectory kfs = system_.keyframeTrajectory();
  std::vector<double> kf_times;
  kf_times.reserve(kfs.size());
  s.keyframes.reserve(kfs.size() * kPoseStride);
  for (const StampedPose& p : kfs) {
    appendPose(p.pose, s.keyframes);
    kf_times.push_back(p.timestamp);
  }
  if (with_points) {
    const std::vector<MapPoint> pts = system_.mapPoints();
    s.points.reserve(pts.size() * kPointStride);
    for (const MapPoint& p : pts) {
      if (!p.position.allFinite()) continue;
      s.points.push_back(static_cast<float>(p.position.x()));
      s.points.push_back(static_cast<float>(p.position.y()));
      s.points.push_back(static_cast<float>(p.position.z()));
      s.points.push_back(p.is_corner ? -1.f : p.intensity);  // the page marks corners
    }
  }
  if (const std::optional<StampedPose> cur = system_.latestPose()) {
    std::vector<float> v;
    appendPose(cur->pose, v);
    std::copy(v.begin(), v.end(), s.current.begin());
    s.has_current = true;
  }
  if (std::optional<TrackedImage> img = system_.latestTrackedImage()) {
    s.image.frame_index = img->frame_index;
    s.image.width = img->width;
    s.image.height = img->height;
    s.image.pixels = std::move(img->pixels);
    s.image.points.reserve(img->points.size() * 2);
    for (const Eigen::Vector2f& p : img->points) {
      s.image.points.push_back(p.x());
      s.image.points.push_back(p.y());
    }
  }
  const SystemStats st = system_.stats();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const LoopClosureEvent& l : st.loops) {
      const int a = keyframeIndex(l.current_keyframe_id, kf_times);
      const int b = keyframeIndex(l.matched_keyframe_id, kf_times);
      if (a >= 0 && b >= 0) s.loops.push_back({a, b});
    }
    for (int id : reactivated_ids_) {
      const int i = keyframeIndex(id, kf_times);
      if (i >= 0 && (s.reactivated.empty() || s.reactivated.back() != i))
        s.reactivated.push_back(i);
    }
  }
  const auto now = std::chrono::steady_clock::now();
  if (rate_frames_ < 0) {
    rate_frames_ = st.frames;
    rate_time_ = now;
  } else if (const double dt = std::chrono::duration<double>(now - rate_time_).count(); dt >= 1.0) {
    fps_ = static_cast<double>(st.frames - rate_frames_) / dt;
    rate_frames_ = st.frames;
    rate_time_ = now;
  }
  ViewerFigures& f = s.figures;
  f.source = source_;
  f.mode = mode_;
  f.status = toString(system_.status());
  f.fps = fps_;
  f.frames = st.frames;
  f.tracked_frames = st.tracked_frames;
  f.dropped_frames = st.dropped_frames;
  f.keyframes = st.keyframes;
  f.loops = st.loops_closed;
  f.reactivations = st.reuse.reactivations;
  if (with_points) point_count_ = static_cast<std::int64_t>(s.points.size() / kPointStride);
  f.map_points = point_count_;
  for (const StageTiming& t : st.latency)
    if (t.stage == "submit_to_tracked") {
      f.latency_mean_ms = t.mean_ms;
      f.latency_p99_ms = t.p99_ms;
    }
  for (const StageTiming& t : st.stages)
    if (t.stage == "total") f.ms_per_frame = t.mean_ms;
  f.rss_mb = currentRssMb();
  f.map_mb = static_cast<double>(st.map.bytes) / (1024.0 * 1024.0);
  f.finished = finished_.load();
  return s;
}

}  // namespace ldsm::viewer
