// The viewer's page: the files of its web folder (HTML, JS, CSS and the three.js files copied
// from Debian's libjs-three), read into memory once when the server starts. Only these files are
// ever served, looked up by exact name: no path from a request ever reaches the file system, so
// nothing outside the folder can be read ("..", encoded or not, finds nothing).
#pragma once

#include <cstddef>
#include <map>
#include <string>

namespace ldsm::viewer {

struct WebFile {
  std::string content_type;
  std::string body;
};

class WebFiles {
 public:
  /// Reads every regular file under `root` (at most 3 folders deep, names of letters, digits,
  /// '.', '-' and '_', at most `max_bytes` in all). Throws ldsm::InputError naming the folder
  /// when it is missing, has no index.html or is too large.
  explicit WebFiles(const std::string& root, std::size_t max_bytes = 32u << 20);

  /// The file for a request path ("/" is "/index.html"), or null.
  const WebFile* find(const std::string& path) const;
  std::size_t size() const { return files_.size(); }
  const std::string& root() const { return root_; }

 private:
  std::string root_;
  std::map<std::string, WebFile> files_;  ///< by request path, e.g. "/three/three.min.js"
};

/// Where the page is: `configured` when not empty, else $LDSM_WEB_ROOT, else
/// <executable folder>/../share/ldsm/web (the build tree and the install tree alike).
std::string findWebRoot(const std::string& configured);

}  // namespace ldsm::viewer
