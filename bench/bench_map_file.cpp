// Map files (docs/map-file.md): size and save/load time of a synthetic map with the sizes of a
// real one (default: 1000 keyframes, each with 600 points, 400 described corners and 5 links, the
// point cloud of all their points, odometry and loop edges, a 1 MB vocabulary).
//
//   bench_map_file [--keyframes N] [--points N] [--corners N] [--links N] [--no-cloud]
//                  [--vocabulary BYTES] [--repeat N] [--file PATH]
//
// Prints the file's size per keyframe and per section, and the median over --repeat runs of
// encoding (encodeMap), writing (drivers::writeMapFile: temporary file, fsync, rename), reading
// (drivers::readMapFile) and decoding with every check (decodeMap). Exit code 1 when loading
// (read + decode) takes a second or more.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "ldsm/drivers/map_file_io.h"
#include "ldsm/map_file.h"
#include "mapfile/map_codec.h"
#include "synthetic_map.h"

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int intArg(int argc, char** argv, int& i) {
  if (i + 1 >= argc) {
    std::fprintf(stderr, "%s needs a value\n", argv[i]);
    std::exit(2);
  }
  return std::atoi(argv[++i]);
}

}  // namespace

int main(int argc, char** argv) {
  ldsm::test::SyntheticMapSize size;
  size.keyframes = 1000;
  size.points_per_keyframe = 600;
  size.corners_per_keyframe = 400;
  size.links_per_keyframe = 5;
  size.loop_edges = 20;
  size.vocabulary_bytes = 1000000;
  bool cloud = true;
  int repeat = 5;
  std::string file = (std::filesystem::temp_directory_path() / "bench_map_file.ldsmmap").string();
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--keyframes") {
      size.keyframes = intArg(argc, argv, i);
    } else if (a == "--points") {
      size.points_per_keyframe = intArg(argc, argv, i);
    } else if (a == "--corners") {
      size.corners_per_keyframe = intArg(argc, argv, i);
    } else if (a == "--links") {
      size.links_per_keyframe = intArg(argc, argv, i);
    } else if (a == "--vocabulary") {
      size.vocabulary_bytes = static_cast<std::size_t>(intArg(argc, argv, i));
    } else if (a == "--repeat") {
      repeat = std::max(1, intArg(argc, argv, i));
    } else if (a == "--no-cloud") {
      cloud = false;
    } else if (a == "--file" && i + 1 < argc) {
      file = argv[++i];
    } else {
      std::fprintf(stderr, "unknown argument %s (see the comment at the top of the source)\n",
                   argv[i]);
      return 2;
    }
  }

  ldsm::MapData map = ldsm::test::syntheticMap(size);
  if (!cloud) map.points.clear();
  std::vector<double> encode_ms, write_ms, read_ms, decode_ms;
  std::vector<std::uint8_t> bytes;
  for (int r = 0; r < repeat; ++r) {
    auto t0 = Clock::now();
    bytes = ldsm::encodeMap(map);
    encode_ms.push_back(msSince(t0));
    t0 = Clock::now();
    ldsm::drivers::writeMapFile(file, bytes);
    write_ms.push_back(msSince(t0));
    t0 = Clock::now();
    const std::vector<std::uint8_t> read = ldsm::drivers::readMapFile(file);
    read_ms.push_back(msSince(t0));
    t0 = Clock::now();
    const ldsm::MapData back = ldsm::decodeMap(read.data(), read.size(), file);
    decode_ms.push_back(msSince(t0));
    if (back.keyframes.size() != map.keyframes.size()) return 3;
  }
  const ldsm::MapFileSummary s = ldsm::summarizeMap(bytes.data(), bytes.size(), file);
  std::filesystem::remove(file);

  const double kib = static_cast<double>(bytes.size()) / 1024.0;
  std::printf("map: %zu keyframes, %zu patch points, %zu corners, %zu cloud points, %zu graph "
              "edges, vocabulary %zu bytes\n",
              s.keyframes, s.patch_points, s.corners, s.points, s.graph_edges, s.vocabulary_bytes);
  std::printf("file: %.1f MiB, %.1f KiB per keyframe\n", kib / 1024.0,
              kib / static_cast<double>(std::max<std::size_t>(1, s.keyframes)));
  std::printf("sections (KiB per keyframe):");
  for (const ldsm::MapFileSection& section : s.sections)
    std::printf(" %s %.2f", section.tag.c_str(),
                static_cast<double>(section.bytes) / 1024.0 /
                    static_cast<double>(std::max<std::size_t>(1, s.keyframes)));
  std::printf("\n");
  const double load = median(read_ms) + median(decode_ms);
  std::printf("median of %d: encode %.0f ms, write %.0f ms (save %.0f ms); read %.0f ms, decode "
              "%.0f ms (load %.0f ms)\n",
              repeat, median(encode_ms), median(write_ms), median(encode_ms) + median(write_ms),
              median(read_ms), median(decode_ms), load);
  if (load >= 1000.0) {
    std::printf("FAIL: loading takes %.0f ms, the target is under a second\n", load);
    return 1;
  }
  return 0;
}
