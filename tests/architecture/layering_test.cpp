// The dependency rules of the code base, checked on the source tree itself:
//  * inside core/src, a module includes only the modules below it (kAllowed);
//  * the public headers (core/include/ldsm) include only public headers;
//  * core never includes calib or drivers, calib never includes drivers.
// A new core module must be given its place in kAllowed before anything may include it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace ldsm {
namespace {

namespace fs = std::filesystem;

/// The modules each core module may include (besides itself and the public ldsm/ headers).
const std::map<std::string, std::set<std::string>>& allowedModules() {
  static const std::map<std::string, std::set<std::string>> kAllowed = {
      {"math", {}},
      {"concurrency", {}},
      {"config", {}},
      {"camera", {"math"}},
      {"image", {"math"}},
      {"eval", {"math"}},
      {"model", {"math", "camera", "image"}},
      {"kernels", {"math", "image", "model"}},
      {"features", {"math", "camera", "image", "model"}},
      {"alignment", {"math", "camera", "image", "model"}},
      {"frontend", {"math", "camera", "image", "model", "kernels", "features"}},
      {"backend", {"math", "camera", "image", "model", "kernels", "features"}},
      {"map", {"math", "model", "concurrency"}},
      {"loop", {"math", "camera", "image", "model", "features", "concurrency", "alignment"}},
      {"reuse",
       {"math", "camera", "image", "model", "features", "concurrency", "alignment", "map"}},
      {"pipeline",
       {"math", "concurrency", "config", "camera", "image", "eval", "model", "kernels", "features",
        "alignment", "frontend", "backend", "map", "loop", "reuse"}},
  };
  return kAllowed;
}

std::vector<std::string> includesOf(const fs::path& file) {
  static const std::regex kInclude(R"re(^\s*#\s*include\s*"([^"]+)")re");
  std::vector<std::string> out;
  std::ifstream in(file);
  std::string line;
  std::smatch m;
  while (std::getline(in, line))
    if (std::regex_search(line, m, kInclude)) out.push_back(m[1]);
  return out;
}

bool isSource(const fs::path& p) {
  return p.extension() == ".h" || p.extension() == ".cpp";
}

/// Every include in `root`/core/src that breaks the module table, as "file: include".
std::vector<std::string> coreModuleViolations(const fs::path& root) {
  std::vector<std::string> out;
  const fs::path src = root / "core" / "src";
  for (const auto& entry : fs::recursive_directory_iterator(src)) {
    if (!entry.is_regular_file() || !isSource(entry.path())) continue;
    const fs::path rel = fs::relative(entry.path(), src);
    const std::string module = rel.has_parent_path() ? rel.begin()->string() : "";
    const auto allowed = allowedModules().find(module);
    for (const std::string& inc : includesOf(entry.path())) {
      const auto slash = inc.find('/');
      if (slash == std::string::npos) continue;  // same folder or a system header
      const std::string target = inc.substr(0, slash);
      if (target == "ldsm" || target == module) continue;
      if (target == "calib" || target == "drivers" || inc.rfind("ldsm/drivers", 0) == 0) {
        out.push_back(rel.string() + ": " + inc);
        continue;
      }
      if (!fs::exists(src / target)) continue;  // a system header with a path
      if (module.empty() || allowed == allowedModules().end() || !allowed->second.count(target))
        out.push_back(rel.string() + ": " + inc);
    }
  }
  return out;
}

/// Public headers that include anything but public headers (or system headers).
std::vector<std::string> publicHeaderViolations(const fs::path& root) {
  std::vector<std::string> out;
  const fs::path inc_root = root / "core" / "include";
  const fs::path src = root / "core" / "src";
  for (const auto& entry : fs::recursive_directory_iterator(inc_root)) {
    if (!entry.is_regular_file() || !isSource(entry.path())) continue;
    for (const std::string& inc : includesOf(entry.path())) {
      const auto slash = inc.find('/');
      if (slash == std::string::npos) continue;
      const std::string top = inc.substr(0, slash);
      const bool internal = fs::exists(src / top);
      const bool other_lib = inc.rfind("ldsm/drivers", 0) == 0 || inc.rfind("ldsm/calib", 0) == 0;
      if (internal || other_lib)
        out.push_back(fs::relative(entry.path(), root).string() + ": " + inc);
    }
  }
  return out;
}

/// Files of `library` (calib, core) that include a library above it.
std::vector<std::string> libraryViolations(const fs::path& root, const std::string& library,
                                           const std::vector<std::string>& forbidden) {
  std::vector<std::string> out;
  if (!fs::exists(root / library)) return out;
  for (const auto& entry : fs::recursive_directory_iterator(root / library)) {
    if (!entry.is_regular_file() || !isSource(entry.path())) continue;
    for (const std::string& inc : includesOf(entry.path()))
      for (const std::string& f : forbidden)
        if (inc.rfind(f, 0) == 0)
          out.push_back(fs::relative(entry.path(), root).string() + ": " + inc);
  }
  return out;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += "\n  " + x;
  return s;
}

const fs::path kRoot = LDSM_SOURCE_DIR;

TEST(Layering, CoreModulesIncludeOnlyTheModulesBelowThem) {
  const std::vector<std::string> v = coreModuleViolations(kRoot);
  EXPECT_TRUE(v.empty()) << v.size()
                         << " forbidden includes (see the table in this test):" << join(v);
}

TEST(Layering, EveryCoreModuleHasItsPlaceInTheTable) {
  for (const auto& entry : fs::directory_iterator(kRoot / "core" / "src")) {
    if (!entry.is_directory()) continue;
    EXPECT_TRUE(allowedModules().count(entry.path().filename().string()))
        << "core/src/" << entry.path().filename().string()
        << " is not in the module table of this test";
  }
}

TEST(Layering, PublicHeadersIncludeOnlyPublicHeaders) {
  const std::vector<std::string> v = publicHeaderViolations(kRoot);
  EXPECT_TRUE(v.empty()) << join(v);
}

TEST(Layering, LibrariesDependOneWay) {
  // apps -> drivers, calib -> core
  const std::vector<std::string> core =
      libraryViolations(kRoot, "core", {"ldsm/drivers/", "ldsm/calib/"});
  EXPECT_TRUE(core.empty()) << "core includes calib or drivers:" << join(core);
  const std::vector<std::string> calib = libraryViolations(kRoot, "calib", {"ldsm/drivers/"});
  EXPECT_TRUE(calib.empty()) << "calib includes drivers:" << join(calib);
}

TEST(Layering, TheCheckFindsAForbiddenInclude) {
  // A throw-away tree: the math module including the pipeline must be reported, a pipeline file
  // including math must not.
  const fs::path root = fs::path(LDSM_TEST_TMP) / "layering_tree";
  fs::remove_all(root);
  fs::create_directories(root / "core" / "src" / "math");
  fs::create_directories(root / "core" / "src" / "pipeline");
  fs::create_directories(root / "core" / "include" / "ldsm");
  std::ofstream(root / "core" / "src" / "math" / "bad.h") << "#include \"pipeline/system.h\"\n";
  std::ofstream(root / "core" / "src" / "pipeline" / "good.cpp") << "#include \"math/bad.h\"\n";
  std::ofstream(root / "core" / "include" / "ldsm" / "leak.h") << "#include \"math/bad.h\"\n";
  const std::vector<std::string> v = coreModuleViolations(root);
  ASSERT_EQ(v.size(), 1u) << join(v);
  EXPECT_EQ(v[0], "math/bad.h: pipeline/system.h");
  EXPECT_EQ(publicHeaderViolations(root).size(), 1u);
  fs::remove_all(root);
}

}  // namespace
}  // namespace ldsm
