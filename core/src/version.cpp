#include "ldsm/version.h"

namespace ldsm {
const char* versionString() {
  return LDSM_VERSION;
}
}  // namespace ldsm
