#include "wire_format.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "ldsm/drivers/json_writer.h"

namespace ldsm::viewer {
namespace {

void putU32(std::string& s, std::uint32_t v) {
  const char b[4] = {static_cast<char>(v & 0xff), static_cast<char>((v >> 8) & 0xff),
                     static_cast<char>((v >> 16) & 0xff), static_cast<char>((v >> 24) & 0xff)};
  s.append(b, 4);
}

void putFloats(std::string& s, const float* data, std::size_t n) {
  // The page reads float32 little-endian; every platform ldsm builds for stores floats so.
  static_assert(sizeof(float) == 4, "float32 expected");
  s.append(reinterpret_cast<const char*>(data), n * sizeof(float));
}

/// A record with its length prefix still to be filled in (finish()).
std::string startRecord(std::uint32_t kind, std::size_t capacity) {
  std::string s;
  s.reserve(kLengthBytes + capacity);
  putU32(s, 0);
  putU32(s, kind);
  return s;
}

WireMessage finish(std::string s) {
  const auto n = static_cast<std::uint32_t>(s.size() - kLengthBytes);
  for (std::size_t i = 0; i < kLengthBytes; ++i) s[i] = static_cast<char>((n >> (8 * i)) & 0xff);
  return WireMessage{std::move(s)};
}

double finiteOr(double v, double fallback) {
  return std::isfinite(v) ? v : fallback;
}

}  // namespace

int strideOf(StreamKind kind) {
  return kind == StreamKind::Points ? kPointStride : kPoseStride;
}

void appendDelta(StreamKind kind, const std::vector<float>& data, std::size_t from,
                 std::size_t have, std::size_t max_elements, std::vector<WireMessage>& out) {
  const auto stride = static_cast<std::size_t>(strideOf(kind));
  const std::size_t total = data.size() / stride;
  from = std::min({from, have, total});
  if (from == total && have == total) return;  // up to date
  max_elements = std::max<std::size_t>(max_elements, 1);
  std::size_t start = from;
  do {
    const std::size_t count = std::min(max_elements, total - start);
    std::string m = startRecord(static_cast<std::uint32_t>(kind),
                                kHeaderBytes + count * stride * sizeof(float));
    putU32(m, static_cast<std::uint32_t>(start));
    putU32(m, static_cast<std::uint32_t>(count));
    putU32(m, static_cast<std::uint32_t>(start + count));
    putFloats(m, data.data() + start * stride, count * stride);
    out.push_back(finish(std::move(m)));
    start += count;
  } while (start < total);
}

WireMessage encodeImage(const ViewerImage& image) {
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  const std::size_t n = std::min(pixels, image.pixels.size());
  const std::size_t points = image.points.size() / 2;
  std::string m = startRecord(kImageMessage, kHeaderBytes + pixels + 3 + points * 8);
  putU32(m, static_cast<std::uint32_t>(image.width));
  putU32(m, static_cast<std::uint32_t>(n == pixels ? image.height : 0));
  putU32(m, static_cast<std::uint32_t>(points));
  if (n == pixels) m.append(reinterpret_cast<const char*>(image.pixels.data()), n);
  m.resize((m.size() + 3) / 4 * 4, '\0');  // the prefix is 4 bytes: the message is aligned too
  putFloats(m, image.points.data(), points * 2);
  return finish(std::move(m));
}

WireMessage encodeFigures(const ViewerSnapshot& s, std::size_t max_list) {
  const ViewerFigures& f = s.figures;
  drivers::JsonWriter j;
  j.beginObject();
  j.key("type").value("figures");
  j.key("source").value(f.source);
  j.key("mode").value(f.mode);
  j.key("status").value(f.status);
  j.key("fps").value(finiteOr(f.fps, 0.0));
  j.key("frames").value(f.frames);
  j.key("tracked_frames").value(f.tracked_frames);
  j.key("dropped_frames").value(f.dropped_frames);
  j.key("keyframes").value(f.keyframes);
  j.key("loops").value(f.loops);
  j.key("reactivations").value(f.reactivations);
  j.key("map_points").value(f.map_points);
  j.key("latency_mean_ms").value(finiteOr(f.latency_mean_ms, 0.0));
  j.key("latency_p99_ms").value(finiteOr(f.latency_p99_ms, 0.0));
  j.key("ms_per_frame").value(finiteOr(f.ms_per_frame, 0.0));
  j.key("rss_mb").value(finiteOr(f.rss_mb, 0.0));
  j.key("map_mb").value(finiteOr(f.map_mb, 0.0));
  j.key("finished").value(f.finished);
  j.key("current");
  if (s.has_current) {
    j.beginArray();
    for (float v : s.current) j.value(finiteOr(v, 0.0));
    j.endArray();
  } else {
    j.null();
  }
  j.key("loop_edges").beginArray();
  const std::size_t first_loop = s.loops.size() > max_list ? s.loops.size() - max_list : 0;
  for (std::size_t i = first_loop; i < s.loops.size(); ++i)
    j.beginArray().value(s.loops[i][0]).value(s.loops[i][1]).endArray();
  j.endArray();
  j.key("reactivated").beginArray();
  const std::size_t first_re =
      s.reactivated.size() > max_list ? s.reactivated.size() - max_list : 0;
  for (std::size_t i = first_re; i < s.reactivated.size(); ++i) j.value(s.reactivated[i]);
  j.endArray();
  j.endObject();
  const std::string json = j.str();
  std::string m = startRecord(kFiguresMessage, 4 + json.size());
  m += json;
  return finish(std::move(m));
}

}  // namespace ldsm::viewer
