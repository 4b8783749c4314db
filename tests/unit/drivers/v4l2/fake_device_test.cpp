// The fake V4L2 device itself must follow the kernel's buffer state machine, or the driver tests
// built on it would prove nothing: wrong orderings fail the way videobuf2 fails them.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <poll.h>

#include <cerrno>
#include <cstring>

#include "fake_v4l2_kernel.h"

namespace ldsm::test {
namespace {

v4l2_buffer buffer(std::uint32_t index) {
  v4l2_buffer b;
  std::memset(&b, 0, sizeof b);
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = index;
  return b;
}

int requestBuffers(FakeV4l2Kernel& k, int fd, std::uint32_t count) {
  v4l2_requestbuffers r;
  std::memset(&r, 0, sizeof r);
  r.count = count;
  r.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  r.memory = V4L2_MEMORY_MMAP;
  const int rc = k.ioctl(fd, VIDIOC_REQBUFS, &r);
  return rc < 0 ? rc : static_cast<int>(r.count);
}

TEST(FakeV4l2Device, OpenOnlyTheConfiguredPath) {
  FakeV4l2Kernel k;
  EXPECT_EQ(k.open("/dev/video0", O_RDWR), -ENOENT);
  const int fd = k.open("/dev/video7", O_RDWR | O_NONBLOCK);
  EXPECT_GE(fd, 0);
  EXPECT_EQ(k.openCount(), 1);
  EXPECT_EQ(k.close(fd), 0);
  EXPECT_EQ(k.close(fd), -EBADF);
  EXPECT_EQ(k.openCount(), 0);
}

TEST(FakeV4l2Device, BufferOrderingErrors) {
  FakeV4l2Kernel k;
  const int fd = k.open("/dev/video7", O_RDWR | O_NONBLOCK);
  v4l2_buffer b = buffer(0);
  EXPECT_EQ(k.ioctl(fd, VIDIOC_QBUF, &b), -EINVAL) << "QBUF before REQBUFS";
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  EXPECT_EQ(k.ioctl(fd, VIDIOC_STREAMON, &type), -EINVAL) << "STREAMON without buffers";
  EXPECT_EQ(k.ioctl(fd, VIDIOC_DQBUF, &b), -EINVAL) << "DQBUF while not streaming";

  ASSERT_EQ(requestBuffers(k, fd, 3), 3);
  b = buffer(3);
  EXPECT_EQ(k.ioctl(fd, VIDIOC_QBUF, &b), -EINVAL) << "index out of range";
  b = buffer(0);
  EXPECT_EQ(k.ioctl(fd, VIDIOC_QBUF, &b), 0);
  b = buffer(0);
  EXPECT_EQ(k.ioctl(fd, VIDIOC_QBUF, &b), -EINVAL) << "queued twice";
  b = buffer(1);
  b.memory = V4L2_MEMORY_USERPTR;
  EXPECT_EQ(k.ioctl(fd, VIDIOC_QBUF, &b), -EINVAL) << "wrong memory type";

  v4l2_format f;
  std::memset(&f, 0, sizeof f);
  f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  f.fmt.pix.pixelformat = V4L2_PIX_FMT_YUYV;
  EXPECT_EQ(k.ioctl(fd, VIDIOC_S_FMT, &f), -EBUSY) << "S_FMT with buffers allocated";

  ASSERT_EQ(k.ioctl(fd, VIDIOC_STREAMON, &type), 0);
  EXPECT_EQ(requestBuffers(k, fd, 2), -EBUSY) << "REQBUFS while streaming";
  k.close(fd);
}

TEST(FakeV4l2Device, StreamingCycleWithEagain) {
  FakeV4l2Kernel k;
  const int fd = k.open("/dev/video7", O_RDWR | O_NONBLOCK);
  ASSERT_EQ(requestBuffers(k, fd, 2), 2);
  void* maps[2];
  for (std::uint32_t i = 0; i < 2; ++i) {
    v4l2_buffer b = buffer(i);
    ASSERT_EQ(k.ioctl(fd, VIDIOC_QUERYBUF, &b), 0);
    int error = 0;
    maps[i] = k.mmap(b.length, fd, b.m.offset, &error);
    ASSERT_NE(maps[i], nullptr);
    EXPECT_TRUE(k.mmap(b.length, fd, b.m.offset + 1, &error) == nullptr && error == EINVAL);
    ASSERT_EQ(k.ioctl(fd, VIDIOC_QBUF, &b), 0);
  }
  EXPECT_EQ(requestBuffers(k, fd, 4), -EBUSY) << "REQBUFS while mapped";
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  ASSERT_EQ(k.ioctl(fd, VIDIOC_STREAMON, &type), 0);

  v4l2_buffer b = buffer(0);
  EXPECT_EQ(k.ioctl(fd, VIDIOC_DQBUF, &b), -EAGAIN) << "nothing filled before poll";
  short revents = 0;
  ASSERT_EQ(k.poll(fd, 100, &revents), 1);
  EXPECT_TRUE(revents & POLLIN);
  ASSERT_EQ(k.ioctl(fd, VIDIOC_DQBUF, &b), 0);
  EXPECT_EQ(b.sequence, 0u);
  EXPECT_EQ(b.bytesused, 64u * 48u);
  EXPECT_EQ(static_cast<unsigned char*>(maps[b.index])[64 * 5 + 3], fakePixel(0, 3, 5));
  EXPECT_EQ(k.ioctl(fd, VIDIOC_DQBUF, &b), -EAGAIN);
  // Both buffers now: one with the application, one queued. Fill and take the queued one.
  ASSERT_EQ(k.poll(fd, 100, &revents), 1);
  v4l2_buffer b2 = buffer(0);
  ASSERT_EQ(k.ioctl(fd, VIDIOC_DQBUF, &b2), 0);
  EXPECT_NE(b2.index, b.index);
  EXPECT_EQ(k.poll(fd, 100, &revents), 0) << "no buffer queued: nothing can arrive";

  ASSERT_EQ(k.ioctl(fd, VIDIOC_STREAMOFF, &type), 0);
  EXPECT_EQ(k.ioctl(fd, VIDIOC_DQBUF, &b), -EINVAL);
  for (std::uint32_t i = 0; i < 2; ++i) {
    v4l2_buffer q = buffer(i);
    ASSERT_EQ(k.ioctl(fd, VIDIOC_QUERYBUF, &q), 0);
    EXPECT_EQ(k.munmap(maps[i], q.length), 0);
  }
  EXPECT_EQ(requestBuffers(k, fd, 0), 0);
  EXPECT_EQ(k.bufferCount(), 0);
  k.close(fd);
}

TEST(FakeV4l2Device, UnplugMakesEveryCallFailWithEnodev) {
  FakeV4l2Kernel k;
  const int fd = k.open("/dev/video7", O_RDWR | O_NONBLOCK);
  k.unplug();
  v4l2_capability cap;
  EXPECT_EQ(k.ioctl(fd, VIDIOC_QUERYCAP, &cap), -ENODEV);
  short revents = 0;
  EXPECT_EQ(k.poll(fd, 10, &revents), 1);
  EXPECT_TRUE(revents & POLLERR);
  EXPECT_EQ(k.open("/dev/video7", O_RDWR), -ENOENT) << "the device node is gone";
  EXPECT_EQ(k.close(fd), 0);
}

}  // namespace
}  // namespace ldsm::test
