#include "mapfile/map_format.h"

#include <cstdio>

namespace ldsm::mapfile {

std::string tagText(std::uint32_t tag) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<unsigned char>(tag >> (8 * i));
    if (c >= 0x20 && c < 0x7F && c != '\\') {
      s += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "\\x%02X", c);
      s += hex;
    }
  }
  return s;
}

std::string sectionLabel(std::uint32_t tag) {
  const char* name = nullptr;
  if (tag == kCalibrationTag) name = "calibration";
  if (tag == kKeyframesTag) name = "keyframes";
  if (tag == kKeyframeDataTag) name = "keyframe data";
  if (tag == kPointsTag) name = "points";
  if (tag == kCovisibilityTag) name = "covisibility";
  if (tag == kGraphTag) name = "pose graph";
  if (tag == kVocabularyTag) name = "vocabulary";
  if (tag == kRefinementTag) name = "calibration refinement";
  return "section " + tagText(tag) + (name ? std::string(" (") + name + ")" : std::string());
}

}  // namespace ldsm::mapfile
