#include "thread_stack_floor.h"

#include <dlfcn.h>
#include <pthread.h>

#include <algorithm>

namespace {

using SetStackSize = int (*)(pthread_attr_t*, std::size_t);

SetStackSize cLibrarySetStackSize() {
  static const SetStackSize real =
      reinterpret_cast<SetStackSize>(dlsym(RTLD_NEXT, "pthread_attr_setstacksize"));
  return real;
}

}  // namespace

// Interposes the C library's function for the whole program (libraries calling it through their
// PLT reach this one); see thread_stack_floor.h.
extern "C" int pthread_attr_setstacksize(pthread_attr_t* attr, std::size_t size) {
  const SetStackSize real = cLibrarySetStackSize();
  if (real == nullptr) return 0;  // no C library behind us: keep the default stack
  return real(attr, std::max(size, ldsm::viewer::kMinThreadStack));
}

namespace ldsm::viewer {

bool threadStackFloorActive() {
  pthread_attr_t attr;
  if (pthread_attr_init(&attr) != 0) return false;
  std::size_t size = 0;
  const bool raised = pthread_attr_setstacksize(&attr, 16 * 1024) == 0 &&
                      pthread_attr_getstacksize(&attr, &size) == 0 && size >= kMinThreadStack;
  pthread_attr_destroy(&attr);
  return raised;
}

}  // namespace ldsm::viewer
