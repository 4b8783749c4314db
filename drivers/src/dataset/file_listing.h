// Listing the image files of a folder in natural order ("2.png" before "10.png").
#pragma once

#include <string>
#include <vector>

namespace ldsm::drivers::detail {

/// Natural order: runs of digits compare by value, everything else byte by byte.
bool naturalLess(const std::string& a, const std::string& b);

/// Sorts in natural order.
void sortNaturally(std::vector<std::string>& names);

/// Paths (dir/name) of the regular files of `dir` with an image extension, in natural order of
/// their names. Throws ldsm::InputError "<dir>: cannot list folder" when `dir` is unreadable.
std::vector<std::string> listImageFiles(const std::string& dir);

}  // namespace ldsm::drivers::detail
