#include "ldsm/drivers/ply_reader.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>

#include "ldsm/error.h"

namespace ldsm::drivers {
namespace {

struct Property {
  std::string name;
  int bytes = 0;
  char kind = 'f';  ///< 'i' signed, 'u' unsigned, 'f' floating
};

bool propertyType(const std::string& t, Property& p) {
  static const struct {
    const char* name;
    int bytes;
    char kind;
  } kTypes[] = {{"char", 1, 'i'},  {"int8", 1, 'i'},    {"uchar", 1, 'u'},  {"uint8", 1, 'u'},
                {"short", 2, 'i'}, {"int16", 2, 'i'},   {"ushort", 2, 'u'}, {"uint16", 2, 'u'},
                {"int", 4, 'i'},   {"int32", 4, 'i'},   {"uint", 4, 'u'},   {"uint32", 4, 'u'},
                {"float", 4, 'f'}, {"float32", 4, 'f'}, {"double", 8, 'f'}, {"float64", 8, 'f'}};
  for (const auto& k : kTypes)
    if (t == k.name) {
      p.bytes = k.bytes;
      p.kind = k.kind;
      return true;
    }
  return false;
}

std::uint8_t toByte(double v) {
  return static_cast<std::uint8_t>(v >= 0.0 && v <= 255.0 ? v : v > 255.0 ? 255.0 : 0.0);
}

double decode(const char* b, const Property& p) {
  if (p.kind == 'f') {
    if (p.bytes == 4) {
      float f;
      std::memcpy(&f, b, 4);
      return f;
    }
    double d;
    std::memcpy(&d, b, 8);
    return d;
  }
  std::uint64_t u = 0;
  for (int i = p.bytes - 1; i >= 0; --i) u = (u << 8) | static_cast<unsigned char>(b[i]);
  if (p.kind == 'u') return static_cast<double>(u);
  const std::uint64_t sign = std::uint64_t{1} << (8 * p.bytes - 1);
  return static_cast<double>(static_cast<std::int64_t>(u ^ sign) - static_cast<std::int64_t>(sign));
}

}  // namespace

PlyPoints readPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  auto fail = [&](const std::string& what) { return InputError(path + ": " + what); };
  std::string line;
  if (!std::getline(in, line) || line.rfind("ply", 0) != 0) throw fail("not a PLY file");
  bool binary = false, have_format = false, in_vertex = false, vertex_seen = false;
  long long count = -1;
  std::vector<Property> props;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "end_header") break;
    if (word == "comment" || word == "obj_info" || word.empty()) continue;
    if (word == "format") {
      std::string f;
      ls >> f;
      if (f == "binary_little_endian")
        binary = true;
      else if (f != "ascii")
        throw fail("unsupported format " + f);
      have_format = true;
    } else if (word == "element") {
      std::string name;
      ls >> name;
      in_vertex = name == "vertex";
      if (in_vertex) {
        if (!(ls >> count) || count < 0) throw fail("bad vertex count");
        vertex_seen = true;
      } else if (!vertex_seen) {
        throw fail("element " + name + " before the vertices is not supported");
      }
    } else if (word == "property") {
      if (!in_vertex) continue;
      std::string type, name;
      ls >> type >> name;
      if (type == "list") throw fail("list property in the vertex element is not supported");
      Property p;
      p.name = name;
      if (!propertyType(type, p)) throw fail("unknown property type " + type);
      props.push_back(p);
    } else {
      throw fail("unexpected header line \"" + line + "\"");
    }
  }
  if (!in || !have_format || count < 0) throw fail("incomplete header");
  auto index = [&](const char* name) {
    for (std::size_t i = 0; i < props.size(); ++i)
      if (props[i].name == name) return static_cast<int>(i);
    return -1;
  };
  const int ix = index("x"), iy = index("y"), iz = index("z");
  if (ix < 0 || iy < 0 || iz < 0) throw fail("vertex element without x, y, z");
  const int ir = index("red"), ig = index("green"), ib = index("blue"), ii = index("intensity");
  const bool colours = ir >= 0 && ig >= 0 && ib >= 0;
  std::size_t stride = 0;
  for (const Property& p : props) stride += static_cast<std::size_t>(p.bytes);
  // Bound the allocation by what the file can hold.
  const auto header_end = in.tellg();
  in.seekg(0, std::ios::end);
  const auto remaining = static_cast<long long>(in.tellg() - header_end);
  in.seekg(header_end);
  const long long min_bytes = binary ? 1 : 2;  // ASCII: a digit and a separator at least
  if (count >
      remaining / std::max<long long>(binary ? static_cast<long long>(stride)
                                             : min_bytes * static_cast<long long>(props.size()),
                                      1))
    throw fail("file is shorter than its " + std::to_string(count) + " vertices");
  PlyPoints out;
  out.points.reserve(static_cast<std::size_t>(count));
  std::vector<double> v(props.size());
  std::vector<char> rec(stride);
  for (long long n = 0; n < count; ++n) {
    if (binary) {
      if (!in.read(rec.data(), static_cast<std::streamsize>(stride)))
        throw fail("file ends at vertex " + std::to_string(n) + " of " + std::to_string(count));
      std::size_t off = 0;
      for (std::size_t k = 0; k < props.size(); ++k) {
        v[k] = decode(rec.data() + off, props[k]);
        off += static_cast<std::size_t>(props[k].bytes);
      }
    } else {
      for (std::size_t k = 0; k < props.size(); ++k)
        if (!(in >> v[k]))
          throw fail("vertex " + std::to_string(n) + " of " + std::to_string(count) +
                     ": missing or non-numeric value");
    }
    out.points.emplace_back(static_cast<float>(v[ix]), static_cast<float>(v[iy]),
                            static_cast<float>(v[iz]));
    if (colours)
      out.colours.push_back({toByte(v[ir]), toByte(v[ig]),
                             toByte(v[ib])});
    if (ii >= 0) out.intensities.push_back(static_cast<float>(v[ii]));
  }
  return out;
}

}  // namespace ldsm::drivers
