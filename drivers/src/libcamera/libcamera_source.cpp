// The libcamera FrameSource: loads the plugin on demand and converts its frames.
#include <dlfcn.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "dataset/video_plugin_loader.h"
#include "ldsm/drivers/libcamera_source.h"
#include "ldsm/error.h"
#include "libcamera/libcamera_plugin_api.h"

namespace ldsm::drivers {
namespace fs = std::filesystem;
namespace {

constexpr int kMaxBadFramesInARow = 30;

/// The loaded plugin, or nullptr with the reason in `why`.
const LdsmLibcameraPlugin* tryLoadPlugin(std::string& why) {
  std::string searched;
  for (const std::string& folder : detail::videoPluginFolders()) {
    const fs::path file = fs::path(folder) / LDSM_LIBCAMERA_PLUGIN_FILE;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) {
      searched += (searched.empty() ? "" : ", ") + folder;
      continue;
    }
    void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (handle == nullptr) {
      const char* error = dlerror();
      why = file.string() + ": cannot load the libcamera plugin (" + (error ? error : "?") + ")";
      return nullptr;
    }
    const auto entry =
        reinterpret_cast<LdsmLibcameraPluginEntry>(dlsym(handle, LDSM_LIBCAMERA_PLUGIN_ENTRY));
    const LdsmLibcameraPlugin* plugin = entry != nullptr ? entry() : nullptr;
    if (plugin == nullptr || plugin->abi_version != LDSM_LIBCAMERA_PLUGIN_ABI_VERSION) {
      why = file.string() + ": not an ldsm libcamera plugin of interface version " +
            std::to_string(LDSM_LIBCAMERA_PLUGIN_ABI_VERSION);
      return nullptr;
    }
    return plugin;
  }
#if defined(LDSM_HAVE_LIBCAMERA_PLUGIN)
  why = std::string("the libcamera plugin ") + LDSM_LIBCAMERA_PLUGIN_FILE +
        " was not found (searched: " + (searched.empty() ? "no folder" : searched) +
        "); set LDSM_PLUGIN_PATH to its folder";
#else
  why =
      "ldsm was built without libcamera (pkg-config did not find libcamera when it was "
      "configured); install the libcamera development files and rebuild, or use a V4L2 "
      "camera";
#endif
  return nullptr;
}

const LdsmLibcameraPlugin& loadPlugin() {
  std::string why;
  const LdsmLibcameraPlugin* plugin = tryLoadPlugin(why);
  if (plugin == nullptr) throw DeviceError("libcamera: " + why);
  return *plugin;
}

class LibcameraSource final : public FrameSource {
 public:
  LibcameraSource(const LdsmLibcameraPlugin& plugin, const LibcameraOptions& options)
      : plugin_(plugin), options_(options) {
    std::vector<std::uint32_t> fourccs;
    std::vector<std::uint64_t> modifiers;
    for (LibcameraPixelFormat f : options.formats) {
      fourccs.push_back(libcameraFourCc(f).fourcc);
      modifiers.push_back(libcameraFourCc(f).modifier);
    }
    const LibcameraControls controls = mapLibcameraControls(options);
    LdsmCameraSettings settings{};
    settings.camera_id = options.camera_id.c_str();
    settings.raw = options.raw ? 1 : 0;
    settings.fourccs = fourccs.data();
    settings.modifiers = modifiers.data();
    settings.format_count = static_cast<int>(fourccs.size());
    settings.width = options.width;
    settings.height = options.height;
    settings.buffer_count = options.buffer_count;
    settings.ae_enable = controls.ae_enable ? 1 : 0;
    settings.exposure_time_us = controls.exposure_time_us;
    settings.analogue_gain = controls.analogue_gain;
    settings.frame_duration_us = controls.frame_duration_us;
    char error[1024] = "";
    camera_ = plugin_.open(&settings, &stream_, error, sizeof error);
    if (camera_ == nullptr) throw DeviceError(std::string("libcamera: ") + error);
    format_ = classifyLibcameraFormat(stream_.fourcc, stream_.modifier);
    name_ = stream_.camera_id;
    spdlog::info("libcamera: camera {} streaming {} {}x{}", name_, toString(format_), stream_.width,
                 stream_.height);
  }
  ~LibcameraSource() override { close(); }
  LibcameraSource(const LibcameraSource&) = delete;
  LibcameraSource& operator=(const LibcameraSource&) = delete;

  SourceInfo info() const override {
    SourceInfo info;
    info.name = "libcamera:" + name_;
    info.width = stream_.width;
    info.height = stream_.height;
    info.frame_count = -1;
    info.nominal_fps = options_.fps;
    return info;
  }

  bool next(Frame& frame) override {
    if (camera_ == nullptr) return false;
    for (int bad = 0;;) {
      LdsmCameraFrame f{};
      char error[1024] = "";
      const int r = plugin_.next(camera_, options_.timeout_ms, &f, error, sizeof error);
      if (r <= 0) {
        close();
        throw DeviceError(
            "libcamera: camera " + name_ + ": " +
            (r == 0 ? "timeout: no frame within " + std::to_string(options_.timeout_ms) +
                          " ms (is the sensor connected and streaming? raise the timeout for "
                          "long exposures)"
                    : std::string(error)));
      }
      std::string problem;
      if (convertLibcameraPlane(format_, f.data, f.size, stream_.width, stream_.height,
                                stream_.stride, frame.image, problem)) {
        frame.index = index_++;
        frame.timestamp = static_cast<double>(f.timestamp_ns) * 1e-9;
        frame.exposure_ms = exposureMsFromLibcamera(f.exposure_time_us);
        return true;
      }
      spdlog::warn("libcamera: camera {}: frame skipped: {}", name_, problem);
      if (++bad >= kMaxBadFramesInARow) {
        close();
        throw DeviceError("libcamera: camera " + name_ + ": " + std::to_string(bad) +
                          " bad frames in a row (last: " + problem + ")");
      }
    }
  }

 private:
  void close() noexcept {
    if (camera_ != nullptr) plugin_.close(camera_);
    camera_ = nullptr;
  }

  const LdsmLibcameraPlugin& plugin_;
  LibcameraOptions options_;
  LdsmCamera* camera_ = nullptr;
  LdsmCameraStream stream_{};
  LibcameraPixelFormat format_ = LibcameraPixelFormat::Unsupported;
  std::string name_;
  std::int64_t index_ = 0;
};

}  // namespace

bool libcameraAvailable() {
  std::string why;
  return tryLoadPlugin(why) != nullptr;
}

std::vector<std::string> listLibcameraCameras() {
  const LdsmLibcameraPlugin& plugin = loadPlugin();
  std::vector<char> ids(16384, '\0');
  char error[1024] = "";
  const int n = plugin.list(ids.data(), ids.size(), error, sizeof error);
  if (n < 0) throw DeviceError(std::string("libcamera: ") + error);
  std::vector<std::string> cameras;
  std::string all(ids.data());
  for (std::size_t start = 0; start < all.size();) {
    const std::size_t end = std::min(all.find('\n', start), all.size());
    if (end > start) cameras.push_back(all.substr(start, end - start));
    start = end + 1;
  }
  return cameras;
}

std::unique_ptr<FrameSource> openLibcameraSource(const LibcameraOptions& options) {
  validate(options);
  return std::make_unique<LibcameraSource>(loadPlugin(), options);
}

}  // namespace ldsm::drivers
