// The dependency rules of the code base, checked on the source tree itself:
//  * core/src's modules sit in layers (kLayers, docs/architecture.md); a module includes only
//    the modules kAllowed gives it, all in lower layers, and kAllowed holds no allowance that no
//    file uses, so that the table is the real dependency graph;
//  * a public header (core/include/ldsm) belongs to the module that implements it (kPublicOwner):
//    including it counts as including that module (only the pipeline may include ldsm/system.h);
//  * the public headers include only public headers;
//  * core never includes calib or drivers, calib never includes drivers.
// Quoted and angle-bracket includes are both checked. A new core module must be given its place
// in kLayers and kAllowed, a new public header its owner, before anything may include them.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace ldsm {
namespace {

namespace fs = std::filesystem;

/// The layers of core/src, lowest first (the order drawn in docs/architecture.md).
const std::vector<std::set<std::string>>& layers() {
  static const std::vector<std::set<std::string>> kLayers = {
      {"math", "concurrency"},
      {"camera", "image", "config", "eval"},
      {"model"},
      {"kernels", "features", "alignment", "mapfile"},
      {"frontend", "backend", "map"},
      {"loop", "reuse"},
      {"pipeline"},
  };
  return kLayers;
}

/// The modules each core module includes (besides itself and the public headers nobody owns).
const std::map<std::string, std::set<std::string>>& allowedModules() {
  static const std::map<std::string, std::set<std::string>> kAllowed = {
      {"math", {}},
      {"concurrency", {}},
      {"config", {}},
      {"camera", {"math"}},
      {"image", {"math"}},  // the four-float vector of its SIMD row kernels
      {"eval", {}},
      {"model", {"math", "image"}},
      {"kernels", {"math", "image", "model"}},
      {"features", {"math", "config", "image", "model"}},
      {"alignment", {"math", "camera", "image", "model"}},
      {"mapfile", {"math", "camera", "model"}},
      {"frontend",
       {"math", "concurrency", "config", "camera", "image", "model", "kernels", "features"}},
      {"backend",
       {"math", "concurrency", "config", "camera", "image", "model", "kernels", "features"}},
      {"map", {"math", "model", "concurrency"}},
      {"loop",
       {"math", "config", "camera", "image", "model", "features", "concurrency", "alignment"}},
      {"reuse", {"math", "config", "camera", "model", "features", "alignment", "map"}},
      {"pipeline",
       {"math", "concurrency", "config", "camera", "image", "features", "frontend", "backend",
        "map", "mapfile", "loop", "reuse"}},
  };
  return kAllowed;
}

/// The module a public header belongs to: including it is including that module. Headers of no
/// module (error.h, types.h) may be included by anyone; version.h and build_info.h only by the
/// files at the top of core/src that implement them.
std::optional<std::string> publicOwner(const std::string& inc) {
  static const std::vector<std::pair<std::string, std::string>> kPublicOwner = {
      {"ldsm/system.h", "pipeline"},
      {"ldsm/events.h", "pipeline"},
      {"ldsm/config.h", "config"},
      {"ldsm/config/", "config"},
      {"ldsm/image.h", "image"},
      {"ldsm/camera/", "camera"},
      {"ldsm/eval/", "eval"},
      {"ldsm/loop/", "loop"},
      {"ldsm/map_file.h", "mapfile"},
      {"ldsm/error.h", ""},
      {"ldsm/types.h", ""},
      {"ldsm/version.h", "(top level)"},
      {"ldsm/build_info.h", "(top level)"},
  };
  for (const auto& [prefix, owner] : kPublicOwner)
    if (inc.rfind(prefix, 0) == 0) return owner;
  return std::nullopt;
}

std::vector<std::string> includesOf(const fs::path& file) {
  static const std::regex kInclude(R"re(^\s*#\s*include\s*["<]([^">]+)[">])re");
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

/// What the includes of `root`/core/src show: the ones that break the rules ("file: include")
/// and the module dependencies actually used ("module -> module").
struct CoreIncludes {
  std::vector<std::string> violations;
  std::set<std::pair<std::string, std::string>> used;
};

CoreIncludes coreIncludes(const fs::path& root) {
  CoreIncludes out;
  const fs::path src = root / "core" / "src";
  for (const auto& entry : fs::recursive_directory_iterator(src)) {
    if (!entry.is_regular_file() || !isSource(entry.path())) continue;
    const fs::path rel = fs::relative(entry.path(), src);
    const std::string module = rel.has_parent_path() ? rel.begin()->string() : "(top level)";
    const auto allowed = allowedModules().find(module);
    const auto refuse = [&](const std::string& inc) {
      out.violations.push_back(rel.string() + ": " + inc);
    };
    for (const std::string& inc : includesOf(entry.path())) {
      const auto slash = inc.find('/');
      if (slash == std::string::npos) continue;  // same folder or a system header
      std::string target = inc.substr(0, slash);
      if (target == "calib" || target == "drivers" || inc.rfind("ldsm/drivers/", 0) == 0 ||
          inc.rfind("ldsm/calib/", 0) == 0) {
        refuse(inc);
        continue;
      }
      if (target == "ldsm") {
        const std::optional<std::string> owner = publicOwner(inc);
        if (!owner) {
          refuse(inc + " (a public header without an owner in this test)");
          continue;
        }
        if (owner->empty()) continue;  // error.h, types.h
        target = *owner;
      } else if (!fs::exists(src / target)) {
        continue;  // a system header with a path
      }
      if (target == module) continue;
      if (module == "(top level)") {
        if (target != "(top level)" && inc.rfind("ldsm/", 0) != 0) refuse(inc);
        continue;
      }
      if (allowed == allowedModules().end() || !allowed->second.count(target))
        refuse(inc);
      else
        out.used.insert({module, target});
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
  const std::vector<std::string> v = coreIncludes(kRoot).violations;
  EXPECT_TRUE(v.empty()) << v.size()
                         << " forbidden includes (see the table in this test):" << join(v);
}

TEST(Layering, EveryAllowanceIsUsed) {
  // An allowance no file uses is removed, so that the table (and docs/architecture.md) is the
  // real dependency graph.
  const auto used = coreIncludes(kRoot).used;
  for (const auto& [module, targets] : allowedModules())
    for (const std::string& target : targets)
      EXPECT_TRUE(used.count({module, target}))
          << module << " may include " << target << " but no file does: remove the allowance";
}

TEST(Layering, EveryAllowanceGoesToALowerLayer) {
  std::map<std::string, std::size_t> rank;
  for (std::size_t i = 0; i < layers().size(); ++i)
    for (const std::string& m : layers()[i]) rank[m] = i;
  for (const auto& [module, targets] : allowedModules()) {
    ASSERT_TRUE(rank.count(module)) << module << " has no layer";
    for (const std::string& target : targets) {
      ASSERT_TRUE(rank.count(target)) << target << " has no layer";
      EXPECT_LT(rank[target], rank[module]) << module << " -> " << target;
    }
  }
  EXPECT_EQ(rank.size(), allowedModules().size()) << "a layer names a module not in kAllowed";
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
  // A throw-away tree: the math module including the pipeline (quoted, or angle-bracketed) or
  // the public System header must be reported, a pipeline file including math and ldsm/system.h
  // must not; a public header including an internal one is reported.
  const fs::path root = fs::path(LDSM_TEST_TMP) / "layering_tree";
  fs::remove_all(root);
  fs::create_directories(root / "core" / "src" / "math");
  fs::create_directories(root / "core" / "src" / "pipeline");
  fs::create_directories(root / "core" / "include" / "ldsm");
  std::ofstream(root / "core" / "src" / "math" / "bad.h")
      << "#include \"pipeline/system.h\"\n#include <pipeline/x.h>\n#include \"ldsm/system.h\"\n"
      << "#include \"ldsm/types.h\"\n#include <Eigen/Core>\n";
  std::ofstream(root / "core" / "src" / "pipeline" / "good.cpp")
      << "#include \"math/bad.h\"\n#include \"ldsm/system.h\"\n";
  std::ofstream(root / "core" / "include" / "ldsm" / "leak.h") << "#include \"math/bad.h\"\n";
  const CoreIncludes c = coreIncludes(root);
  std::vector<std::string> v = c.violations;
  std::sort(v.begin(), v.end());
  ASSERT_EQ(v.size(), 3u) << join(v);
  EXPECT_EQ(v[0], "math/bad.h: ldsm/system.h");
  EXPECT_EQ(v[1], "math/bad.h: pipeline/system.h");
  EXPECT_EQ(v[2], "math/bad.h: pipeline/x.h");
  EXPECT_TRUE(c.used.count({"pipeline", "math"}));
  EXPECT_EQ(publicHeaderViolations(root).size(), 1u);
  fs::remove_all(root);
}

}  // namespace
}  // namespace ldsm
