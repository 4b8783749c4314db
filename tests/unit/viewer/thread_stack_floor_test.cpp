// The thread stack floor (apps/viewer/thread_stack_floor.h): civetweb's fixed 100 KB thread
// stacks are raised so that its threads start however much static TLS the process's libraries
// take (with OpenBLAS as the system BLAS they did not: EINVAL, and --serve could not serve).
#include <gtest/gtest.h>
#include <pthread.h>

#include "thread_stack_floor.h"

namespace ldsm::viewer {
namespace {

TEST(ThreadStackFloor, SmallStacksAreRaisedLargeOnesKept) {
  ASSERT_TRUE(threadStackFloorActive()) << "this program's pthread_attr_setstacksize is not used";
  pthread_attr_t attr;
  ASSERT_EQ(pthread_attr_init(&attr), 0);
  std::size_t size = 0;
  ASSERT_EQ(pthread_attr_setstacksize(&attr, 100 * 1024), 0);  // civetweb's
  ASSERT_EQ(pthread_attr_getstacksize(&attr, &size), 0);
  EXPECT_EQ(size, kMinThreadStack);
  ASSERT_EQ(pthread_attr_setstacksize(&attr, 4 * kMinThreadStack), 0);
  ASSERT_EQ(pthread_attr_getstacksize(&attr, &size), 0);
  EXPECT_EQ(size, 4 * kMinThreadStack);
  pthread_attr_destroy(&attr);
}

TEST(ThreadStackFloor, AThreadWithARaisedStackRuns) {
  pthread_attr_t attr;
  ASSERT_EQ(pthread_attr_init(&attr), 0);
  ASSERT_EQ(pthread_attr_setstacksize(&attr, 64 * 1024), 0);
  pthread_t thread;
  int ran = 0;
  ASSERT_EQ(pthread_create(
                &thread, &attr,
                [](void* p) -> void* {
                  *static_cast<int*>(p) = 1;
                  return nullptr;
                },
                &ran),
            0);
  pthread_join(thread, nullptr);
  pthread_attr_destroy(&attr);
  EXPECT_EQ(ran, 1);
}

}  // namespace
}  // namespace ldsm::viewer
