// The frame of a map file (docs/map-file.md, "Layout"): signature, version, the section table
// with a CRC-32 per section, and the table's own CRC-32. Reading it checks everything but the
// sections' contents.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace ldsm::mapfile {

struct SectionEntry {
  std::uint32_t tag = 0;
  std::uint32_t checksum = 0;  ///< CRC-32 of the section's bytes
  std::uint64_t offset = 0;    ///< from the start of the file
  std::uint64_t size = 0;
};

struct MapLayout {
  std::uint32_t version = 0;
  std::vector<SectionEntry> sections;  ///< in table order

  /// The entry of a tag; nullptr when absent.
  const SectionEntry* find(std::uint32_t tag) const;
};

/// Reads and checks the header and the table: the signature, a version this build reads, the
/// table's checksum, sections inside the file that tile it without gaps or overlaps, no tag
/// twice, every required section present and every section's checksum. Throws ldsm::InputError
/// "<where>: ..." naming the section at fault.
MapLayout readMapLayout(const std::uint8_t* data, std::size_t size, const std::string& where);

/// Bytes of the header and a table of `sections` entries: where the first section starts.
std::size_t layoutBytes(std::size_t sections);

/// Fills in the header and the table of `file`, whose first layoutBytes(sections.size()) bytes
/// were left for them, the sections following; computes the checksums.
void writeMapLayout(std::vector<std::uint8_t>& file, std::vector<SectionEntry> sections);

}  // namespace ldsm::mapfile
