// Natural-order listing of image files.
#include "dataset/file_listing.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <system_error>

#include "ldsm/drivers/dataset_format.h"
#include "ldsm/error.h"

namespace fs = std::filesystem;

namespace ldsm::drivers::detail {
namespace {

bool isDigit(char c) {
  return c >= '0' && c <= '9';
}

}  // namespace

bool naturalLess(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (isDigit(a[i]) && isDigit(b[j])) {
      // Compare the digit runs by value: skip leading zeros, then longer run = larger number.
      std::size_t ia = i, jb = j;
      while (ia < a.size() && a[ia] == '0') ++ia;
      while (jb < b.size() && b[jb] == '0') ++jb;
      std::size_t ea = ia, eb = jb;
      while (ea < a.size() && isDigit(a[ea])) ++ea;
      while (eb < b.size() && isDigit(b[eb])) ++eb;
      if (ea - ia != eb - jb) return ea - ia < eb - jb;
      const int cmp = a.compare(ia, ea - ia, b, jb, eb - jb);
      if (cmp != 0) return cmp < 0;
      // Same value: fewer leading zeros first, so that the order stays strict.
      if (ia - i != jb - j) return ia - i < jb - j;
      i = ea;
      j = eb;
      continue;
    }
    if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
    ++i;
    ++j;
  }
  return a.size() - i < b.size() - j;
}

void sortNaturally(std::vector<std::string>& names) {
  std::sort(names.begin(), names.end(), naturalLess);
}

std::vector<std::string> listImageFiles(const std::string& dir) {
  std::error_code ec;
  fs::directory_iterator it(dir, ec);
  if (ec) throw InputError(dir + ": cannot list folder: " + ec.message());
  std::vector<std::string> names;
  for (const auto& entry : it) {
    std::error_code type_ec;
    if (!entry.is_regular_file(type_ec)) continue;
    const std::string name = entry.path().filename().string();
    if (name.front() != '.' && hasImageExtension(name)) names.push_back(name);  // no hidden
  }
  sortNaturally(names);
  std::vector<std::string> paths;
  paths.reserve(names.size());
  for (const auto& name : names) paths.push_back((fs::path(dir) / name).string());
  return paths;
}

std::string imageFolderOf(const std::string& dir) {
  std::error_code ec;
  if (listImageFiles(dir).size() >= 2) return dir;
  std::vector<std::string> subdirs;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::error_code type_ec;
    const std::string name = entry.path().filename().string();
    if (entry.is_directory(type_ec) && name.front() != '.') subdirs.push_back(name);
  }
  sortNaturally(subdirs);
  for (const std::string& sub : subdirs) {
    const std::string path = (fs::path(dir) / sub).string();
    std::error_code list_ec;
    fs::directory_iterator probe(path, list_ec);
    if (list_ec) continue;
    if (listImageFiles(path).size() >= 2) return path;
  }
  return dir;
}

}  // namespace ldsm::drivers::detail
