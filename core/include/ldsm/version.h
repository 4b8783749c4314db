#pragma once

namespace ldsm {
/// The library version, "major.minor.patch".
const char* versionString();
}  // namespace ldsm
