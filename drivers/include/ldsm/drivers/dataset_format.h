// Dataset layouts ldsm reads offline, their names on the command line, and detection of the layout
// of a folder (or video file) from its contents.
#pragma once

#include <string>

namespace ldsm::drivers {

/// On-disk layout of a recorded sequence.
enum class DatasetFormat {
  Auto,     ///< detect from the folder contents (detectDatasetFormat)
  TumMono,  ///< times.txt ("id t [exposure_ms]") + images/ or images.zip, camera.txt, pcalib.txt
  Euroc,    ///< EuRoC ASL: mav0/cam0/data.csv + mav0/cam0/data/*.png
  Kitti,    ///< KITTI odometry: sequences/NN/{image_0/,times.txt,calib.txt}, poses/NN.txt
  TumRgbd,  ///< TUM RGB-D: rgb.txt ("timestamp path"), groundtruth.txt
  Folder,   ///< a plain folder of images, naturally sorted, timestamps assumed at a fixed rate
  Video,    ///< a video file decoded with OpenCV
};

/// "auto", "tum-mono", "euroc", "kitti", "tum-rgbd", "folder" or "video".
const char* toString(DatasetFormat format);

/// Inverse of toString(). Throws ldsm::ConfigError listing the accepted names.
DatasetFormat parseDatasetFormat(const std::string& name);

/// Detects the layout of `path` (never returns Auto), checking in this order:
/// a regular file with a video extension -> Video; mav0/cam0/data.csv or cam0/data.csv -> Euroc;
/// sequences/NN/image_0 or image_0/ + times.txt -> Kitti; rgb.txt -> TumRgbd;
/// times.txt + images/ or images.zip -> TumMono; image files -> Folder.
/// Throws ldsm::InputError "<path>: no such file or directory" when the path is missing and
/// an InputError listing what was looked for when no layout matches.
DatasetFormat detectDatasetFormat(const std::string& path);

/// True for file names whose extension is a still-image format ldsm decodes (png, jpg, ...).
bool hasImageExtension(const std::string& file_name);

/// True for file names whose extension is a video container (mp4, avi, mkv, ...).
bool hasVideoExtension(const std::string& file_name);

}  // namespace ldsm::drivers
