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

/// The folder holding the images of a plain image-folder dataset: `dir` itself when it has at
/// least two images, else the first subfolder (natural order) with at least two, else `dir`.
/// Lets a folder like rtabmap_loop84/ (images in samples/, a ground-truth bitmap beside it) be
/// opened by its top folder.
std::string imageFolderOf(const std::string& dir);

}  // namespace ldsm::drivers::detail
