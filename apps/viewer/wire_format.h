// The messages the viewer sends to a page over its WebSocket (the page's side is
// web/viewer.js). Every array travels as a prefix delta: "keep your first `from` elements, drop
// the rest, append these", so a page that has the first n elements of an array only receives what
// changed after the first difference (a loop closure that moves old poses resends from there).
//
// Binary message, little-endian:
//   u32 kind, u32 from, u32 count, u32 total, then count * stride float32
//   kind 1: trajectory (stride 7), 2: keyframes (stride 7), 3: map points (stride 4);
//   `total` is the array's length after the message (the page checks it).
//   kind 4: image: u32 4, u32 width, u32 height, u32 point count, width*height grey bytes,
//   then (padded to 4 bytes) point count * 2 float32 pixel coordinates.
// Text message: one JSON object {"type":"figures", ...} per update (figures, current pose, loop
// edges, reactivated keyframes).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "snapshot.h"

namespace ldsm::viewer {

enum class StreamKind : std::uint32_t { Trajectory = 1, Keyframes = 2, Points = 3 };
inline constexpr std::uint32_t kImageMessage = 4;
inline constexpr std::size_t kHeaderBytes = 16;

/// The stride (floats per element) of a stream.
int strideOf(StreamKind kind);

/// One message for the page: binary (arrays, image) or text (JSON).
struct WireMessage {
  bool binary = true;
  std::string bytes;
};

/// Messages bringing a page that holds `have` elements of `data` (whose first `from` elements it
/// holds unchanged) up to date: one message per chunk of at most `max_elements` elements, or a
/// single empty one that only truncates. Appends to `out`; nothing when the page is up to date.
void appendDelta(StreamKind kind, const std::vector<float>& data, std::size_t from,
                 std::size_t have, std::size_t max_elements, std::vector<WireMessage>& out);

/// The image message (kind 4).
WireMessage encodeImage(const ViewerImage& image);

/// The JSON text message with the figures, the current pose, loop edges and reactivated
/// keyframes (at most `max_list` of each, the newest).
WireMessage encodeFigures(const ViewerSnapshot& snapshot, std::size_t max_list);

}  // namespace ldsm::viewer
