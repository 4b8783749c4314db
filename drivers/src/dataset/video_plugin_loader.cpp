// The video plugin is looked up in a few folders and opened with dlopen(); its videoio and
// codec libraries come with it.
#include "dataset/video_plugin_loader.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "ldsm/error.h"

namespace ldsm::drivers::detail {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> splitPath(const std::string& list) {
  std::vector<std::string> folders;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t end = std::min(list.find(':', start), list.size());
    if (end > start) folders.push_back(list.substr(start, end - start));
    start = end + 1;
  }
  return folders;
}

std::string executableFolder() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

}  // namespace

std::vector<std::string> videoPluginFolders() {
  if (const char* env = std::getenv("LDSM_PLUGIN_PATH"); env != nullptr && *env != '\0')
    return splitPath(env);
  std::vector<std::string> folders;
  const std::string exe_folder = executableFolder();
  if (!exe_folder.empty())
    folders.push_back((fs::path(exe_folder) / LDSM_PLUGIN_RELATIVE_DIR).lexically_normal());
  for (const char* folder : {LDSM_PLUGIN_INSTALL_DIR, LDSM_PLUGIN_BUILD_DIR}) {
    if (std::find(folders.begin(), folders.end(), folder) == folders.end())
      folders.emplace_back(folder);
  }
  return folders;
}

const LdsmVideoPlugin& loadVideoPlugin(const std::string& video) {
  const std::vector<std::string> folders = videoPluginFolders();
  std::string searched;
  for (const std::string& folder : folders) {
    const fs::path file = fs::path(folder) / kVideoPluginFile;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) {
      searched += (searched.empty() ? "" : ", ") + folder;
      continue;
    }
    const std::string prefix = video + ": cannot read video: " + file.string() + ": ";
    void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
    if (handle == nullptr) {
      const char* why = dlerror();
      throw InputError(prefix + "cannot load the video plugin (" + (why ? why : "?") + ")");
    }
    const auto entry =
        reinterpret_cast<LdsmVideoPluginEntry>(dlsym(handle, LDSM_VIDEO_PLUGIN_ENTRY));
    const LdsmVideoPlugin* plugin = entry != nullptr ? entry() : nullptr;
    if (plugin == nullptr || plugin->abi_version != LDSM_VIDEO_PLUGIN_ABI_VERSION)
      throw InputError(prefix + "not an ldsm video plugin of interface version " +
                       std::to_string(LDSM_VIDEO_PLUGIN_ABI_VERSION));
    return *plugin;
  }
  throw InputError(video + ": cannot read video: the video plugin " + kVideoPluginFile +
                   " was not found (searched: " + (searched.empty() ? "no folder" : searched) +
                   "); build ldsm with OpenCV videoio or set LDSM_PLUGIN_PATH to its folder");
}

}  // namespace ldsm::drivers::detail
