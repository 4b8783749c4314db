// Vocabulary::serialize() / deserialize(): the binary format documented in vocabulary.h.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "ldsm/error.h"
#include "loop/vocabulary.h"

namespace ldsm::loop {
namespace {

constexpr char kMagic[8] = {'L', 'D', 'S', 'M', 'V', 'O', 'C', 'B'};
constexpr std::size_t kHeaderBytes = 8 + 6 * 4;
constexpr std::size_t kDescriptorBytes = 32;
constexpr std::size_t kChecksumBytes = 8;

std::uint64_t readU64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
std::uint32_t readU32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}
void writeU64(std::uint8_t* p, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void writeU32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

/// FNV-1a over 64-bit little-endian words, the tail zero-padded, then the byte count.
std::uint64_t checksum(const std::uint8_t* data, std::size_t size) {
  constexpr std::uint64_t kPrime = 0x100000001B3ull;
  std::uint64_t h = 0xCBF29CE484222325ull;
  std::size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    h ^= readU64(data + i);
    h *= kPrime;
  }
  if (i < size) {
    std::uint8_t tail[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    std::memcpy(tail, data + i, size - i);
    h ^= readU64(tail);
    h *= kPrime;
  }
  h ^= static_cast<std::uint64_t>(size);
  h *= kPrime;
  return h;
}

std::uint32_t floatBits(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof(u));
  return u;
}
float bitsFloat(std::uint32_t u) {
  float f = 0.f;
  std::memcpy(&f, &u, sizeof(f));
  return f;
}

/// The header of a serialised vocabulary, checked.
struct Header {
  std::uint32_t k = 0;
  std::uint32_t levels = 0;
  std::uint64_t nodes = 0;
  std::uint64_t words = 0;
  std::uint32_t documents = 0;
};

/// Reads and checks the header, the size it implies and the checksum; InputError naming `where`
/// and the problem otherwise.
Header readHeader(const std::uint8_t* data, std::size_t size, const std::string& where) {
  auto fail = [&where](const std::string& what) -> InputError {
    return InputError(where + ": " + what);
  };
  if (data == nullptr || size < 8 || std::memcmp(data, kMagic, 8) != 0) {
    throw fail("not an ldsm vocabulary (missing \"LDSMVOCB\" signature)");
  }
  if (size < kHeaderBytes) {
    throw fail("truncated vocabulary: " + std::to_string(size) + " bytes, the header alone has " +
               std::to_string(kHeaderBytes));
  }
  const std::uint32_t version = readU32(data + 8);
  if (version != Vocabulary::kFormatVersion) {
    throw fail("unsupported vocabulary format version " + std::to_string(version) +
               " (this build reads version " + std::to_string(Vocabulary::kFormatVersion) + ")");
  }
  Header h;
  h.k = readU32(data + 12);
  h.levels = readU32(data + 16);
  h.nodes = readU32(data + 20);
  h.words = readU32(data + 24);
  h.documents = readU32(data + 28);
  if (h.k < 2 || h.k > static_cast<std::uint32_t>(Vocabulary::kMaxBranching)) {
    throw fail("corrupt vocabulary: branching " + std::to_string(h.k) + " outside [2, " +
               std::to_string(Vocabulary::kMaxBranching) + "]");
  }
  if (h.levels < 1 || h.levels > static_cast<std::uint32_t>(Vocabulary::kMaxLevels)) {
    throw fail("corrupt vocabulary: levels " + std::to_string(h.levels) + " outside [1, " +
               std::to_string(Vocabulary::kMaxLevels) + "]");
  }
  if (h.nodes < 2 || h.words < 1 || h.words >= h.nodes) {
    throw fail("corrupt vocabulary: " + std::to_string(h.nodes) + " nodes and " +
               std::to_string(h.words) + " words");
  }
  const std::uint64_t expected =
      kHeaderBytes + h.nodes + (h.nodes - 1) * kDescriptorBytes + 4 * h.words + kChecksumBytes;
  if (size < expected) {
    throw fail("truncated vocabulary: " + std::to_string(size) + " bytes, expected " +
               std::to_string(expected) + " for " + std::to_string(h.nodes) + " nodes and " +
               std::to_string(h.words) + " words");
  }
  if (size > expected) {
    throw fail("corrupt vocabulary: " + std::to_string(size - expected) +
               " unexpected bytes after the end of the data");
  }
  if (checksum(data, size - kChecksumBytes) != readU64(data + size - kChecksumBytes)) {
    throw fail("corrupt vocabulary: checksum mismatch");
  }
  return h;
}

/// The first child of every node of the breadth-first layout (children follow their parent,
/// contiguously, in parent order), checking that the tree fits the header: at most k children,
/// at most `levels` deep, every node reachable, one leaf per word.
std::vector<std::uint32_t> linkTree(const std::vector<std::uint8_t>& child_count, const Header& h,
                                    const std::string& where) {
  auto fail = [&where](const std::string& what) -> InputError {
    return InputError(where + ": " + what);
  };
  std::vector<std::uint32_t> first_child(h.nodes, 0u);
  std::vector<std::uint8_t> depth(h.nodes, 0);
  std::uint64_t next = 1;
  std::uint64_t leaves = 0;
  for (std::uint64_t n = 0; n < h.nodes; ++n) {
    const std::uint32_t count = child_count[n];
    if (count == 0) {
      ++leaves;
      continue;
    }
    if (count > h.k) {
      throw fail("corrupt vocabulary: node " + std::to_string(n) + " has " + std::to_string(count) +
                 " children, more than the branching " + std::to_string(h.k));
    }
    if (next <= n || next + count > h.nodes) {
      throw fail("corrupt vocabulary: the children of node " + std::to_string(n) +
                 " lie outside the node table");
    }
    if (depth[n] + 1u > h.levels) {
      throw fail("corrupt vocabulary: the tree is deeper than its " + std::to_string(h.levels) +
                 " levels");
    }
    first_child[n] = static_cast<std::uint32_t>(next);
    for (std::uint32_t c = 0; c < count; ++c) {
      depth[next + c] = static_cast<std::uint8_t>(depth[n] + 1);
    }
    next += count;
  }
  if (next != h.nodes) {
    throw fail("corrupt vocabulary: " + std::to_string(h.nodes - next) +
               " nodes are not reachable from the root");
  }
  if (leaves != h.words) {
    throw fail("corrupt vocabulary: " + std::to_string(leaves) + " leaves but " +
               std::to_string(h.words) + " word weights");
  }
  return first_child;
}

}  // namespace

std::vector<std::uint8_t> Vocabulary::serialize() const {
  if (nodeCount() < 2) throw Error("vocabulary: cannot serialise a vocabulary without a tree");
  const std::size_t nodes = nodeCount();
  const std::size_t words = wordCount();
  const std::size_t size =
      kHeaderBytes + nodes + (nodes - 1) * kDescriptorBytes + 4 * words + kChecksumBytes;
  std::vector<std::uint8_t> out(size);
  std::uint8_t* p = out.data();
  std::memcpy(p, kMagic, 8);
  writeU32(p + 8, kFormatVersion);
  writeU32(p + 12, static_cast<std::uint32_t>(branching_));
  writeU32(p + 16, static_cast<std::uint32_t>(levels_));
  writeU32(p + 20, static_cast<std::uint32_t>(nodes));
  writeU32(p + 24, static_cast<std::uint32_t>(words));
  writeU32(p + 28, training_images_);
  p += kHeaderBytes;
  std::memcpy(p, child_count_.data(), nodes);
  p += nodes;
  for (std::size_t n = 1; n < nodes; ++n) {
    for (std::size_t w = 0; w < 4; ++w) writeU64(p + 8 * w, node_descriptor_[n][w]);
    p += kDescriptorBytes;
  }
  for (float weight : word_weight_) {
    writeU32(p, floatBits(weight));
    p += 4;
  }
  writeU64(p, checksum(out.data(), size - kChecksumBytes));
  return out;
}

Vocabulary Vocabulary::deserialize(const std::uint8_t* data, std::size_t size,
                                   const std::string& where) {
  const Header h = readHeader(data, size, where);
  Vocabulary v;
  v.branching_ = static_cast<int>(h.k);
  v.levels_ = static_cast<int>(h.levels);
  v.training_images_ = h.documents;
  const std::uint8_t* p = data + kHeaderBytes;
  v.child_count_.assign(p, p + h.nodes);
  p += h.nodes;
  v.first_child_ = linkTree(v.child_count_, h, where);
  v.node_descriptor_.resize(h.nodes);
  v.node_descriptor_[0] = OrbDescriptor{};
  for (std::uint64_t n = 1; n < h.nodes; ++n) {
    for (std::size_t w = 0; w < 4; ++w) v.node_descriptor_[n][w] = readU64(p + 8 * w);
    p += kDescriptorBytes;
  }
  v.buildWordIndex();
  for (std::uint64_t w = 0; w < h.words; ++w) {
    const float weight = bitsFloat(readU32(p));
    p += 4;
    if (!std::isfinite(weight) || weight < 0.f) {
      throw InputError(where + ": corrupt vocabulary: weight of word " + std::to_string(w) +
                       " is not a finite non-negative number");
    }
    v.word_weight_[w] = weight;
  }
  return v;
}

}  // namespace ldsm::loop
