// The constants of the map file format (docs/map-file.md): signature, version, header layout and
// the sections a version-1 file holds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace ldsm::mapfile {

constexpr char kMagic[8] = {'L', 'D', 'S', 'M', 'M', 'A', 'P', '\0'};
/// The version this build writes and the newest it reads. Bump it for any change a reader of the
/// previous version would misread; a new, optional section needs no bump (readers skip unknown
/// tags).
constexpr std::uint32_t kFormatVersion = 1;

/// magic (8), version (u32), section count (u32), header checksum (u32), then the table.
constexpr std::size_t kHeaderBytes = 20;
/// Per section: tag (4 bytes), checksum (u32), offset (u64), size (u64).
constexpr std::size_t kTableEntryBytes = 24;
/// More sections than this is a corrupt header, not a big map.
constexpr std::uint32_t kMaxSections = 256;

/// Section tags: four ASCII bytes, read as a little-endian u32.
constexpr std::uint32_t tagOf(const char (&s)[5]) {
  return static_cast<std::uint32_t>(static_cast<unsigned char>(s[0])) |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[1])) << 8 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[2])) << 16 |
         static_cast<std::uint32_t>(static_cast<unsigned char>(s[3])) << 24;
}

constexpr std::uint32_t kCalibrationTag = tagOf("CALB");
constexpr std::uint32_t kKeyframesTag = tagOf("KFRM");
constexpr std::uint32_t kKeyframeDataTag = tagOf("KFDT");
constexpr std::uint32_t kPointsTag = tagOf("PNTS");
constexpr std::uint32_t kCovisibilityTag = tagOf("COVI");
constexpr std::uint32_t kGraphTag = tagOf("GRPH");
constexpr std::uint32_t kVocabularyTag = tagOf("VOCB");
constexpr std::uint32_t kRefinementTag = tagOf("CALR");

/// The sections of a version-1 file, in the order they are written; all are required.
constexpr std::uint32_t kSectionOrder[] = {kCalibrationTag,  kKeyframesTag, kKeyframeDataTag,
                                           kPointsTag,       kCovisibilityTag, kGraphTag,
                                           kVocabularyTag};

/// Optional sections this build writes after the required ones (every time) and reads when
/// present; a file without them is read with their defaults.
constexpr std::uint32_t kOptionalSections[] = {kRefinementTag};

/// "KFDT" for a tag, with non-printable bytes as "\xNN".
std::string tagText(std::uint32_t tag);
/// "section KFDT (keyframe data)"; unknown tags: "section XXXX".
std::string sectionLabel(std::uint32_t tag);

}  // namespace ldsm::mapfile
