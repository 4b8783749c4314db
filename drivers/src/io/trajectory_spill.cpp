#include "ldsm/drivers/trajectory_spill.h"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

// One pose as stored: timestamp, translation, quaternion (x, y, z, w), map.
struct Record {
  double v[8];
  std::int32_t map;
  std::int32_t pad;
};

Record toRecord(const StampedPose& p) {
  const Eigen::Vector3d& t = p.pose.translation;
  const Eigen::Quaterniond& q = p.pose.rotation;
  return {{p.timestamp, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}, p.map, 0};
}

StampedPose fromRecord(const Record& r) {
  StampedPose p;
  p.timestamp = r.v[0];
  p.pose.translation = {r.v[1], r.v[2], r.v[3]};
  p.pose.rotation = Eigen::Quaterniond(r.v[7], r.v[4], r.v[5], r.v[6]);
  p.map = r.map;
  return p;
}

}  // namespace

TrajectorySpill::TrajectorySpill(std::string path) : path_(std::move(path)) {}

TrajectorySpill::~TrajectorySpill() {
  if (file_) std::fclose(file_);
}

void TrajectorySpill::append(const Trajectory& poses) {
  pending_.insert(pending_.end(), poses.begin(), poses.end());
  if (pending_.empty()) return;
  if (!file_) {
    // After a failed write the file is opened again and written on from its last whole record.
    const std::filesystem::path parent = std::filesystem::path(path_).parent_path();
    std::error_code ec;
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    file_ = std::fopen(path_.c_str(), written_ > 0 ? "r+b" : "wb");
    if (!file_) throw Error(path_ + ": cannot open: " + std::strerror(errno));
    const long whole = static_cast<long>(written_) * static_cast<long>(sizeof(Record));
    if (std::fseek(file_, whole, SEEK_SET) != 0) {
      const int err = errno;
      std::fclose(file_);
      file_ = nullptr;
      throw Error(path_ + ": cannot seek: " + std::strerror(err));
    }
  }
  std::size_t done = 0;
  for (; done < pending_.size(); ++done) {
    const Record r = toRecord(pending_[done]);
    if (std::fwrite(&r, sizeof r, 1, file_) != 1) break;
  }
  const bool flushed = std::fflush(file_) == 0;
  if (done == pending_.size() && flushed) {
    written_ += static_cast<std::int64_t>(done);
    pending_.clear();
    return;
  }
  // Where the file ends is unknown now: the next call writes on from the last whole record.
  const int err = errno;
  std::fclose(file_);
  file_ = nullptr;
  throw Error(path_ + ": cannot write the frame poses: " + std::strerror(err));
}

Trajectory TrajectorySpill::read(const Trajectory& newer) const {
  Trajectory out;
  out.reserve(static_cast<std::size_t>(written_) + pending_.size() + newer.size());
  if (written_ > 0) {
    std::FILE* in = std::fopen(path_.c_str(), "rb");
    if (!in) throw Error(path_ + ": cannot read: " + std::strerror(errno));
    Record r;
    for (std::int64_t i = 0; i < written_ && std::fread(&r, sizeof r, 1, in) == 1; ++i)
      out.push_back(fromRecord(r));
    std::fclose(in);
    if (static_cast<std::int64_t>(out.size()) != written_)
      throw Error(path_ + ": holds " + std::to_string(out.size()) + " frame poses, " +
                  std::to_string(written_) + " were written");
  }
  out.insert(out.end(), pending_.begin(), pending_.end());
  out.insert(out.end(), newer.begin(), newer.end());
  return out;
}

void TrajectorySpill::remove() {
  if (file_) std::fclose(file_);
  file_ = nullptr;
  written_ = 0;
  pending_.clear();
  std::error_code ec;
  std::filesystem::remove(path_, ec);
}

}  // namespace ldsm::drivers
