// The viewer's publishing thread: at a fixed rate, while at least one page is connected, it takes
// a snapshot from its source (value copies of the System's published state), works out where each
// array changed, and offers every page the deltas it is missing (wire_format.h). It runs at the
// lowest priority, takes nothing from the source while no page is connected, and never waits for a
// page: a page still busy with its previous batch is skipped and caught up later.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "client_channel.h"
#include "snapshot.h"

namespace ldsm::viewer {

struct PublisherOptions {
  double update_hz = 10.0;  ///< snapshots per second while a page is connected
  int points_every = 5;     ///< map points every n-th snapshot (they are the largest)
  std::size_t max_chunk_elements = 65536;  ///< elements per binary message
  std::size_t max_list = 4096;  ///< loop edges / reactivated keyframes per figures message
};

struct PublisherCounters {
  std::int64_t snapshots = 0;
  std::int64_t batches_sent = 0;
  std::int64_t batches_skipped = 0;  ///< a page was still busy with its previous batch
};

class Publisher {
 public:
  Publisher(SnapshotSource& source, const PublisherOptions& options);
  ~Publisher();
  Publisher(const Publisher&) = delete;
  Publisher& operator=(const Publisher&) = delete;

  void add(const std::shared_ptr<ClientChannel>& client);
  void remove(const ClientChannel* client);
  std::size_t clients() const;
  /// Publishes once more now (e.g. the final state at the end of a run) and returns when done.
  void publishNow();
  void stop();
  PublisherCounters counters() const;

 private:
  void run();
  void tick();

  SnapshotSource& source_;
  PublisherOptions options_;
  mutable std::mutex clients_mutex_;
  std::vector<std::shared_ptr<ClientChannel>> clients_;
  std::mutex tick_mutex_;  ///< one tick at a time (the thread and publishNow())
  std::vector<float> trajectory_, keyframes_, points_;  ///< the newest versions sent
  std::int64_t ticks_ = 0;
  std::atomic<std::int64_t> snapshots_{0}, sent_{0}, skipped_{0};
  std::mutex wake_mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace ldsm::viewer
