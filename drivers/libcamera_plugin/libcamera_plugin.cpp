// The libcamera plugin: CameraManager, one stream (raw or video role), FrameBufferAllocator,
// one request per buffer, ExposureTime / AnalogueGain / AeEnable / FrameDurationLimits controls
// at start, completed requests handed from libcamera's thread to next() through a queue.
// Written against libcamera 0.0.3; no camera is available where it is built, see
// docs/live-capture.md for what is tested.
#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <libcamera/libcamera.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "libcamera/libcamera_plugin_api.h"

namespace lc = libcamera;

struct LdsmCamera {
  std::unique_ptr<lc::CameraManager> manager;
  std::shared_ptr<lc::Camera> camera;
  bool acquired = false;
  bool started = false;
  std::unique_ptr<lc::CameraConfiguration> config;
  lc::Stream* stream = nullptr;
  std::unique_ptr<lc::FrameBufferAllocator> allocator;
  std::vector<std::unique_ptr<lc::Request>> requests;
  struct Mapping {
    void* address = nullptr;
    std::size_t length = 0;
  };
  std::map<int, Mapping> mappings;  // dmabuf fd -> whole buffer mapping

  std::mutex mutex;
  std::condition_variable completed_changed;
  std::deque<lc::Request*> completed;
  bool disconnected = false;
  lc::Request* in_hand = nullptr;  // given to the caller, requeued on the next call

  void onRequestCompleted(lc::Request* request) {
    if (request->status() == lc::Request::RequestCancelled) return;
    {
      std::lock_guard<std::mutex> lock(mutex);
      completed.push_back(request);
    }
    completed_changed.notify_one();
  }
  void onDisconnected() {
    {
      std::lock_guard<std::mutex> lock(mutex);
      disconnected = true;
    }
    completed_changed.notify_one();
  }

  ~LdsmCamera() {
    if (camera) {
      if (started) camera->stop();
      camera->requestCompleted.disconnect(this);
      camera->disconnected.disconnect(this);
    }
    requests.clear();
    for (auto& [fd, m] : mappings) munmap(m.address, m.length);
    if (allocator && stream != nullptr) allocator->free(stream);
    allocator.reset();
    if (acquired) camera->release();
    camera.reset();
    if (manager) manager->stop();
  }
};

namespace {

void setError(char* error, std::size_t size, const std::string& message) {
  if (size == 0) return;
  std::snprintf(error, size, "%s", message.c_str());
}

std::string errnoText(int negative_errno) {
  return std::strerror(-negative_errno);
}

std::string cameraList(const lc::CameraManager& manager) {
  std::string s;
  for (const auto& c : manager.cameras()) s += (s.empty() ? "" : ", ") + c->id();
  return s.empty() ? "none" : s;
}

std::string formatList(const lc::StreamFormats& formats) {
  std::string s;
  for (const lc::PixelFormat& f : formats.pixelformats())
    s += (s.empty() ? "" : ", ") + f.toString();
  return s.empty() ? "none" : s;
}

bool startManager(LdsmCamera& cam, char* error, std::size_t error_size) {
  cam.manager = std::make_unique<lc::CameraManager>();
  const int r = cam.manager->start();
  if (r < 0) {
    cam.manager.reset();
    setError(error, error_size,
             "cannot start the camera manager (" + errnoText(r) +
                 "); only one process (and one camera manager in it) can use libcamera at a "
                 "time");
    return false;
  }
  return true;
}

/// Maps every plane's dmabuf of every buffer once.
bool mapBuffers(LdsmCamera& cam, char* error, std::size_t error_size) {
  for (const auto& buffer : cam.allocator->buffers(cam.stream)) {
    for (const lc::FrameBuffer::Plane& plane : buffer->planes()) {
      const int fd = plane.fd.get();
      if (cam.mappings.count(fd) != 0) continue;
      const off_t length = lseek(fd, 0, SEEK_END);
      if (length <= 0) {
        setError(error, error_size, "cannot size a frame buffer (lseek on its dmabuf failed)");
        return false;
      }
      void* address = mmap(nullptr, static_cast<std::size_t>(length), PROT_READ, MAP_SHARED, fd, 0);
      if (address == MAP_FAILED) {
        setError(error, error_size,
                 std::string("cannot map a frame buffer: ") + std::strerror(errno));
        return false;
      }
      cam.mappings[fd] = {address, static_cast<std::size_t>(length)};
    }
  }
  return true;
}

bool chooseFormat(lc::StreamConfiguration& sc, const LdsmCameraSettings& s, char* error,
                  std::size_t error_size) {
  const std::vector<lc::PixelFormat> offered = sc.formats().pixelformats();
  for (int i = 0; i < s.format_count; ++i) {
    const lc::PixelFormat wanted(s.fourccs[i], s.modifiers[i]);
    if (std::find(offered.begin(), offered.end(), wanted) != offered.end()) {
      sc.pixelFormat = wanted;
      return true;
    }
  }
  setError(error, error_size,
           "format not supported: the " + std::string(s.raw ? "raw" : "video") + " stream offers " +
               formatList(sc.formats()) +
               " and none is a grey or YUV format ldsm converts; try the other stream role");
  return false;
}

bool configure(LdsmCamera& cam, const LdsmCameraSettings& s, LdsmCameraStream* out, char* error,
               std::size_t error_size) {
  const lc::StreamRole role = s.raw ? lc::StreamRole::Raw : lc::StreamRole::VideoRecording;
  cam.config = cam.camera->generateConfiguration({role});
  if (!cam.config || cam.config->size() != 1) {
    setError(error, error_size,
             "the camera cannot produce a " + std::string(s.raw ? "raw" : "video") + " stream");
    return false;
  }
  lc::StreamConfiguration& sc = cam.config->at(0);
  if (!chooseFormat(sc, s, error, error_size)) return false;
  if (s.width > 0)
    sc.size = lc::Size(static_cast<unsigned>(s.width), static_cast<unsigned>(s.height));
  sc.bufferCount = static_cast<unsigned>(s.buffer_count);
  const lc::PixelFormat wanted_format = sc.pixelFormat;
  const lc::Size wanted_size = sc.size;
  if (cam.config->validate() == lc::CameraConfiguration::Invalid) {
    setError(error, error_size, "format not supported: the camera rejects " + sc.toString());
    return false;
  }
  if (sc.pixelFormat != wanted_format || (s.width > 0 && sc.size != wanted_size)) {
    setError(error, error_size,
             "format not supported: asked for " + wanted_format.toString() + " " +
                 wanted_size.toString() + ", the camera offers " + sc.toString());
    return false;
  }
  const int r = cam.camera->configure(cam.config.get());
  if (r < 0) {
    setError(error, error_size, "cannot configure the camera (" + errnoText(r) + ")");
    return false;
  }
  cam.stream = sc.stream();
  out->fourcc = sc.pixelFormat.fourcc();
  out->modifier = sc.pixelFormat.modifier();
  out->width = static_cast<int>(sc.size.width);
  out->height = static_cast<int>(sc.size.height);
  out->stride = static_cast<int>(sc.stride);
  return true;
}

bool setControls(LdsmCamera& cam, const LdsmCameraSettings& s, lc::ControlList& controls,
                 char* error, std::size_t error_size) {
  const lc::ControlInfoMap& available = cam.camera->controls();
  auto has = [&](const lc::ControlId& id) { return available.find(&id) != available.end(); };
  auto missing = [&](const char* name) {
    setError(error, error_size, std::string("the camera has no ") + name + " control");
    return false;
  };
  if (!s.ae_enable) {
    if (!has(lc::controls::AeEnable)) return missing("AeEnable (auto exposure)");
    controls.set(lc::controls::AeEnable, false);
  }
  if (s.exposure_time_us > 0) {
    if (!has(lc::controls::ExposureTime)) return missing("ExposureTime");
    controls.set(lc::controls::ExposureTime, s.exposure_time_us);
  }
  if (s.analogue_gain > 0.0f) {
    if (!has(lc::controls::AnalogueGain)) return missing("AnalogueGain");
    controls.set(lc::controls::AnalogueGain, s.analogue_gain);
  }
  if (s.frame_duration_us > 0) {
    if (!has(lc::controls::FrameDurationLimits)) return missing("FrameDurationLimits (frame rate)");
    const std::int64_t limits[2] = {s.frame_duration_us, s.frame_duration_us};
    controls.set(lc::controls::FrameDurationLimits, lc::Span<const std::int64_t, 2>(limits));
  }
  return true;
}

int listCameras(char* ids, std::size_t ids_size, char* error, std::size_t error_size) {
  LdsmCamera cam;
  if (!startManager(cam, error, error_size)) return -1;
  std::string all;
  const auto cameras = cam.manager->cameras();
  for (const auto& c : cameras) all += c->id() + "\n";
  setError(ids, ids_size, all);
  return static_cast<int>(cameras.size());
}

LdsmCamera* openCamera(const LdsmCameraSettings* s, LdsmCameraStream* out, char* error,
                       std::size_t error_size) {
  auto cam = std::make_unique<LdsmCamera>();
  if (!startManager(*cam, error, error_size)) return nullptr;
  const auto cameras = cam->manager->cameras();
  if (cameras.empty()) {
    setError(error, error_size,
             "no camera found: libcamera sees no camera (check the sensor's ribbon cable and "
             "its dtoverlay, and that `cam --list` or `libcamera-hello --list-cameras` shows it; "
             "USB webcams are V4L2 devices: use the V4L2 source)");
    return nullptr;
  }
  const std::string id = s->camera_id != nullptr ? s->camera_id : "";
  cam->camera = id.empty() ? cameras.front() : cam->manager->get(id);
  if (!cam->camera) {
    setError(error, error_size,
             "camera '" + id + "' not found (cameras: " + cameraList(*cam->manager) + ")");
    return nullptr;
  }
  std::snprintf(out->camera_id, sizeof out->camera_id, "%s", cam->camera->id().c_str());
  const int acquired = cam->camera->acquire();
  if (acquired < 0) {
    setError(error, error_size,
             "camera " + cam->camera->id() + " busy: another process uses it (" +
                 errnoText(acquired) + ")");
    return nullptr;
  }
  cam->acquired = true;
  if (!configure(*cam, *s, out, error, error_size)) return nullptr;

  cam->allocator = std::make_unique<lc::FrameBufferAllocator>(cam->camera);
  if (cam->allocator->allocate(cam->stream) < 0) {
    setError(error, error_size, "cannot allocate frame buffers");
    return nullptr;
  }
  if (!mapBuffers(*cam, error, error_size)) return nullptr;
  for (const auto& buffer : cam->allocator->buffers(cam->stream)) {
    std::unique_ptr<lc::Request> request = cam->camera->createRequest();
    if (!request || request->addBuffer(cam->stream, buffer.get()) < 0) {
      setError(error, error_size, "cannot create a capture request");
      return nullptr;
    }
    cam->requests.push_back(std::move(request));
  }
  lc::ControlList controls(lc::controls::controls);
  if (!setControls(*cam, *s, controls, error, error_size)) return nullptr;
  cam->camera->requestCompleted.connect(cam.get(), &LdsmCamera::onRequestCompleted);
  cam->camera->disconnected.connect(cam.get(), &LdsmCamera::onDisconnected);
  const int started = cam->camera->start(&controls);
  if (started < 0) {
    setError(error, error_size, "cannot start the camera (" + errnoText(started) + ")");
    return nullptr;
  }
  cam->started = true;
  for (const auto& request : cam->requests) {
    if (cam->camera->queueRequest(request.get()) < 0) {
      setError(error, error_size, "cannot queue a capture request");
      return nullptr;
    }
  }
  return cam.release();
}

void closeCamera(LdsmCamera* cam) {
  delete cam;
}

int nextFrame(LdsmCamera* cam, int timeout_ms, LdsmCameraFrame* frame, char* error,
              std::size_t error_size) {
  if (cam->in_hand != nullptr) {
    cam->in_hand->reuse(lc::Request::ReuseBuffers);
    cam->camera->queueRequest(cam->in_hand);
    cam->in_hand = nullptr;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    lc::Request* request = nullptr;
    {
      std::unique_lock<std::mutex> lock(cam->mutex);
      if (!cam->completed_changed.wait_until(
              lock, deadline, [&] { return cam->disconnected || !cam->completed.empty(); }))
        return 0;
      if (cam->disconnected) {
        setError(error, error_size,
                 "camera disconnected (unplugged?); reconnect it and start again");
        return -1;
      }
      request = cam->completed.front();
      cam->completed.pop_front();
    }
    lc::FrameBuffer* buffer = request->buffers().begin()->second;
    const lc::FrameMetadata& md = buffer->metadata();
    if (md.status != lc::FrameMetadata::FrameSuccess || buffer->planes().empty() ||
        md.planes().size() == 0) {
      request->reuse(lc::Request::ReuseBuffers);  // a failed frame: give it back, wait again
      cam->camera->queueRequest(request);
      continue;
    }
    const lc::FrameBuffer::Plane& plane = buffer->planes()[0];
    const LdsmCamera::Mapping& m = cam->mappings.at(plane.fd.get());
    frame->data = static_cast<const unsigned char*>(m.address) + plane.offset;
    frame->size = std::min<std::size_t>(md.planes()[0].bytesused, plane.length);
    const lc::ControlList& meta = request->metadata();
    const auto sensor_time = meta.get(lc::controls::SensorTimestamp);
    frame->timestamp_ns = sensor_time ? *sensor_time : static_cast<std::int64_t>(md.timestamp);
    const auto exposure = meta.get(lc::controls::ExposureTime);
    frame->exposure_time_us = exposure ? *exposure : -1;
    const auto gain = meta.get(lc::controls::AnalogueGain);
    frame->analogue_gain = gain ? *gain : -1.0;
    frame->sequence = md.sequence;
    cam->in_hand = request;
    return 1;
  }
}

const LdsmLibcameraPlugin kPlugin = {
    LDSM_LIBCAMERA_PLUGIN_ABI_VERSION,
    "libcamera",
    [](char* ids, size_t ids_size, char* error, size_t error_size) {
      try {
        return listCameras(ids, ids_size, error, error_size);
      } catch (const std::exception& e) {
        setError(error, error_size, e.what());
        return -1;
      }
    },
    [](const LdsmCameraSettings* s, LdsmCameraStream* out, char* error,
       size_t error_size) -> LdsmCamera* {
      try {
        return openCamera(s, out, error, error_size);
      } catch (const std::exception& e) {
        setError(error, error_size, e.what());
        return nullptr;
      }
    },
    [](LdsmCamera* cam) { closeCamera(cam); },
    [](LdsmCamera* cam, int timeout_ms, LdsmCameraFrame* frame, char* error, size_t error_size) {
      try {
        return nextFrame(cam, timeout_ms, frame, error, error_size);
      } catch (const std::exception& e) {
        setError(error, error_size, e.what());
        return -1;
      }
    },
};

}  // namespace

extern "C" __attribute__((visibility("default"))) const LdsmLibcameraPlugin*
ldsm_libcamera_plugin_v1() {
  return &kPlugin;
}
