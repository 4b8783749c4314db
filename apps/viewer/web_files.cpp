#include "web_files.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ldsm/error.h"

namespace ldsm::viewer {
namespace fs = std::filesystem;
namespace {

bool safeName(const std::string& name) {
  if (name.empty() || name[0] == '.') return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '-' || c == '_';
    if (!ok) return false;
  }
  return true;
}

std::string contentType(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".png") return "image/png";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".json") return "application/json";
  return "application/octet-stream";
}

}  // namespace

WebFiles::WebFiles(const std::string& root, std::size_t max_bytes) : root_(root) {
  std::error_code ec;
  if (!fs::is_directory(root, ec))
    throw InputError("viewer: web folder " + root + " not found (set --web-root or LDSM_WEB_ROOT)");
  std::size_t total = 0;
  auto it = fs::recursive_directory_iterator(root, fs::directory_options::skip_permission_denied);
  for (; it != fs::recursive_directory_iterator(); ++it) {
    const fs::path& p = it->path();
    if (!safeName(p.filename().string())) {
      if (it->is_directory(ec)) it.disable_recursion_pending();
      continue;
    }
    if (it->is_directory(ec)) {
      if (it.depth() >= 2) it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file(ec)) continue;
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    WebFile f{contentType(p), ss.str()};
    total += f.body.size();
    if (total > max_bytes)
      throw InputError("viewer: web folder " + root + " holds more than " +
                       std::to_string(max_bytes >> 20) + " MB");
    files_["/" + fs::relative(p, root).generic_string()] = std::move(f);
  }
  if (!files_.count("/index.html"))
    throw InputError("viewer: web folder " + root + " has no index.html");
}

const WebFile* WebFiles::find(const std::string& path) const {
  const auto it = files_.find(path == "/" ? std::string("/index.html") : path);
  return it == files_.end() ? nullptr : &it->second;
}

std::string findWebRoot(const std::string& configured) {
  if (!configured.empty()) return configured;
  if (const char* env = std::getenv("LDSM_WEB_ROOT"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return "share/ldsm/web";
  return (exe.parent_path().parent_path() / "share" / "ldsm" / "web").string();
}

}  // namespace ldsm::viewer
