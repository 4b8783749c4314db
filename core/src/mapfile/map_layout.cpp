#include "mapfile/map_layout.h"

#include <algorithm>
#include <cstring>

#include "ldsm/error.h"
#include "mapfile/byte_order.h"
#include "mapfile/crc32.h"
#include "mapfile/map_format.h"

namespace ldsm::mapfile {
namespace {

std::string str(std::uint64_t v) { return std::to_string(v); }

/// CRC-32 of the header's first 16 bytes and the table (all but the checksum field itself).
std::uint32_t headerChecksum(const std::uint8_t* file, std::size_t sections) {
  const std::uint32_t c = crc32(file, 16);
  return crc32(file + kHeaderBytes, sections * kTableEntryBytes, c);
}

}  // namespace

const SectionEntry* MapLayout::find(std::uint32_t tag) const {
  for (const SectionEntry& s : sections)
    if (s.tag == tag) return &s;
  return nullptr;
}

std::size_t layoutBytes(std::size_t sections) { return kHeaderBytes + sections * kTableEntryBytes; }

void writeMapLayout(std::vector<std::uint8_t>& file, std::vector<SectionEntry> sections) {
  std::uint8_t* p = file.data();
  std::memcpy(p, kMagic, sizeof(kMagic));
  storeU32(p + 8, kFormatVersion);
  storeU32(p + 12, static_cast<std::uint32_t>(sections.size()));
  std::uint8_t* e = p + kHeaderBytes;
  for (SectionEntry& s : sections) {
    s.checksum = crc32(p + s.offset, static_cast<std::size_t>(s.size));
    storeU32(e, s.tag);
    storeU32(e + 4, s.checksum);
    storeU64(e + 8, s.offset);
    storeU64(e + 16, s.size);
    e += kTableEntryBytes;
  }
  storeU32(p + 16, headerChecksum(p, sections.size()));
}

MapLayout readMapLayout(const std::uint8_t* data, std::size_t size, const std::string& where) {
  const auto fail = [&where](const std::string& what) { return InputError(where + ": " + what); };
  if (data == nullptr || size < sizeof(kMagic) || std::memcmp(data, kMagic, sizeof(kMagic)) != 0)
    throw fail("not an ldsm map (no \"LDSMMAP\" signature)");
  if (size < kHeaderBytes)
    throw fail("truncated: " + str(size) + " bytes, the header alone has " + str(kHeaderBytes));
  MapLayout layout;
  layout.version = loadU32(data + 8);
  if (layout.version > kFormatVersion)
    throw fail("format version " + str(layout.version) + " is newer than this build reads (" +
               str(kFormatVersion) + "): it was written by a newer ldsm");
  if (layout.version == 0) throw fail("corrupt header: format version 0");
  const std::uint32_t count = loadU32(data + 12);
  if (count == 0 || count > kMaxSections)
    throw fail("corrupt header: " + str(count) + " sections (1 to " + str(kMaxSections) + ")");
  const std::size_t table_end = layoutBytes(count);
  if (size < table_end)
    throw fail("truncated: the table of " + str(count) + " sections ends at byte " +
               str(table_end) + ", the file has " + str(size) + " bytes");
  if (headerChecksum(data, count) != loadU32(data + 16))
    throw fail("corrupt header: the section table's checksum does not match");

  const std::uint8_t* e = data + kHeaderBytes;
  for (std::uint32_t i = 0; i < count; ++i, e += kTableEntryBytes) {
    SectionEntry s{loadU32(e), loadU32(e + 4), loadU64(e + 8), loadU64(e + 16)};
    const std::string label = sectionLabel(s.tag);
    if (s.offset < table_end || s.offset > size || s.size > size - s.offset)
      throw fail(label + ": bytes " + str(s.offset) + " to " + str(s.offset + s.size) +
                 " lie outside the file (" + str(size) + " bytes; truncated?)");
    if (layout.find(s.tag) != nullptr) throw fail(label + ": appears twice in the table");
    layout.sections.push_back(s);
  }

  // The sections tile the file after the table: nothing unchecked hides between them.
  std::vector<SectionEntry> by_offset = layout.sections;
  std::stable_sort(by_offset.begin(), by_offset.end(),
                   [](const SectionEntry& a, const SectionEntry& b) { return a.offset < b.offset; });
  std::uint64_t at = table_end;
  for (const SectionEntry& s : by_offset) {
    if (s.offset < at)
      throw fail(sectionLabel(s.tag) + ": overlaps the section before it (starts at byte " +
                 str(s.offset) + ", before byte " + str(at) + ")");
    if (s.offset > at)
      throw fail(str(s.offset - at) + " bytes at byte " + str(at) + " belong to no section");
    at = s.offset + s.size;
  }
  if (at < size)
    throw fail(str(size - at) + " unexpected bytes after the last section (at byte " + str(at) +
               ")");

  for (const std::uint32_t tag : kSectionOrder)
    if (layout.find(tag) == nullptr) throw fail(sectionLabel(tag) + ": missing (required)");
  for (const SectionEntry& s : layout.sections) {
    if (crc32(data + s.offset, static_cast<std::size_t>(s.size)) != s.checksum)
      throw fail(sectionLabel(s.tag) + ": checksum mismatch (the file is corrupt)");
  }
  return layout;
}

}  // namespace ldsm::mapfile
