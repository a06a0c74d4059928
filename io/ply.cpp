// PLY in (ASCII and binary; positions, polygons or tristrips, per-corner `texcoord` lists or
// per-vertex texture coordinates) and out (binary, MeshLab's per-wedge texture coordinates,
// charts).
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "io/scan.h"
#include "io/write.h"

namespace sdp::io {
namespace detail {
namespace {

enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

bool plyTypeFromName(std::string_view n, PlyType& type) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::Uint8},
      {"uint8", PlyType::Uint8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::Uint16},  {"uint16", PlyType::Uint16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},    {"uint", PlyType::Uint32},     {"uint32", PlyType::Uint32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [type_name, t] : kNames) {
    if (n == type_name) {
      type = t;
      return true;
    }
  }
  return false;
}

size_t plyTypeSize(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::Uint8:
      return 1;
    case PlyType::Int16:
    case PlyType::Uint16:
      return 2;
    case PlyType::Int32:
    case PlyType::Uint32:
    case PlyType::Float32:
      return 4;
    case PlyType::Float64:
      return 8;
  }
  return 1;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // item type for lists
  bool is_list = false;
  PlyType count_type = PlyType::Uint8;
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  size_t body_offset = 0;
  int body_first_line = 0;  // line number of the header's last line
};

PlyHeader parsePlyHeader(std::string_view text, const std::string& name) {
  LineReader lines(text, false);
  std::string_view line, token;
  if (!lines.next(line) || !LineTokens(line).next(token) || token != "ply") {
    fail(name, "not a PLY file (first line is not 'ply')");
  }
  PlyHeader header;
  bool has_format = false;
  while (true) {
    if (!lines.next(line)) fail(name, "file ends in the header (no end_header line)");
    LineTokens tokens(line);
    if (!tokens.next(token)) continue;
    const std::string at = lineAt(lines.line());
    if (token == "end_header") break;
    if (token == "comment" || token == "obj_info") continue;
    if (token == "format") {
      std::string_view format;
      tokens.next(format);
      if (format == "ascii") {
        header.format = PlyFormat::Ascii;
      } else if (format == "binary_little_endian") {
        header.format = PlyFormat::BinaryLittleEndian;
      } else if (format == "binary_big_endian") {
        header.format = PlyFormat::BinaryBigEndian;
      } else {
        fail(name, at + "unknown format " + quoted(format));
      }
      has_format = true;
    } else if (token == "element") {
      PlyElement element;
      std::string_view element_name, count;
      if (!tokens.next(element_name) || !tokens.next(count)) {
        fail(name, at + "element line needs a name and a count");
      }
      if (!parseInteger(count, element.count) || element.count < 0) {
        fail(name, at + "cannot read element count " + quoted(count));
      }
      element.name = std::string(element_name);
      header.elements.push_back(std::move(element));
    } else if (token == "property") {
      if (header.elements.empty()) fail(name, at + "property before any element");
      PlyProperty property;
      std::string_view type_name, property_name;
      if (!tokens.next(type_name)) fail(name, at + "property line needs a type");
      if (type_name == "list") {
        property.is_list = true;
        std::string_view count_type;
        if (!tokens.next(count_type) || !plyTypeFromName(count_type, property.count_type)) {
          fail(name, at + "unknown list count type " + quoted(count_type));
        }
        if (property.count_type == PlyType::Float32 || property.count_type == PlyType::Float64) {
          fail(name, at + "list count type " + quoted(count_type) + " is not an integer type");
        }
        if (!tokens.next(type_name)) fail(name, at + "list property needs an item type");
      }
      if (!plyTypeFromName(type_name, property.type)) {
        fail(name, at + "unknown property type " + quoted(type_name));
      }
      if (!tokens.next(property_name)) fail(name, at + "property line needs a name");
      property.name = std::string(property_name);
      header.elements.back().properties.push_back(std::move(property));
    } else {
      fail(name, at + "unexpected header line starting with " + quoted(token));
    }
  }
  if (!has_format) fail(name, "header has no format line");
  header.body_offset = text.size() - lines.remainingBytes();
  header.body_first_line = lines.line();
  return header;
}

// Reads the body value by value, in ASCII or binary.
class PlyValueSource {
 public:
  PlyValueSource(std::string_view body, const PlyHeader& header, const std::string& name)
      : body_(body), format_(header.format), tokens_(body, header.body_first_line), name_(name) {}

  bool binary() const { return format_ != PlyFormat::Ascii; }
  size_t remainingBytes() const { return body_.size() - pos_; }

  // False at the end of the data; a malformed ASCII number is an error.
  bool read(PlyType type, double& value) {
    if (!binary()) {
      std::string_view token;
      if (!tokens_.next(token)) return false;
      if (!parseDouble(token, value)) {
        fail(name_, lineAt(tokens_.line()) + "cannot read " + quoted(token) + " as a number");
      }
      return true;
    }
    const size_t size = plyTypeSize(type);
    if (remainingBytes() < size) return false;
    uint64_t bits = 0;
    for (size_t b = 0; b < size; ++b) {
      const uint64_t byte = static_cast<unsigned char>(body_[pos_ + b]);
      const size_t shift = format_ == PlyFormat::BinaryLittleEndian ? b : size - 1 - b;
      bits |= byte << (8 * shift);
    }
    pos_ += size;
    value = decode(type, bits);
    return true;
  }

  // Skips `count` values of `type`; false if the data ends first.
  bool skip(PlyType type, unsigned long long count) {
    if (binary()) {
      const size_t size = plyTypeSize(type);
      if (count > remainingBytes() / size) return false;
      pos_ += static_cast<size_t>(count) * size;
      return true;
    }
    std::string_view token;
    for (unsigned long long i = 0; i < count; ++i) {
      if (!tokens_.next(token)) return false;
    }
    return true;
  }

  int line() const { return tokens_.line(); }

 private:
  static double decode(PlyType type, uint64_t bits) {
    switch (type) {
      case PlyType::Int8:
        return static_cast<int8_t>(static_cast<uint8_t>(bits));
      case PlyType::Uint8:
        return static_cast<uint8_t>(bits);
      case PlyType::Int16:
        return static_cast<int16_t>(static_cast<uint16_t>(bits));
      case PlyType::Uint16:
        return static_cast<uint16_t>(bits);
      case PlyType::Int32:
        return static_cast<int32_t>(static_cast<uint32_t>(bits));
      case PlyType::Uint32:
        return static_cast<uint32_t>(bits);
      case PlyType::Float32: {
        const uint32_t b32 = static_cast<uint32_t>(bits);
        float f;
        std::memcpy(&f, &b32, sizeof f);
        return f;
      }
      case PlyType::Float64: {
        double d;
        std::memcpy(&d, &bits, sizeof d);
        return d;
      }
    }
    return 0;
  }

  std::string_view body_;
  PlyFormat format_;
  size_t pos_ = 0;
  TokenStream tokens_;
  const std::string& name_;
};

// Bytes the smallest record of an element can take: binary scalars and list counts at their
// size, ASCII values at one digit plus a separator. Used to bound header counts by the data.
size_t minRecordBytes(const PlyElement& element, PlyFormat format) {
  size_t bytes = 0;
  for (const PlyProperty& p : element.properties) {
    bytes += format == PlyFormat::Ascii ? 2 : plyTypeSize(p.is_list ? p.count_type : p.type);
  }
  return bytes;
}

std::string elementNoun(const PlyElement& element) {
  if (element.name == "vertex") return "vertices";
  if (element.name == "face") return "faces";
  return "'" + element.name + "' elements";
}

bool isIntegral(double value) {
  return std::isfinite(value) && value == std::floor(value);
}

// Shortest text that reads back as `value` ("500", "2.5", "nan").
std::string numberText(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

// The last scalar property of `element` called `property_name`, or -1.
int scalarProperty(const PlyElement& element, const std::string& property_name) {
  int found = -1;
  for (int p = 0; p < static_cast<int>(element.properties.size()); ++p) {
    const PlyProperty& property = element.properties[p];
    if (!property.is_list && property.name == property_name) found = p;
  }
  return found;
}

// The first list property of `element` with one of `names`, or -1.
int listProperty(const PlyElement& element, std::initializer_list<const char*> names) {
  for (int p = 0; p < static_cast<int>(element.properties.size()); ++p) {
    const PlyProperty& property = element.properties[p];
    if (!property.is_list) continue;
    for (const char* n : names)
      if (property.name == n) return p;
  }
  return -1;
}

// One face record's polygon, once all its properties are read (texcoord may precede the
// indices): its corners, each with its own texture coordinate row, or the vertex's.
void addPlyFace(MeshBuilder& mesh, const std::vector<int>& vertices, const std::vector<double>& uvs,
                bool vertex_uvs) {
  // A list of another length is not MeshLab's: the face is read without texture coordinates.
  const bool per_corner = uvs.size() == 2 * vertices.size();
  mesh.beginPolygon();
  for (size_t c = 0; c < vertices.size(); ++c) {
    int texcoord = vertex_uvs ? vertices[c] : -1;
    if (per_corner) {
      texcoord = static_cast<int>(mesh.texcoordCount());
      mesh.addTexcoord(uvs[2 * c], uvs[2 * c + 1]);
    }
    mesh.addCorner(vertices[c], texcoord);
  }
  mesh.endPolygon();
}

// Stanford's tristrips: a strip's k-th triangle is (s[k], s[k+1], s[k+2]), its first two corners
// swapped when k is odd so every triangle keeps the strip's winding; -1 restarts a strip.
// Triangles with a repeated corner are the joins strippers use between strips: dropped, counted.
class StripTriangulator {
 public:
  // With per-vertex texture coordinates, a corner's texture coordinate row is its vertex.
  StripTriangulator(MeshBuilder& mesh, bool vertex_uvs) : mesh_(mesh), vertex_uvs_(vertex_uvs) {}

  void restart() { run_ = 0; }
  void add(int vertex) {
    window_[run_ % 3] = vertex;
    ++run_;
    if (run_ < 3) return;
    const long long k = run_ - 3;  // the triangle's index within the strip
    int a = window_[k % 3], b = window_[(k + 1) % 3];
    const int c = window_[(k + 2) % 3];
    if (k % 2 == 1) std::swap(a, b);
    if (a == b || b == c || a == c) {
      ++degenerate_;
      return;
    }
    mesh_.beginPolygon();
    for (int v : {a, b, c}) mesh_.addCorner(v, vertex_uvs_ ? v : -1);
    mesh_.endPolygon();
  }
  long long degenerate() const { return degenerate_; }

 private:
  MeshBuilder& mesh_;
  bool vertex_uvs_;
  int window_[3] = {0, 0, 0};
  long long run_ = 0;
  long long degenerate_ = 0;
};

}  // namespace

MeshData parsePly(std::string_view text, const std::string& name) {
  const PlyHeader header = parsePlyHeader(text, name);
  const std::string_view body = text.substr(header.body_offset);

  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  const PlyElement* strip_element = nullptr;  // laser scans' `tristrips`, read beside faces
  for (const PlyElement& element : header.elements) {
    const PlyElement** slot = element.name == "vertex"      ? &vertex_element
                              : element.name == "face"      ? &face_element
                              : element.name == "tristrips" ? &strip_element
                                                            : nullptr;
    if (slot == nullptr) continue;
    if (*slot != nullptr) fail(name, "header declares two '" + element.name + "' elements");
    *slot = &element;
  }
  if (vertex_element == nullptr) fail(name, "header declares no vertex element");
  const bool has_faces = face_element != nullptr && face_element->count > 0;
  const bool has_strips = strip_element != nullptr && strip_element->count > 0;
  if (!has_faces && !has_strips) fail(name, "contains no faces");
  const int strip_property =
      has_strips ? listProperty(*strip_element, {"vertex_indices", "vertex_index"}) : -1;
  if (has_strips && strip_property < 0) fail(name, "tristrips element has no vertex_indices list");

  int axis_property[3];
  for (int axis = 0; axis < 3; ++axis) {
    axis_property[axis] =
        scalarProperty(*vertex_element, std::string(1, static_cast<char>('x' + axis)));
    if (axis_property[axis] < 0) {
      fail(name,
           std::string("vertex element has no scalar property ") + static_cast<char>('x' + axis));
    }
  }
  const int index_property =
      has_faces ? listProperty(*face_element, {"vertex_indices", "vertex_index"}) : -1;
  if (has_faces && index_property < 0) fail(name, "face element has no vertex_indices list");
  // Texture coordinates: per corner in a face list `texcoord` (u0 v0 u1 v1 ..., as MeshLab
  // writes its wedge texture coordinates), else per vertex in scalar pairs (s t, u v,
  // texture_u texture_v).
  const int texcoord_property = has_faces ? listProperty(*face_element, {"texcoord"}) : -1;
  int vertex_uv_property[2] = {-1, -1};
  for (const auto& [u_name, v_name] :
       {std::pair<const char*, const char*>{"s", "t"}, {"u", "v"}, {"texture_u", "texture_v"}}) {
    if (texcoord_property >= 0) break;  // per-corner coordinates win over per-vertex ones
    const int u = scalarProperty(*vertex_element, u_name),
              v = scalarProperty(*vertex_element, v_name);
    if (u >= 0 && v >= 0) {
      vertex_uv_property[0] = u;
      vertex_uv_property[1] = v;
      break;
    }
  }
  const bool vertex_uvs = vertex_uv_property[0] >= 0;

  const long long vertex_count = vertex_element->count;
  MeshBuilder mesh;
  const auto reserveFor = [&](const PlyElement& element) {
    const size_t record = std::max<size_t>(1, minRecordBytes(element, header.format));
    return static_cast<size_t>(std::min<unsigned long long>(
        static_cast<unsigned long long>(element.count), body.size() / record + 1));
  };
  mesh.reserveVertices(reserveFor(*vertex_element));
  if (has_faces) mesh.reserveTriangles(reserveFor(*face_element));
  PlyValueSource source(body, header, name);
  StripTriangulator strips(mesh, vertex_uvs);
  std::vector<int> corner_vertices;  // the current face's, in its record
  std::vector<double> corner_uvs;
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;
    const bool is_vertex = &element == vertex_element;
    const bool is_face = &element == face_element;
    const bool is_strip = &element == strip_element;
    for (long long r = 0; r < element.count; ++r) {
      const auto truncated = [&] {
        fail(name, "file ends after " + std::to_string(r) + " of " + std::to_string(element.count) +
                       " " + elementNoun(element));
      };
      double xyz[3] = {0, 0, 0};
      double vertex_uv[2] = {0, 0};
      corner_vertices.clear();
      corner_uvs.clear();
      for (int p = 0; p < static_cast<int>(element.properties.size()); ++p) {
        const PlyProperty& property = element.properties[p];
        double value = 0;
        if (!property.is_list) {
          if (!source.read(property.type, value)) truncated();
          if (is_vertex) {
            for (int axis = 0; axis < 3; ++axis) {
              if (axis_property[axis] == p) xyz[axis] = value;
            }
            for (int axis = 0; axis < 2; ++axis) {
              if (vertex_uv_property[axis] == p) vertex_uv[axis] = value;
            }
          }
          continue;
        }
        double length = 0;
        if (!source.read(property.count_type, length)) truncated();
        if (!isIntegral(length) || length < 0) {
          fail(name, "list length " + numberText(length) + " in " + element.name + " " +
                         std::to_string(r) + " is not a non-negative integer");
        }
        const auto item_count = static_cast<unsigned long long>(length);
        if (is_face && p == texcoord_property) {
          for (unsigned long long c = 0; c < item_count; ++c) {
            if (!source.read(property.type, value)) truncated();
            corner_uvs.push_back(value);
          }
          continue;
        }
        if (is_strip && p == strip_property) {
          strips.restart();
          for (unsigned long long c = 0; c < item_count; ++c) {
            if (!source.read(property.type, value)) truncated();
            if (value == -1) {
              strips.restart();
              continue;
            }
            if (!isIntegral(value) || value < 0 || value >= static_cast<double>(vertex_count) ||
                value > INT_MAX) {
              fail(name, "tristrip " + std::to_string(r) + " refers to vertex " +
                             numberText(value) + ", but there are " + std::to_string(vertex_count) +
                             " vertices");
            }
            strips.add(static_cast<int>(value));
          }
          continue;
        }
        if (!(is_face && p == index_property)) {
          if (!source.skip(property.type, item_count)) truncated();
          continue;
        }
        const std::string face = "face " + std::to_string(r);
        if (item_count < 3) {
          fail(name, face + " has " + std::to_string(item_count) + " vertices, at least 3 needed");
        }
        for (unsigned long long c = 0; c < item_count; ++c) {
          if (!source.read(property.type, value)) truncated();
          if (!isIntegral(value) || value < 0 || value >= static_cast<double>(vertex_count) ||
              value > INT_MAX) {
            fail(name, face + " refers to vertex " + numberText(value) + ", but there are " +
                           std::to_string(vertex_count) + " vertices");
          }
          corner_vertices.push_back(static_cast<int>(value));
        }
      }
      if (is_vertex) {
        mesh.addVertex(xyz[0], xyz[1], xyz[2]);
        if (vertex_uvs) mesh.addTexcoord(vertex_uv[0], vertex_uv[1]);
      }
      if (is_face) addPlyFace(mesh, corner_vertices, corner_uvs, vertex_uvs);
    }
  }
  MeshData data = mesh.build(name);
  if (strips.degenerate() > 0) {
    data.notes.push_back(std::to_string(strips.degenerate()) +
                         " degenerate tristrip triangles (the joins between strips) were dropped");
  }
  return data;
}

}  // namespace detail

void writePly(const std::string& path, const Positions& V, const Triangles& F,
              const Layout& layout) {
  detail::checkMeshForWriting(path, V, F, layout);
  detail::AtomicFile ply(path);
  detail::ChunkedWriter out(ply.stream());
  std::string& data = out.buffer();
  data += "ply\nformat binary_little_endian 1.0\ncomment written by straightest_param\n";
  data += "element vertex " + std::to_string(V.rows()) + "\n";
  // Positions in double (a scan far from the origin keeps its digits); texture coordinates in
  // float, the only type MeshLab's PLY reader takes for them.
  data += "property double x\nproperty double y\nproperty double z\n";
  data += "element face " + std::to_string(F.rows()) + "\n";
  data += "property list uchar int vertex_indices\nproperty list uchar float texcoord\n";
  // An atlas's chart per face (MeshLab reads it as the per-face attribute `chart`).
  const bool charts = static_cast<Eigen::Index>(layout.chart.size()) == F.rows();
  if (charts) data += "property int chart\n";
  data += "end_header\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    for (int axis = 0; axis < 3; ++axis) detail::putDouble(data, V(i, axis));
    out.maybeFlush();
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    data.push_back(3);
    for (int c = 0; c < 3; ++c) detail::putLittleEndian32(data, static_cast<uint32_t>(F(f, c)));
    data.push_back(6);
    for (int c = 0; c < 3; ++c) {
      detail::putFloat(data, layout.uv(layout.face_uv(f, c), 0));
      detail::putFloat(data, layout.uv(layout.face_uv(f, c), 1));
    }
    if (charts) detail::putLittleEndian32(data, static_cast<uint32_t>(layout.chart[f]));
    out.maybeFlush();
  }
  out.flush();
  ply.commit();
}

}  // namespace sdp::io
