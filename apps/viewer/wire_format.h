// The messages the viewer sends to a page over its HTTP stream, GET /stream (the page's side is
// web/protocol.js). Every array travels as a prefix delta: "keep your first `from` elements, drop
// the rest, append these", so a page that has the first n elements of an array only receives what
// changed after the first difference (a loop closure that moves old poses resends from there).
//
// The stream is a sequence of records, little-endian: u32 length (the bytes that follow), then
// the message, which starts with u32 kind:
//   kind 1: trajectory (stride 7), 2: keyframes (stride 7), 3: map points (stride 4):
//     u32 kind, u32 from, u32 count, u32 total, then count * stride float32;
//     `total` is the array's length after the message (the page checks it).
//   kind 4: image: u32 4, u32 width, u32 height, u32 point count, width*height grey bytes,
//     then (padded to 4 bytes) point count * 2 float32 pixel coordinates.
//   kind 5: figures: u32 5, then one UTF-8 JSON object {"type":"figures", ...} per update
//     (figures, current pose, loop edges, reactivated keyframes).
// Every message is a multiple of 4 bytes long except the figures; nothing travels the other way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "snapshot.h"

namespace ldsm::viewer {

enum class StreamKind : std::uint32_t { Trajectory = 1, Keyframes = 2, Points = 3 };
inline constexpr std::uint32_t kImageMessage = 4;
inline constexpr std::uint32_t kFiguresMessage = 5;
inline constexpr std::size_t kLengthBytes = 4;   ///< the record's length prefix
inline constexpr std::size_t kHeaderBytes = 16;  ///< an array message's header, after the prefix

/// The stride (floats per element) of a stream.
int strideOf(StreamKind kind);

/// One record of the stream, its length prefix included: written to the page as it is.
struct WireMessage {
  std::string bytes;
};

/// Messages bringing a page that holds `have` elements of `data` (whose first `from` elements it
/// holds unchanged) up to date: one message per chunk of at most `max_elements` elements, or a
/// single empty one that only truncates. Appends to `out`; nothing when the page is up to date.
void appendDelta(StreamKind kind, const std::vector<float>& data, std::size_t from,
                 std::size_t have, std::size_t max_elements, std::vector<WireMessage>& out);

/// The image message (kind 4).
WireMessage encodeImage(const ViewerImage& image);

/// The figures message (kind 5): JSON with the figures, the current pose, loop edges and
/// reactivated keyframes (at most `max_list` of each, the newest).
WireMessage encodeFigures(const ViewerSnapshot& snapshot, std::size_t max_list);

}  // namespace ldsm::viewer
