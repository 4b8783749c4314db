#include "map/map_store.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>

namespace ldsm {

MapStore::MapStore() {
  std::lock_guard<std::mutex> lock(mutex_);
  publishLocked(true);
}

std::shared_ptr<const MapSnapshot> MapStore::snapshot() const {
  return std::atomic_load(&snapshot_);
}

void MapStore::publishLocked(bool keyframes_changed) {
  auto s = std::make_shared<MapSnapshot>();
  const std::shared_ptr<const MapSnapshot> previous = std::atomic_load(&snapshot_);
  if (keyframes_changed || !previous) {
    s->keyframes = std::make_shared<const KeyframeTable>(keyframes_);
  } else {
    s->keyframes = previous->keyframes;
  }
  s->keyframe_count = s->keyframes->count();
  s->points = points_;
  s->point_count = point_count_;
  s->maps = maps_;
  s->data_keyframes = data_.size();
  std::size_t point_bytes = 0;
  for (const auto& block : points_) point_bytes += block->capacity() * sizeof(HostedPoint);
  s->data_bytes = data_bytes_ + point_bytes;
  std::atomic_store(&snapshot_, std::shared_ptr<const MapSnapshot>(std::move(s)));
}

void MapStore::setKeyframeLocked(const KeyframeRecord& record) {
  if (record.id < 0) return;  // "no keyframe" (keyframe() of an unknown id) has no place
  KeyframeRecord kf = record;
  kf.map = keyframes_.has(record.id) ? keyframes_[record.id].map : maps_.current();
  keyframes_.set(kf);
}

int MapStore::startNewMap() {
  std::lock_guard<std::mutex> lock(mutex_);
  const int map = maps_.startNew();
  publishLocked(false);
  return map;
}

int MapStore::currentMap() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return maps_.current();
}

bool MapStore::inFirstMap(int map) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return maps_.label(map) == 0;
}

bool MapStore::inCurrentMap(int keyframe_id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return inCurrentMapLocked(keyframe_id);
}

bool MapStore::inCurrentMapLocked(int id) const {
  if (!keyframes_.has(id)) return false;
  return maps_.root(keyframes_[id].map) == maps_.root(maps_.current());
}

int MapStore::mergeMaps(int from, int into, const Sim3d& S_into_from,
                        const std::map<int, Sim3d>& S_world_camera) {
  const int moved = applyCorrection(S_world_camera);
  std::lock_guard<std::mutex> lock(mutex_);
  maps_.merge(from, into, S_into_from);
  publishLocked(false);
  return moved;
}

void MapStore::setKeyframe(const KeyframeRecord& record) {
  std::lock_guard<std::mutex> lock(mutex_);
  setKeyframeLocked(record);
  publishLocked(true);
}

void MapStore::setKeyframes(const std::vector<KeyframeRecord>& records) {
  if (records.empty()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const KeyframeRecord& r : records) setKeyframeLocked(r);
  publishLocked(true);
}

void MapStore::addFrame(const FrameRecord& record) {
  frames_.push(record);
}

void MapStore::reserveFrames(std::size_t n) {
  frames_.reserve(frames_.size() + n);
}

void MapStore::addPoints(const std::vector<HostedPoint>& points) {
  if (points.empty()) return;
  auto block = std::make_shared<const MapSnapshot::PointBlock>(points);
  std::lock_guard<std::mutex> lock(mutex_);
  points_.push_back(std::move(block));
  point_count_ += points.size();
  publishLocked(false);
}

KeyframeRecord MapStore::keyframe(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (id < 0 || id >= static_cast<int>(keyframes_.size())) {
    KeyframeRecord none;
    none.id = -1;
    return none;
  }
  return keyframes_[id];
}

std::size_t MapStore::bytesOf(const MarginalizedKeyframe& kf) {
  return sizeof(MarginalizedKeyframe) + kf.points.capacity() * sizeof(PatchPoint) +
         kf.corners.capacity() * sizeof(Eigen::Vector2f) +
         kf.corner_idepth.capacity() * sizeof(float) +
         kf.descriptors.capacity() * sizeof(OrbDescriptor);
}

void MapStore::setKeyframeData(std::shared_ptr<const MarginalizedKeyframe> data) {
  if (!data) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const int id = data->id;
  const auto old = data_.find(id);
  if (old != data_.end()) data_bytes_ -= bytesOf(*old->second);
  data_bytes_ += bytesOf(*data);
  data_[id] = std::move(data);
  if (keyframes_.has(id)) spatial_.set(id, keyframes_[id].T_w_c.translation());
  publishLocked(false);
}

std::shared_ptr<const MarginalizedKeyframe> MapStore::keyframeData(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = data_.find(id);
  return it == data_.end() ? nullptr : it->second;
}

void MapStore::cullKeyframe(int id) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = data_.find(id);
  if (it != data_.end()) {
    data_bytes_ -= bytesOf(*it->second);
    data_.erase(it);
  }
  spatial_.remove(id);
  covisibility_.remove(id);
  if (id >= 0) {
    if (culled_.size() <= static_cast<std::size_t>(id))
      culled_.resize(static_cast<std::size_t>(id) + 1);
    culled_[static_cast<std::size_t>(id)] = true;
  }
  // Only the blocks holding the keyframe's points are copied (snapshots keep the old ones).
  const auto hosted = [&](const HostedPoint& p) { return p.host == id; };
  std::vector<std::shared_ptr<const MapSnapshot::PointBlock>> kept;
  kept.reserve(points_.size());
  for (auto& block : points_) {
    if (std::none_of(block->begin(), block->end(), hosted)) {
      kept.push_back(std::move(block));
      continue;
    }
    auto rest = std::make_shared<MapSnapshot::PointBlock>();
    // Exactly as large as what stays: a long run culls and rebuilds blocks again and again.
    rest->reserve(block->size() -
                  static_cast<std::size_t>(std::count_if(block->begin(), block->end(), hosted)));
    std::remove_copy_if(block->begin(), block->end(), std::back_inserter(*rest), hosted);
    point_count_ -= block->size() - rest->size();
    if (!rest->empty()) kept.push_back(std::move(rest));
  }
  points_ = std::move(kept);
  publishLocked(false);
}

void MapStore::connect(int a, int b, int weight) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto culled = [&](int id) {
    return id >= 0 && static_cast<std::size_t>(id) < culled_.size() &&
           culled_[static_cast<std::size_t>(id)];
  };
  if (culled(a) || culled(b)) return;
  covisibility_.connect(a, b, weight);
}

std::vector<int> MapStore::covisibleNeighbourhood(const std::vector<int>& start, int hops,
                                                  std::size_t max_count) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<int> out;
  for (const int id : covisibility_.neighbourhood(start, hops, max_count))
    if (data_.count(id) != 0 && inCurrentMapLocked(id)) out.push_back(id);
  return out;
}

std::vector<int> MapStore::keyframesNear(const Eigen::Vector3d& centre, double radius) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<int> out = spatial_.near(centre, radius);
  out.erase(std::remove_if(out.begin(), out.end(), [&](int id) { return !inCurrentMapLocked(id); }),
            out.end());
  return out;
}

StoredMap MapStore::firstMap() const {
  std::lock_guard<std::mutex> lock(mutex_);
  StoredMap out;
  const auto first = [&](int id) {
    return keyframes_.has(id) && maps_.label(keyframes_[id].map) == 0;
  };
  keyframes_.forEach([&](const KeyframeRecord& kf) {
    if (first(kf.id)) out.keyframes.push_back(kf);
  });
  for (const auto& [id, data] : data_)
    if (first(id)) out.data.push_back(data);
  for (const auto& block : points_)
    for (const HostedPoint& p : *block)
      if (p.host < 0 || first(p.host)) out.points.push_back(p);
  for (const auto& e : covisibility_.edges())
    if (first(e[0]) && first(e[1])) out.covisibility.push_back(e);
  out.S_report_world = maps_.reportFrame();
  return out;
}

void MapStore::loadMap(const StoredMap& map) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (KeyframeRecord kf : map.keyframes) {
    kf.map = 0;
    setKeyframeLocked(kf);
    keyframes_.edit(kf.id).map = 0;
  }
  for (const auto& data : map.data) {
    if (!data || data->id < 0 || data->id >= static_cast<int>(keyframes_.size())) continue;
    data_bytes_ += bytesOf(*data);
    data_[data->id] = data;
    spatial_.set(data->id, keyframes_[data->id].T_w_c.translation());
  }
  if (!map.points.empty()) {
    points_.push_back(std::make_shared<const MapSnapshot::PointBlock>(map.points));
    point_count_ += map.points.size();
  }
  for (const auto& e : map.covisibility) covisibility_.connect(e[0], e[1], e[2]);
  publishLocked(true);
}

int MapStore::mostRedundantKeyframe(double max_angle_rad, const std::vector<int>& exclude) const {
  std::lock_guard<std::mutex> lock(mutex_);
  struct View {
    int id;
    Eigen::Vector3d centre, axis;
  };
  std::vector<View> views;
  for (const auto& [id, data] : data_) {
    if (!inCurrentMapLocked(id)) continue;
    const SE3d& T = keyframes_[id].T_w_c;
    views.push_back({id, T.translation(), T.so3() * Eigen::Vector3d::UnitZ()});
  }
  const double min_cos = std::cos(max_angle_rad);
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (const View& a : views) {
    if (std::find(exclude.begin(), exclude.end(), a.id) != exclude.end()) continue;
    for (const View& b : views) {
      if (a.id == b.id || a.axis.dot(b.axis) < min_cos) continue;
      const double d = (a.centre - b.centre).squaredNorm();
      if (d < best_distance) {
        best_distance = d;
        best = a.id;
      }
    }
  }
  return best;
}

std::size_t MapStore::dataKeyframeCount() const {
  return snapshot()->data_keyframes;
}

std::size_t MapStore::pointCount() const {
  return snapshot()->point_count;
}

std::size_t MapStore::dataBytes() const {
  return snapshot()->data_bytes;
}

int MapStore::applyCorrection(const std::map<int, Sim3d>& S_world_camera) {
  std::lock_guard<std::mutex> lock(mutex_);
  // Old -> new world transform of every keyframe that moves.
  std::map<int, Sim3d> moves;
  for (const auto& [id, S_new] : S_world_camera) {
    if (!keyframes_.has(id)) continue;
    KeyframeRecord& kf = keyframes_.edit(id);
    const Sim3d S_old(kf.T_w_c.so3(), kf.T_w_c.translation(), kf.scale);
    moves[id] = S_new * S_old.inverse();
    kf.T_w_c = SE3d(S_new.so3(), S_new.translation());
    kf.scale = S_new.scale();
    if (data_.count(id) != 0) spatial_.set(id, kf.T_w_c.translation());
  }
  // Keyframes folded out of the pose graph move with the one they follow: resolved along the
  // chain of followed keyframes to one that moves (memoised: each keyframe once).
  if (!moves.empty() && !follows_.empty()) {
    enum : std::int8_t { kUnknown, kStays, kMoves };
    std::vector<std::int8_t> state(follows_.size(), kUnknown);
    std::vector<Sim3d> move(follows_.size());
    std::vector<int> path;
    for (std::size_t start = 0; start < follows_.size(); ++start) {
      if (follows_[start] < 0 || moves.count(static_cast<int>(start)) != 0) continue;
      path.clear();
      int k = static_cast<int>(start);
      std::int8_t found = kStays;
      Sim3d found_move;
      // Walk until a keyframe that moves, one already resolved, or the end of the chain (a
      // guard against a cycle, which folding never makes: at most as many steps as keyframes).
      while (true) {
        const auto m = moves.find(k);
        if (m != moves.end()) {
          found = kMoves;
          found_move = m->second;
          break;
        }
        const auto ks = static_cast<std::size_t>(k);
        if (ks < state.size() && state[ks] != kUnknown) {
          found = state[ks];
          found_move = move[ks];
          break;
        }
        if (ks >= follows_.size() || follows_[ks] < 0 || path.size() > follows_.size()) break;
        path.push_back(k);
        k = follows_[ks];
      }
      for (const int p : path) {
        state[static_cast<std::size_t>(p)] = found;
        move[static_cast<std::size_t>(p)] = found_move;
      }
    }
    for (std::size_t id = 0; id < state.size() && id < keyframes_.size(); ++id) {
      if (state[id] != kMoves || !keyframes_.has(static_cast<int>(id))) continue;
      KeyframeRecord& kf = keyframes_.edit(static_cast<int>(id));
      const Sim3d S_new = move[id] * Sim3d(kf.T_w_c.so3(), kf.T_w_c.translation(), kf.scale);
      moves[static_cast<int>(id)] = move[id];
      kf.T_w_c = SE3d(S_new.so3(), S_new.translation());
      kf.scale = S_new.scale();
      if (data_.count(static_cast<int>(id)) != 0)
        spatial_.set(static_cast<int>(id), kf.T_w_c.translation());
    }
  }
  // Copy on write: only the blocks holding points of a keyframe that moves are copied.
  const auto moved = [&](const HostedPoint& p) { return moves.count(p.host) != 0; };
  for (auto& block : points_) {
    if (std::none_of(block->begin(), block->end(), moved)) continue;
    auto copy = std::make_shared<MapSnapshot::PointBlock>(*block);
    for (HostedPoint& p : *copy) {
      const auto it = moves.find(p.host);
      if (it != moves.end()) p.position = (it->second * p.position.cast<double>()).cast<float>();
    }
    block = std::move(copy);
  }
  publishLocked(true);
  return static_cast<int>(moves.size());
}

void MapStore::followKeyframes(const std::vector<std::pair<int, int>>& folded) {
  if (folded.empty()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, followed] : folded) {
    if (id < 0 || followed < 0 || id == followed) continue;
    const auto k = static_cast<std::size_t>(id);
    if (follows_.size() <= k) follows_.resize(k + 1, -1);
    follows_[k] = followed;
  }
}

bool MapStore::composeFrame(const FrameRecord& f, const MapSnapshot& s, StampedPose& out) {
  const KeyframeTable& keyframes = *s.keyframes;
  if (f.reference_keyframe < 0 || f.reference_keyframe >= static_cast<int>(keyframes.size()))
    return false;
  const KeyframeRecord& kf = keyframes[f.reference_keyframe];
  if (kf.id < 0) return false;
  const SE3d T_ref_c(f.T_ref_c.so3(), kf.scale * f.T_ref_c.translation());
  const int label = s.maps.label(kf.map);
  const SE3d T_w_c = kf.T_w_c * T_ref_c;
  out = {f.timestamp, label == 0 ? s.maps.report(T_w_c) : T_w_c.toPose(), label};
  return true;
}

Trajectory MapStore::frameTrajectory() const {
  // The frames published so far (tracking keeps appending; the lock only keeps retireFrames()
  // from freeing records while they are read), then the keyframe poses of the latest snapshot
  // they are composed with.
  std::lock_guard<std::mutex> lock(frames_mutex_);
  const std::size_t first = frames_.first();
  const std::size_t n = frames_.size();
  const std::shared_ptr<const MapSnapshot> s = snapshot();
  Trajectory out;
  out.reserve(n - first);
  StampedPose p;
  for (std::size_t i = first; i < n; ++i)
    if (composeFrame(frames_[i], *s, p)) out.push_back(p);
  return out;
}

void MapStore::setFrameHistory(std::size_t frames) {
  frame_history_ = frames;
}

std::size_t MapStore::retireFrames() {
  if (frame_history_ == 0) return 0;
  const std::size_t n = frames_.size();
  if (n < frame_history_ + kFrameChunk) return 0;
  const std::size_t until = (n - frame_history_) / kFrameChunk * kFrameChunk;
  std::lock_guard<std::mutex> lock(frames_mutex_);
  const std::size_t first = frames_.first();
  if (until <= first) return 0;
  const std::shared_ptr<const MapSnapshot> s = snapshot();
  StampedPose p;
  for (std::size_t i = first; i < until; ++i)
    if (composeFrame(frames_[i], *s, p)) retired_.push_back(p);
  frames_.releaseBefore(until);
  retired_count_ += static_cast<std::int64_t>(until - first);
  // Nobody takes them: the oldest go, so that memory stays bounded all the same.
  const std::size_t backlog = kRetiredBacklog * kFrameChunk;
  if (retired_.size() > backlog) {
    const std::size_t drop = retired_.size() - backlog;
    retired_.erase(retired_.begin(), retired_.begin() + static_cast<std::ptrdiff_t>(drop));
    retired_lost_ += static_cast<std::int64_t>(drop);
  }
  return until - first;
}

Trajectory MapStore::takeRetiredFrames() {
  std::lock_guard<std::mutex> lock(frames_mutex_);
  Trajectory out;
  out.swap(retired_);
  return out;
}

std::int64_t MapStore::retiredFrameCount() const {
  std::lock_guard<std::mutex> lock(frames_mutex_);
  return retired_count_;
}

std::int64_t MapStore::lostRetiredFrameCount() const {
  std::lock_guard<std::mutex> lock(frames_mutex_);
  return retired_lost_;
}

Trajectory MapStore::keyframeTrajectory() const {
  const std::shared_ptr<const MapSnapshot> s = snapshot();
  Trajectory out;
  out.reserve(s->keyframes->count());
  s->keyframes->forEach([&](const KeyframeRecord& kf) {
    const int label = s->maps.label(kf.map);
    out.push_back({kf.timestamp, label == 0 ? s->maps.report(kf.T_w_c) : kf.T_w_c.toPose(), label});
  });
  return out;
}

std::vector<MapPoint> MapStore::points(std::size_t extra) const {
  const std::shared_ptr<const MapSnapshot> s = snapshot();
  std::vector<MapPoint> out;
  out.reserve(s->point_count + extra);
  const KeyframeTable& keyframes = *s->keyframes;
  for (const auto& block : s->points)
    for (const HostedPoint& p : *block) {
      MapPoint m = p.mapPoint();
      const bool hosted = p.host >= 0 && p.host < static_cast<int>(keyframes.size());
      m.map = hosted ? s->maps.label(keyframes[p.host].map) : 0;
      if (m.map == 0) m.position = s->maps.reportFrame() * m.position;
      out.push_back(m);
    }
  return out;
}

std::size_t MapStore::keyframeCount() const {
  return snapshot()->keyframe_count;
}

bool MapStore::hasKeyframe(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_.has(id);
}

}  // namespace ldsm
