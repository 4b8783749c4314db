// Writing files so that a crash or a full disk never leaves half a file behind.
#pragma once

#include <string>

namespace ldsm::drivers {

/// Writes `contents` to a temporary file beside `path`, flushes it to disk and renames it over
/// `path` (atomic on POSIX file systems). Throws ldsm::Error naming the path when the directory
/// is not writable or the write fails; the temporary file is removed then.
void writeFileAtomically(const std::string& path, const std::string& contents);

}  // namespace ldsm::drivers
