// Read-only access to the entries of a zip archive (TUM-Mono images.zip) with libzip.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

struct zip;

namespace ldsm::drivers::detail {

class ZipArchive {
 public:
  /// Opens `path` read-only. Throws ldsm::InputError naming the file when it is not a zip.
  explicit ZipArchive(const std::string& path);
  ~ZipArchive();
  ZipArchive(const ZipArchive&) = delete;
  ZipArchive& operator=(const ZipArchive&) = delete;

  const std::string& path() const { return path_; }

  /// Names of the file entries (directories left out), in archive order.
  std::vector<std::string> fileNames() const;

  /// Index of the entry called `name`; throws ldsm::InputError when there is none.
  std::uint64_t indexOf(const std::string& name) const;

  /// Reads the whole entry `index` into `bytes` (its capacity is reused). Throws
  /// ldsm::InputError "<archive>:<entry>: ..." on failure.
  void read(std::uint64_t index, std::vector<unsigned char>& bytes) const;

 private:
  std::string path_;
  struct zip* archive_ = nullptr;
};

}  // namespace ldsm::drivers::detail
