#include "mapfile/map_codec.h"

#include <iterator>

#include "ldsm/error.h"
#include "mapfile/map_checks.h"
#include "mapfile/map_format.h"
#include "mapfile/map_layout.h"
#include "mapfile/map_sections.h"

namespace ldsm::mapfile {
namespace {

void writeSection(ByteWriter& w, std::uint32_t tag, const MapData& map) {
  if (tag == kCalibrationTag) writeCalibration(w, map.calibration);
  if (tag == kKeyframesTag) writeKeyframes(w, map.keyframes);
  if (tag == kKeyframeDataTag) writeKeyframeData(w, map.data);
  if (tag == kPointsTag) writePoints(w, map.points);
  if (tag == kCovisibilityTag) writeCovisibility(w, map.covisibility);
  if (tag == kGraphTag) writeGraph(w, map.graph);
  if (tag == kVocabularyTag) w.bytes(map.vocabulary.data(), map.vocabulary.size());
  if (tag == kRefinementTag) writeRefinement(w, map.calibration);
}

void readSection(ByteReader& r, std::uint32_t tag, MapData& map) {
  if (tag == kCalibrationTag) map.calibration = readCalibration(r);
  if (tag == kKeyframesTag) map.keyframes = readKeyframes(r);
  if (tag == kKeyframeDataTag) map.data = readKeyframeData(r);
  if (tag == kPointsTag) map.points = readPoints(r);
  if (tag == kCovisibilityTag) map.covisibility = readCovisibility(r);
  if (tag == kGraphTag) map.graph = readGraph(r);
  if (tag == kVocabularyTag) {
    const std::size_t n = r.remaining();
    const std::uint8_t* p = r.bytes(n);
    map.vocabulary.assign(p, p + n);
  }
  if (tag == kRefinementTag) readRefinement(r, map.calibration);
}

/// Bytes to reserve for the whole file (exact but for the small sections).
std::size_t estimatedBytes(const MapData& map) {
  return layoutBytes(std::size(kSectionOrder) + std::size(kOptionalSections)) + 256 +
         map.keyframes.size() * 96 + keyframeDataBytes(map.data) + map.points.size() * 40 +
         map.covisibility.size() * 12 + map.graph.size() * 472 + map.vocabulary.size();
}

}  // namespace
}  // namespace ldsm::mapfile

namespace ldsm {

using mapfile::ByteReader;
using mapfile::ByteWriter;
using mapfile::kOptionalSections;
using mapfile::kSectionOrder;
using mapfile::layoutBytes;
using mapfile::SectionEntry;
using mapfile::sectionLabel;

std::vector<std::uint8_t> encodeMap(const MapData& map) {
  if (const auto problem = mapfile::findMapProblem(map))
    throw Error("map to save: " + sectionLabel(problem->section) + ": " + problem->what);
  std::vector<std::uint8_t> file;
  file.reserve(mapfile::estimatedBytes(map));
  file.resize(layoutBytes(std::size(kSectionOrder) + std::size(kOptionalSections)));
  ByteWriter w(file);
  std::vector<SectionEntry> sections;
  const auto write = [&](std::uint32_t tag) {
    SectionEntry s;
    s.tag = tag;
    s.offset = file.size();
    mapfile::writeSection(w, tag, map);
    s.size = file.size() - s.offset;
    sections.push_back(s);
  };
  for (const std::uint32_t tag : kSectionOrder) write(tag);
  for (const std::uint32_t tag : kOptionalSections) write(tag);
  mapfile::writeMapLayout(file, std::move(sections));
  return file;
}

MapData decodeMap(const std::uint8_t* data, std::size_t size, const std::string& where) {
  const mapfile::MapLayout layout = mapfile::readMapLayout(data, size, where);
  MapData map;
  const auto read = [&](const SectionEntry& s) {
    ByteReader r(data + s.offset, static_cast<std::size_t>(s.size),
                 where + ": " + sectionLabel(s.tag));
    mapfile::readSection(r, s.tag, map);
    r.expectEnd();
  };
  for (const std::uint32_t tag : kSectionOrder) read(*layout.find(tag));  // readMapLayout checked
  for (const std::uint32_t tag : kOptionalSections)
    if (const SectionEntry* s = layout.find(tag)) read(*s);
  if (const auto problem = mapfile::findMapProblem(map))
    throw InputError(where + ": " + sectionLabel(problem->section) + ": " + problem->what);
  return map;
}

}  // namespace ldsm
