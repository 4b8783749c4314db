#include "ldsm/drivers/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "ldsm/error.h"

namespace ldsm::drivers {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what, int err) {
  throw Error(path + ": cannot write: " + what + ": " + std::strerror(err));
}

// Opens a new, uniquely named temporary file next to `path` (O_EXCL so we never clobber one).
int openTemporary(const std::string& path, std::string& tmp_path) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    tmp_path = path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(attempt);
    const int fd = ::open(tmp_path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
    if (errno != EEXIST) fail(path, "creating " + tmp_path, errno);
  }
  fail(path, "no free temporary file name", EEXIST);
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::string& contents) {
  writeFileAtomically(path, contents.data(), contents.size());
}

void writeFileAtomically(const std::string& path, const void* bytes, std::size_t size) {
  std::string tmp_path;
  const int fd = openTemporary(path, tmp_path);
  const char* data = static_cast<const char*>(bytes);
  std::size_t left = size;
  int err = 0;
  while (left > 0) {
    const ssize_t n = ::write(fd, data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      err = errno;
      break;
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  if (err == 0 && ::fsync(fd) != 0) err = errno;
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && std::rename(tmp_path.c_str(), path.c_str()) != 0) err = errno;
  if (err != 0) {
    ::unlink(tmp_path.c_str());
    fail(path, "writing " + tmp_path, err);
  }
}

}  // namespace ldsm::drivers
