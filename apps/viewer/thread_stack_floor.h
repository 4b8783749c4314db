// civetweb (Debian's libcivetweb 1.15) starts its threads with a fixed 100 KB stack
// (pthread_attr_setstacksize at build time, no run-time option). glibc carves a thread's static TLS
// out of that stack and refuses (EINVAL) a stack smaller than the process's static TLS plus a
// minimum: the engine's libraries already take 59 KB (glog 30, metis 29), and with OpenBLAS as the
// system BLAS (61 KB more) every civetweb thread failed to start and --serve could not serve.
// The floor: this program's pthread_attr_setstacksize raises a requested size below
// kMinThreadStack (256 KB) to it and otherwise passes it through to the C library's. A size a
// library asks for is a minimum for its own code; more never hurts it.
#pragma once

#include <cstddef>

namespace ldsm::viewer {

inline constexpr std::size_t kMinThreadStack = 256 * 1024;

/// Whether the floor is in effect in this process (its pthread_attr_setstacksize is the one the
/// libraries call); referenced by the server so that the definition is always linked in.
bool threadStackFloorActive();

}  // namespace ldsm::viewer
