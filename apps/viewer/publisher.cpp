#include "publisher.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "stream_delta.h"
#include "thread_priority.h"
#include "wire_format.h"

namespace ldsm::viewer {

Publisher::Publisher(SnapshotSource& source, const PublisherOptions& options)
    : source_(source), options_(options) {
  options_.update_hz = std::clamp(options_.update_hz, 0.1, 60.0);
  options_.points_every = std::max(options_.points_every, 1);
  thread_ = std::thread([this] { run(); });
}

Publisher::~Publisher() {
  stop();
}

void Publisher::add(const std::shared_ptr<ClientChannel>& client) {
  std::lock_guard<std::mutex> lock(clients_mutex_);
  clients_.push_back(client);
}

void Publisher::remove(const ClientChannel* client) {
  std::lock_guard<std::mutex> lock(clients_mutex_);
  clients_.erase(std::remove_if(clients_.begin(), clients_.end(),
                                [client](const auto& c) { return c.get() == client; }),
                 clients_.end());
}

std::size_t Publisher::clients() const {
  std::lock_guard<std::mutex> lock(clients_mutex_);
  return clients_.size();
}

void Publisher::stop() {
  {
    std::lock_guard<std::mutex> lock(wake_mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

PublisherCounters Publisher::counters() const {
  return {snapshots_.load(), sent_.load(), skipped_.load()};
}

void Publisher::publishNow() {
  tick();
}

void Publisher::run() {
  lowerThisThreadPriority();
  const auto period = std::chrono::duration<double>(1.0 / options_.update_hz);
  std::unique_lock<std::mutex> lock(wake_mutex_);
  while (!stop_) {
    lock.unlock();
    try {
      tick();
    } catch (const std::exception& e) {
      // The viewer must never take the run down: report and carry on.
      spdlog::warn("viewer: {}", e.what());
    }
    lock.lock();
    wake_.wait_for(lock, period, [this] { return stop_; });
  }
}

void Publisher::tick() {
  std::lock_guard<std::mutex> tick_lock(tick_mutex_);
  std::vector<std::shared_ptr<ClientChannel>> clients;
  {
    std::lock_guard<std::mutex> lock(clients_mutex_);
    clients = clients_;
  }
  if (clients.empty()) return;  // nobody watching: nothing is read from the source
  // A page that has nothing yet gets the points at once.
  bool with_points = ticks_++ % options_.points_every == 0;
  for (const auto& c : clients) with_points = with_points || c->points.have == 0;
  ViewerSnapshot snap = source_.snapshot(with_points);
  snapshots_.fetch_add(1, std::memory_order_relaxed);
  if (!with_points) snap.points = points_;

  const std::size_t d_traj = firstDifference(trajectory_, snap.trajectory, kPoseStride);
  const std::size_t d_kf = firstDifference(keyframes_, snap.keyframes, kPoseStride);
  const std::size_t d_pts = firstDifference(points_, snap.points, kPointStride);
  trajectory_ = snap.trajectory;
  keyframes_ = snap.keyframes;
  points_ = snap.points;

  const std::size_t n_traj = snap.trajectory.size() / kPoseStride;
  const std::size_t n_kf = snap.keyframes.size() / kPoseStride;
  const std::size_t n_pts = snap.points.size() / kPointStride;
  const WireMessage figures = encodeFigures(snap, options_.max_list);
  for (const auto& c : clients) {
    c->trajectory.changedFrom(d_traj);
    c->keyframes.changedFrom(d_kf);
    c->points.changedFrom(d_pts);
    if (c->failed()) continue;
    std::vector<WireMessage> batch;
    const std::size_t chunk = options_.max_chunk_elements;
    appendDelta(StreamKind::Trajectory, snap.trajectory, c->trajectory.valid, c->trajectory.have,
                chunk, batch);
    appendDelta(StreamKind::Keyframes, snap.keyframes, c->keyframes.valid, c->keyframes.have, chunk,
                batch);
    appendDelta(StreamKind::Points, snap.points, c->points.valid, c->points.have, chunk, batch);
    const bool new_image = snap.image.frame_index >= 0 && snap.image.frame_index != c->image_frame;
    if (new_image) batch.push_back(encodeImage(snap.image));
    batch.push_back(figures);
    if (c->offer(std::move(batch))) {
      c->trajectory.sent(n_traj);
      c->keyframes.sent(n_kf);
      c->points.sent(n_pts);
      if (new_image) c->image_frame = snap.image.frame_index;
      sent_.fetch_add(1, std::memory_order_relaxed);
    } else {
      skipped_.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

}  // namespace ldsm::viewer
