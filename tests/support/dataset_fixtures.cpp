// Writers of the small dataset fixtures used by the dataset tests.
#include "dataset_fixtures.h"

#include <zip.h>

#include <cstdint>
#include <cstdio>
#include <sstream>

namespace ldsm::test {
namespace {

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

std::string padded(int k, int width) {
  std::string s = std::to_string(k);
  return std::string(width > static_cast<int>(s.size()) ? width - s.size() : 0, '0') + s;
}

}  // namespace

void writeZip(const std::string& path,
              const std::vector<std::pair<std::string, std::vector<unsigned char>>>& entries) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  int error = 0;
  zip_t* archive = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error);
  ASSERT_NE(archive, nullptr) << path;
  for (const auto& [name, bytes] : entries) {
    if (!name.empty() && name.back() == '/') {
      ASSERT_GE(zip_dir_add(archive, name.c_str(), ZIP_FL_ENC_UTF_8), 0) << name;
      continue;
    }
    // The source does not free the buffer; `entries` outlives zip_close().
    zip_source_t* source = zip_source_buffer(archive, bytes.data(), bytes.size(), 0);
    ASSERT_NE(source, nullptr);
    ASSERT_GE(zip_file_add(archive, name.c_str(), source, ZIP_FL_ENC_UTF_8), 0) << name;
  }
  ASSERT_EQ(zip_close(archive), 0) << path;
}

void writeTumMonoFixture(const std::string& root, int n, bool zipped) {
  std::ostringstream times;
  times << "# id timestamp exposure\n";
  std::vector<std::pair<std::string, std::vector<unsigned char>>> entries;
  for (int k = 0; k < n; ++k) {
    times << padded(k, 5) << " " << fixed(0.05 * k, 6) << " " << fixed(10.0 + k, 3) << "\n";
    const std::string name = padded(k, 5) + ".png";
    if (zipped) {
      entries.emplace_back(name, encodePng(patternImage(k)));
    } else {
      writeImage(root + "/images/" + name, patternImage(k));
    }
  }
  if (zipped) writeZip(root + "/images.zip", entries);
  writeText(root + "/times.txt", times.str());
  writeText(root + "/camera.txt", "Pinhole 20 20 12 8 0\n24 16\nnone\n24 16\n");
  std::string response;
  for (int v = 0; v < 256; ++v) response += std::to_string(v) + (v < 255 ? " " : "\n");
  writeText(root + "/pcalib.txt", response);
  writeImage(root + "/vignette.png",
             cv::Mat(kFixtureHeight, kFixtureWidth, CV_8U, cv::Scalar(255)));
  std::ostringstream gt;
  for (int k = 0; k < n; ++k) gt << fixed(0.05 * k, 6) << " " << 0.1 * k << " 0 0 0 0 0 1\n";
  writeText(root + "/groundtruth.txt", gt.str());
}

void writeEurocFixture(const std::string& root, int n) {
  std::ostringstream csv;
  csv << "#timestamp [ns],filename\r\n";  // EuRoC files have Windows line ends
  for (int k = 0; k < n; ++k) {
    const std::int64_t ns = 1403715273000000000LL + 50000000LL * k;
    csv << ns << "," << ns << ".png\r\n";
    writeImage(root + "/mav0/cam0/data/" + std::to_string(ns) + ".png", patternImage(k));
  }
  writeText(root + "/mav0/cam0/data.csv", csv.str());
  writeText(root + "/mav0/cam0/sensor.yaml",
            "%YAML:1.0\nsensor_type: camera\nrate_hz: 20\nresolution: [24, 16]\n"
            "camera_model: pinhole\nintrinsics: [20.0, 21.0, 12.0, 8.0]\n"
            "distortion_model: radial-tangential\n"
            "distortion_coefficients: [-0.1, 0.01, 0.0, 0.0]\n");
}

void writeKittiFixture(const std::string& root, int n) {
  const std::string seq = root + "/sequences/04";
  std::ostringstream times, poses;
  for (int k = 0; k < n; ++k) {
    times << fixed(0.1 * k, 6) << "e+00\n";
    poses << "1 0 0 0 0 1 0 0 0 0 1 " << 0.5 * k << "\n";
    writeImage(seq + "/image_0/" + padded(k, 6) + ".png", patternImage(k));
  }
  writeText(seq + "/times.txt", times.str());
  writeText(seq + "/calib.txt", "P0: 20 0 12 0 0 20 8 0 0 0 1 0\n");
  writeText(root + "/poses/04.txt", poses.str());
}

void writeTumRgbdFixture(const std::string& root, int n) {
  std::ostringstream list;
  list << "# color images\n# file: 'rgbd_dataset_test.bag'\n# timestamp filename\n";
  for (int k = 0; k < n; ++k) {
    const std::string t = fixed(1305031102.0 + 0.033 * k, 6);
    list << t << " rgb/" << t << ".png\n";
    cv::Mat colour;
    cv::Mat grey = patternImage(k);
    cv::merge(std::vector<cv::Mat>{grey, grey, grey}, colour);
    writeImage(root + "/rgb/" + t + ".png", colour);
  }
  writeText(root + "/rgb.txt", list.str());
}

}  // namespace ldsm::test
