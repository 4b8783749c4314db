// The viewer serves only the files of its web folder, by exact name.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ldsm/error.h"
#include "test_paths.h"
#include "web_files.h"

namespace ldsm::viewer {
namespace {

namespace fs = std::filesystem;

std::string makeWebRoot(const std::string& name) {
  const std::string dir = test::scratchDir(name);
  fs::create_directories(dir + "/web/three");
  std::ofstream(dir + "/web/index.html") << "<html>ldsm</html>";
  std::ofstream(dir + "/web/three/three.min.js") << "var THREE;";
  std::ofstream(dir + "/secret.txt") << "not for the page";
  std::ofstream(dir + "/web/.hidden") << "hidden";
  return dir;
}

TEST(WebFiles, ServesItsFilesByExactName) {
  const std::string dir = makeWebRoot("web_files_serve");
  const WebFiles files(dir + "/web");
  ASSERT_NE(files.find("/"), nullptr);
  EXPECT_EQ(files.find("/")->body, "<html>ldsm</html>");
  EXPECT_EQ(files.find("/index.html")->content_type, "text/html; charset=utf-8");
  ASSERT_NE(files.find("/three/three.min.js"), nullptr);
  EXPECT_EQ(files.find("/three/three.min.js")->content_type, "text/javascript; charset=utf-8");
  EXPECT_EQ(files.size(), 2u);  // not the hidden file
}

TEST(WebFiles, NothingOutsideTheFolderIsFound) {
  const std::string dir = makeWebRoot("web_files_traversal");
  const WebFiles files(dir + "/web");
  for (const char* p :
       {"/../secret.txt", "/three/../../secret.txt", "/%2e%2e/secret.txt", "//secret.txt",
        "/./index.html", "/.hidden", "/etc/passwd", "", "/three/", "/index.html/"})
    EXPECT_EQ(files.find(p), nullptr) << p;
}

TEST(WebFiles, MissingFolderOrPageIsAnError) {
  const std::string dir = test::scratchDir("web_files_missing");
  EXPECT_THROW(WebFiles(dir + "/nope"), InputError);
  EXPECT_THROW(WebFiles{dir}, InputError);  // no index.html
}

}  // namespace
}  // namespace ldsm::viewer
