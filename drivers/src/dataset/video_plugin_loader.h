// Finding and loading the video plugin (libldsm_video_plugin.so) on demand.
#pragma once

#include <string>
#include <vector>

#include "dataset/video_plugin_api.h"

namespace ldsm::drivers::detail {

/// File name of the plugin.
inline constexpr const char* kVideoPluginFile = "libldsm_video_plugin.so";

/// The folders searched for the plugin, in order. When the environment variable
/// LDSM_PLUGIN_PATH is set and not empty, its ':'-separated folders only; otherwise the folder
/// the tool's install layout puts it in (relative to the running executable), the install
/// folder and the build tree's plugin folder.
std::vector<std::string> videoPluginFolders();

/// Loads the plugin from the first folder of videoPluginFolders() holding it (it is never
/// unloaded; loading again is cheap). Throws ldsm::InputError "<video>: cannot read video: ..."
/// naming the folders searched when it is missing, or the loader's error when it cannot load.
const LdsmVideoPlugin& loadVideoPlugin(const std::string& video);

}  // namespace ldsm::drivers::detail
