// Writing files so that a crash or a full disk never leaves half a file behind.
#pragma once

#include <cstddef>
#include <string>

namespace ldsm::drivers {

/// Writes `contents` to a temporary file beside `path`, flushes it to disk and renames it over
/// `path` (atomic on POSIX file systems). Throws ldsm::Error naming the path when the directory
/// is not writable or the write fails; the temporary file is removed then.
void writeFileAtomically(const std::string& path, const std::string& contents);
/// The same for `size` bytes at `data` (binary files, without a copy into a string).
void writeFileAtomically(const std::string& path, const void* data, std::size_t size);

}  // namespace ldsm::drivers
