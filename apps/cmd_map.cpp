// `ldsm map`: saved maps (docs/map-file.md).
//   ldsm map info FILE
//     checks a map file as loading it would (signature, version, checksums, every section) and
//     prints what it holds: keyframes, points, area, calibration, vocabulary, size per keyframe.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"
#include "ldsm/drivers/map_file_io.h"
#include "ldsm/error.h"
#include "ldsm/loop/vocabulary_builder.h"
#include "ldsm/map_file.h"

namespace ldsm::app {
namespace {

std::string photometricText(const MapFileSummary& s) {
  if (s.has_response && s.has_vignette) return "response and vignette";
  if (s.has_response) return "response only";
  if (s.has_vignette) return "vignette only";
  return "none";
}

double kib(double bytes) { return bytes / 1024.0; }

void printVocabulary(const std::vector<std::uint8_t>& bytes, const std::string& path) {
  if (bytes.empty()) {
    std::printf("vocabulary:   none\n");
    return;
  }
  const loop::VocabularySummary v =
      loop::inspectVocabulary(bytes.data(), bytes.size(), path + ": section VOCB (vocabulary)");
  std::printf("vocabulary:   %zu words (branching %d, levels %d), %.1f KiB\n", v.words,
              v.branching, v.levels, kib(static_cast<double>(bytes.size())));
}

void runInfo(const std::string& path) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<std::uint8_t> bytes = drivers::readMapFile(path);
  const MapFileSummary s = summarizeMap(bytes.data(), bytes.size(), path);
  const std::vector<std::uint8_t> vocabulary = mapFileVocabulary(bytes.data(), bytes.size(), path);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::printf("%s: ldsm map, format version %u, checked in %.3f s\n", path.c_str(), s.version,
              seconds);
  std::printf("keyframes:    %zu (%zu with points and features, %zu of them culled)\n",
              s.keyframes, s.data_keyframes, s.culled_keyframes);
  std::printf("points:       %zu in the cloud; %zu patch points, %zu corners, %zu descriptors\n",
              s.points, s.patch_points, s.corners, s.descriptors);
  std::printf("area:         %.2f x %.2f x %.2f (extent of the keyframe centres, map units)\n",
              s.area_max[0] - s.area_min[0], s.area_max[1] - s.area_min[1],
              s.area_max[2] - s.area_min[2]);
  std::printf("calibration:  %dx%d, fx %.3f fy %.3f cx %.3f cy %.3f, radial k %.6g\n",
              s.camera.width, s.camera.height, s.camera.fx, s.camera.fy, s.camera.cx, s.camera.cy,
              s.radial_k);
  if (s.focal_scale != 1.0 || s.cx_shift != 0.0 || s.cy_shift != 0.0)
    std::printf(
        "refined:      measured with fx, fy x %.5f, cx %+.3f, cy %+.3f px (online "
        "calibration refinement)\n",
        s.focal_scale, s.cx_shift, s.cy_shift);
  std::printf("photometric:  %s (hash %016llx)\n", photometricText(s).c_str(),
              static_cast<unsigned long long>(s.photometric_hash));
  printVocabulary(vocabulary, path);
  std::printf("graph:        %zu pose-graph edges, %zu covisibility edges\n", s.graph_edges,
              s.covisibility_edges);
  const double total = static_cast<double>(s.total_bytes);
  std::printf("size:         %llu bytes (%.1f KiB), %.1f KiB per keyframe, %.1f KiB per keyframe "
              "with data\n",
              static_cast<unsigned long long>(s.total_bytes), kib(total),
              s.keyframes > 0 ? kib(total / static_cast<double>(s.keyframes)) : 0.0,
              s.data_keyframes > 0 ? kib(total / static_cast<double>(s.data_keyframes)) : 0.0);
  std::printf("sections:    ");
  for (const MapFileSection& section : s.sections)
    std::printf(" %s %llu", section.tag.c_str(), static_cast<unsigned long long>(section.bytes));
  std::printf(" (bytes)\n");
}

}  // namespace

void addMapCommand(CLI::App& app, CommandResult& /*result*/) {
  CLI::App* map = app.add_subcommand("map", "Saved maps: check and describe map files");
  map->require_subcommand(1);
  auto info_path = std::make_shared<std::string>();
  CLI::App* info =
      map->add_subcommand("info", "Check a map file and print what it holds (docs/map-file.md)");
  info->add_option("file", *info_path, "map file (ldsm run --save-map)")->required();
  info->callback([info_path]() { runInfo(*info_path); });
}

}  // namespace ldsm::app
