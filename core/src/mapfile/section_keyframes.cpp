// KFRM (keyframe poses) and KFDT (keyframe data): docs/map-file.md.
#include <string>

#include "mapfile/map_sections.h"
#include "mapfile/pose_codec.h"

namespace ldsm::mapfile {
namespace {

constexpr std::size_t kKeyframeBytes = 4 + 4 + 8 + 8 + kSE3Bytes + 8;
/// The fixed part of a data keyframe, with its five counts.
constexpr std::size_t kDataHeaderBytes = 4 + 8 + 8 + 8 + 8 + 8 + kSE3Bytes + 4 + 4 + 8 + 4 + 1;
constexpr std::size_t kDataMinBytes = kDataHeaderBytes + 5 * 4;
constexpr std::size_t kPatchPointBytes = 4 * 4 + 2 * kPatternSize * 4 + 4;
constexpr std::size_t kCornerBytes = 2 * 4;
constexpr std::size_t kDescriptorBytes = 32;
constexpr std::size_t kLinkBytes = 4 + kSE3Bytes + 4 + 1;

constexpr std::uint8_t kCulledFlag = 1;
constexpr std::uint8_t kMapKeyframeFlag = 1;
constexpr std::uint32_t kCornerBit = 1u << 31;

void checkFlags(ByteReader& r, std::uint8_t flags, std::uint8_t known, const char* what) {
  if ((flags & ~known) != 0)
    r.fail(std::string(what) + " flags " + std::to_string(flags) + " have unknown bits");
}

void writePatchPoint(ByteWriter& w, const PatchPoint& p) {
  w.f32(p.u);
  w.f32(p.v);
  w.f32(p.idepth);
  w.f32(p.idepth_hessian);
  for (float c : p.colors) w.f32(c);
  for (float g : p.grad_weights) w.f32(g);
  // observations >= 0 (checked before encoding): 31 bits, the corner flag in the top bit.
  w.u32(static_cast<std::uint32_t>(p.observations) | (p.is_corner ? kCornerBit : 0u));
}

PatchPoint readPatchPoint(ByteReader& r) {
  PatchPoint p;
  p.u = r.f32();
  p.v = r.f32();
  p.idepth = r.f32();
  p.idepth_hessian = r.f32();
  for (float& c : p.colors) c = r.f32();
  for (float& g : p.grad_weights) g = r.f32();
  const std::uint32_t packed = r.u32();
  p.observations = static_cast<int>(packed & ~kCornerBit);
  p.is_corner = (packed & kCornerBit) != 0;
  return p;
}

void writeOne(ByteWriter& w, const MarginalizedKeyframe& kf) {
  w.i32(kf.id);
  w.i64(kf.frame_index);
  w.f64(kf.timestamp);
  w.f64(kf.exposure);
  w.f64(kf.aff.a);
  w.f64(kf.aff.b);
  writeSE3(w, kf.T_w_c);
  w.f32(kf.radial_k);
  w.i32(kf.map_points_in_view);
  w.f64(kf.path_length);
  w.i32(kf.newest_when_left);
  w.u8(kf.culled ? kCulledFlag : 0);

  w.count(kf.points.size());
  for (const PatchPoint& p : kf.points) writePatchPoint(w, p);
  w.count(kf.corners.size());
  for (const Eigen::Vector2f& c : kf.corners) {
    w.f32(c.x());
    w.f32(c.y());
  }
  w.count(kf.corner_idepth.size());
  for (float d : kf.corner_idepth) w.f32(d);
  w.count(kf.descriptors.size());
  for (const OrbDescriptor& d : kf.descriptors)
    for (std::uint64_t word : d) w.u64(word);
  w.count(kf.links.size());
  for (const KeyframeLink& l : kf.links) {
    w.i32(l.other);
    writeSE3(w, l.T_this_other);
    w.i32(l.shared_points);
    w.u8(l.map_keyframe ? kMapKeyframeFlag : 0);
  }
}

MarginalizedKeyframe readOne(ByteReader& r) {
  MarginalizedKeyframe kf;
  kf.id = r.i32();
  r.setContext("keyframe " + std::to_string(kf.id));
  kf.frame_index = r.i64();
  kf.timestamp = r.f64();
  kf.exposure = r.f64();
  kf.aff.a = r.f64();
  kf.aff.b = r.f64();
  kf.T_w_c = readSE3(r, "pose");
  kf.radial_k = r.f32();
  kf.map_points_in_view = r.i32();
  kf.path_length = r.f64();
  kf.newest_when_left = r.i32();
  const std::uint8_t flags = r.u8();
  checkFlags(r, flags, kCulledFlag, "keyframe");
  kf.culled = (flags & kCulledFlag) != 0;

  kf.points.resize(r.count("points", kPatchPointBytes));
  for (PatchPoint& p : kf.points) p = readPatchPoint(r);
  kf.corners.resize(r.count("corners", kCornerBytes));
  for (Eigen::Vector2f& c : kf.corners) {
    c.x() = r.f32();
    c.y() = r.f32();
  }
  kf.corner_idepth.resize(r.count("corner depths", 4));
  for (float& d : kf.corner_idepth) d = r.f32();
  kf.descriptors.resize(r.count("descriptors", kDescriptorBytes));
  for (OrbDescriptor& d : kf.descriptors)
    for (std::uint64_t& word : d) word = r.u64();
  kf.links.resize(r.count("links", kLinkBytes));
  for (KeyframeLink& l : kf.links) {
    l.other = r.i32();
    l.T_this_other = readSE3(r, "link pose");
    l.shared_points = r.i32();
    const std::uint8_t link_flags = r.u8();
    checkFlags(r, link_flags, kMapKeyframeFlag, "link");
    l.map_keyframe = (link_flags & kMapKeyframeFlag) != 0;
  }
  return kf;
}

}  // namespace

void writeKeyframes(ByteWriter& w, const std::vector<KeyframeRecord>& keyframes) {
  w.count(keyframes.size());
  for (const KeyframeRecord& kf : keyframes) {
    w.i32(kf.id);
    w.i32(kf.map);
    w.i64(kf.frame_index);
    w.f64(kf.timestamp);
    writeSE3(w, kf.T_w_c);
    w.f64(kf.scale);
  }
}

std::vector<KeyframeRecord> readKeyframes(ByteReader& r) {
  std::vector<KeyframeRecord> keyframes(r.count("keyframes", kKeyframeBytes));
  for (KeyframeRecord& kf : keyframes) {
    kf.id = r.i32();
    r.setContext("keyframe " + std::to_string(kf.id));
    kf.map = r.i32();
    kf.frame_index = r.i64();
    kf.timestamp = r.f64();
    kf.T_w_c = readSE3(r, "pose");
    kf.scale = r.f64();
  }
  r.setContext("");
  return keyframes;
}

void writeKeyframeData(ByteWriter& w, const std::vector<MarginalizedKeyframe>& data) {
  w.count(data.size());
  for (const MarginalizedKeyframe& kf : data) writeOne(w, kf);
}

std::vector<MarginalizedKeyframe> readKeyframeData(ByteReader& r) {
  std::vector<MarginalizedKeyframe> data(r.count("data keyframes", kDataMinBytes));
  for (MarginalizedKeyframe& kf : data) kf = readOne(r);
  r.setContext("");
  return data;
}

std::size_t keyframeDataBytes(const std::vector<MarginalizedKeyframe>& data) {
  std::size_t n = 4;
  for (const MarginalizedKeyframe& kf : data)
    n += kDataMinBytes + kf.points.size() * kPatchPointBytes + kf.corners.size() * kCornerBytes +
         kf.corner_idepth.size() * 4 + kf.descriptors.size() * kDescriptorBytes +
         kf.links.size() * kLinkBytes;
  return n;
}

}  // namespace ldsm::mapfile
