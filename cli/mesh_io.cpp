#include "mesh_io.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>
#include <system_error>

namespace sdp::io {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw ParameterizationError(name + ": " + what);
}

std::string lineAt(int line) {
  return "line " + std::to_string(line) + ": ";
}

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string fileNameOf(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  return name.empty() ? path : name;
}

// Quotes a token for an error message, shortened so the reason stays one readable line.
std::string quoted(std::string_view token) {
  std::string shown(token.substr(0, 40));
  for (char& c : shown) {
    if (!std::isprint(static_cast<unsigned char>(c))) c = '?';
  }
  return "'" + shown + (token.size() > 40 ? "...'" : "'");
}

// ---------------------------------------------------------------------------------------------
// Text scanning

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Splits one line into whitespace-separated tokens.
class LineTokens {
 public:
  LineTokens() = default;
  explicit LineTokens(std::string_view line) : rest_(line) {}

  bool next(std::string_view& token) {
    size_t begin = 0;
    while (begin < rest_.size() && isBlank(rest_[begin])) ++begin;
    if (begin == rest_.size()) {
      rest_ = {};
      return false;
    }
    size_t end = begin;
    while (end < rest_.size() && !isBlank(rest_[end])) ++end;
    token = rest_.substr(begin, end - begin);
    rest_ = rest_.substr(end);
    return true;
  }

 private:
  std::string_view rest_;
};

// Hands out lines with their 1-based numbers; optionally drops '#' comments (OFF, OBJ).
class LineReader {
 public:
  LineReader(std::string_view text, bool strip_comments)
      : text_(text), strip_comments_(strip_comments) {}

  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const size_t end = std::min(text_.find('\n', pos_), text_.size());
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    if (strip_comments_) line = line.substr(0, line.find('#'));
    return true;
  }

  // Skips lines that are empty once comments are removed.
  bool nextContent(std::string_view& line) {
    while (next(line)) {
      if (hasToken(line)) return true;
    }
    return false;
  }

  // Whether anything but blanks and comments follows the current line.
  bool hasMoreContent() const {
    LineReader ahead = *this;
    std::string_view line;
    return ahead.nextContent(line);
  }

  int line() const { return line_; }
  size_t remainingBytes() const { return pos_ >= text_.size() ? 0 : text_.size() - pos_; }

 private:
  static bool hasToken(std::string_view line) {
    return std::any_of(line.begin(), line.end(), [](char c) { return !isBlank(c); });
  }

  std::string_view text_;
  bool strip_comments_;
  size_t pos_ = 0;
  int line_ = 0;
};

// Tokens across line breaks (ASCII PLY bodies).
class TokenStream {
 public:
  explicit TokenStream(std::string_view text, int first_line)
      : lines_(text, false), first_line_(first_line) {}

  bool next(std::string_view& token) {
    while (!tokens_.next(token)) {
      std::string_view line;
      if (!lines_.next(line)) return false;
      tokens_ = LineTokens(line);
    }
    return true;
  }

  int line() const { return first_line_ + lines_.line(); }

 private:
  LineReader lines_;
  LineTokens tokens_;
  int first_line_;
};

// Locale-independent; accepts a leading '+', "nan" and "inf" (read as-is, the core rejects them).
bool parseDouble(std::string_view token, double& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') {
    token.remove_prefix(1);
  }
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ptr != end || token.empty()) return false;
  if (ec == std::errc::result_out_of_range) {
    // Beyond double range: let strtod pick +-HUGE_VAL or the underflowed value.
    const std::string copy(token);
    value = std::strtod(copy.c_str(), nullptr);
    return true;
  }
  return ec == std::errc();
}

bool parseInteger(std::string_view token, long long& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') {
    token.remove_prefix(1);
  }
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end && !token.empty();
}

// ---------------------------------------------------------------------------------------------
// Mesh assembly shared by the readers

class MeshBuilder {
 public:
  void reserveVertices(size_t n) { coords_.reserve(3 * n); }
  void reserveTriangles(size_t n) { corners_.reserve(3 * n); }

  void addVertex(double x, double y, double z) {
    coords_.push_back(x);
    coords_.push_back(y);
    coords_.push_back(z);
  }
  size_t vertexCount() const { return coords_.size() / 3; }

  // Fan triangulation: corners arrive one by one, a triangle per corner from the third on.
  void beginPolygon() { polygon_corners_ = 0; }
  void addCorner(int v) {
    if (polygon_corners_ == 0) {
      first_ = v;
    } else if (polygon_corners_ >= 2) {
      corners_.push_back(first_);
      corners_.push_back(previous_);
      corners_.push_back(v);
    }
    previous_ = v;
    ++polygon_corners_;
  }
  void endPolygon() {
    if (polygon_corners_ > 3) ++polygons_triangulated_;
  }
  size_t triangleCount() const { return corners_.size() / 3; }

  MeshData build(const std::string& name) const {
    if (corners_.empty()) fail(name, "contains no faces");
    if (vertexCount() > static_cast<size_t>(INT_MAX) ||
        triangleCount() > static_cast<size_t>(INT_MAX)) {
      fail(name, "too many vertices or faces (more than 2^31)");
    }
    MeshData mesh;
    mesh.V.resize(static_cast<Eigen::Index>(vertexCount()), 3);
    std::copy(coords_.begin(), coords_.end(), mesh.V.data());
    mesh.F.resize(static_cast<Eigen::Index>(triangleCount()), 3);
    std::copy(corners_.begin(), corners_.end(), mesh.F.data());
    mesh.polygons_triangulated = polygons_triangulated_;
    return mesh;
  }

 private:
  std::vector<double> coords_;
  std::vector<int> corners_;
  int polygon_corners_ = 0;
  int first_ = 0;
  int previous_ = 0;
  int polygons_triangulated_ = 0;
};

// ---------------------------------------------------------------------------------------------
// OFF

// Header counts are claims, not facts: memory is reserved for at most as many items as the
// remaining bytes could hold (smallest lines "0 0 0\n" and "3 0 1 2\n"), and reading simply
// runs out, with "file ends after k of n", when the claim is false.
constexpr size_t kMinOffVertexBytes = 6;
constexpr size_t kMinOffFaceBytes = 8;

size_t plausibleCount(long long claimed, size_t remaining_bytes, size_t min_bytes_each) {
  const size_t possible = remaining_bytes / min_bytes_each + 1;
  return claimed < 0 ? 0 : std::min(static_cast<size_t>(claimed), possible);
}

// "OFF" with the optional prefixes of the Geomview format: ST (texture), C (color), N (normal),
// 4 (homogeneous), n (dimension given next).
bool isOffKeyword(std::string_view token) {
  if (token.size() < 3 || token.substr(token.size() - 3) != "OFF") return false;
  std::string_view prefix = token.substr(0, token.size() - 3);
  for (std::string_view part : {"ST", "C", "N", "4", "n"}) {
    if (prefix.substr(0, part.size()) == part) prefix.remove_prefix(part.size());
  }
  return prefix.empty();
}

MeshData parseOff(std::string_view text, const std::string& name) {
  LineReader lines(text, true);
  std::string_view line;
  if (!lines.nextContent(line)) fail(name, "file is empty");

  // Header: optional keyword, then "vertices faces [edges]", possibly on the keyword's line.
  LineTokens tokens(line);
  std::string_view token;
  tokens.next(token);
  std::vector<std::string_view> counts;
  if (isOffKeyword(token)) {
    if (token.find('4') != std::string_view::npos) fail(name, "4D OFF files are not supported");
    const bool dimension_follows = token.find('n') != std::string_view::npos;
    std::string_view rest;
    if (tokens.next(rest)) {
      if (rest == "BINARY") fail(name, "binary OFF files are not supported");
      counts.push_back(rest);
    }
    if (dimension_follows) {
      // nOFF: the dimension precedes the counts.
      if (counts.empty()) {
        if (!lines.nextContent(line)) fail(name, "file ends in the header");
        tokens = LineTokens(line);
        tokens.next(rest);
        counts.push_back(rest);
      }
      long long dimension = 0;
      if (!parseInteger(counts[0], dimension) || dimension != 3) {
        fail(name, lineAt(lines.line()) + "only 3D nOFF files are supported, dimension is " +
                       quoted(counts[0]));
      }
      counts.clear();
    }
  } else {
    counts.push_back(token);
  }
  while (counts.size() < 2) {
    while (counts.size() < 2 && tokens.next(token)) counts.push_back(token);
    if (counts.size() < 2) {
      if (!lines.nextContent(line)) fail(name, "file ends in the header (no vertex/face counts)");
      tokens = LineTokens(line);
    }
  }
  long long vertex_count = 0, face_count = 0;
  if (!parseInteger(counts[0], vertex_count)) {
    fail(name, lineAt(lines.line()) + "cannot read vertex count " + quoted(counts[0]));
  }
  if (!parseInteger(counts[1], face_count)) {
    fail(name, lineAt(lines.line()) + "cannot read face count " + quoted(counts[1]));
  }
  // The rest of the counts line (edge count) is ignored.

  if (vertex_count < 0) fail(name, "negative vertex count " + std::to_string(vertex_count));
  if (face_count < 0) fail(name, "negative face count " + std::to_string(face_count));

  MeshBuilder mesh;
  mesh.reserveVertices(plausibleCount(vertex_count, lines.remainingBytes(), kMinOffVertexBytes));
  const std::string vertex_total = std::to_string(vertex_count);
  for (long long k = 0; k < vertex_count; ++k) {
    if (!lines.nextContent(line)) {
      fail(name, "file ends after " + std::to_string(k) + " of " + vertex_total + " vertices");
    }
    tokens = LineTokens(line);
    double xyz[3];
    for (int axis = 0; axis < 3; ++axis) {
      if (!tokens.next(token)) {
        if (!lines.hasMoreContent()) {
          fail(name, "file ends after " + std::to_string(k) + " of " + vertex_total + " vertices");
        }
        fail(name, lineAt(lines.line()) + "vertex " + std::to_string(k) + " has " +
                       std::to_string(axis) + " coordinates, 3 needed");
      }
      if (!parseDouble(token, xyz[axis])) {
        fail(name, lineAt(lines.line()) + "cannot read " + quoted(token) + " as a number");
      }
    }
    mesh.addVertex(xyz[0], xyz[1], xyz[2]);
  }

  mesh.reserveTriangles(plausibleCount(face_count, lines.remainingBytes(), kMinOffFaceBytes));
  const std::string face_total = std::to_string(face_count);
  for (long long f = 0; f < face_count; ++f) {
    const std::string face = "face " + std::to_string(f);
    if (!lines.nextContent(line)) {
      fail(name, "file ends after " + std::to_string(f) + " of " + face_total + " faces");
    }
    tokens = LineTokens(line);
    tokens.next(token);
    long long corner_count = 0;
    if (!parseInteger(token, corner_count)) {
      fail(name, lineAt(lines.line()) + "cannot read " + quoted(token) + " as a corner count");
    }
    if (corner_count < 3) {
      fail(name, lineAt(lines.line()) + face + " has " + std::to_string(corner_count) +
                     " vertices, at least 3 needed");
    }
    mesh.beginPolygon();
    for (long long c = 0; c < corner_count; ++c) {
      if (!tokens.next(token)) {
        if (!lines.hasMoreContent()) {
          fail(name, "file ends after " + std::to_string(f) + " of " + face_total + " faces");
        }
        fail(name, lineAt(lines.line()) + face + " lists " + std::to_string(corner_count) +
                       " vertices but gives " + std::to_string(c));
      }
      long long index = 0;
      if (!parseInteger(token, index)) {
        fail(name, lineAt(lines.line()) + "cannot read " + quoted(token) + " as a vertex index");
      }
      if (index < 0 || index >= vertex_count || index > INT_MAX) {
        fail(name, lineAt(lines.line()) + face + " refers to vertex " + std::to_string(index) +
                       ", but there are " + vertex_total + " vertices");
      }
      mesh.addCorner(static_cast<int>(index));
    }
    mesh.endPolygon();
  }
  return mesh.build(name);
}

// ---------------------------------------------------------------------------------------------
// OBJ

MeshData parseObj(std::string_view text, const std::string& name) {
  LineReader lines(text, true);
  MeshBuilder mesh;
  std::string_view line, token;
  long long largest_index = -1;  // largest 0-based forward reference, checked at the end
  int largest_index_line = 0;
  while (lines.nextContent(line)) {
    LineTokens tokens(line);
    tokens.next(token);
    if (token == "v") {
      double xyz[3];
      for (int axis = 0; axis < 3; ++axis) {
        if (!tokens.next(token)) {
          fail(name, lineAt(lines.line()) + "vertex has " + std::to_string(axis) +
                         " coordinates, 3 needed");
        }
        if (!parseDouble(token, xyz[axis])) {
          fail(name, lineAt(lines.line()) + "cannot read " + quoted(token) + " as a number");
        }
      }
      mesh.addVertex(xyz[0], xyz[1], xyz[2]);
    } else if (token == "f") {
      const long long defined = static_cast<long long>(mesh.vertexCount());
      int corners = 0;
      mesh.beginPolygon();
      while (tokens.next(token)) {
        // "v", "v/vt", "v/vt/vn" or "v//vn": only the position index matters here.
        const std::string_view position = token.substr(0, token.find('/'));
        long long index = 0;
        if (!parseInteger(position, index)) {
          fail(name, lineAt(lines.line()) + "cannot read " + quoted(token) + " as a face corner");
        }
        if (index == 0) fail(name, lineAt(lines.line()) + "vertex index 0 (OBJ counts from 1)");
        if (index < 0) {
          // Relative to the vertices defined so far: -1 is the last one.
          if (-index > defined) {
            fail(name, lineAt(lines.line()) + "relative index " + std::to_string(index) +
                           " reaches before the first vertex");
          }
          index += defined;
        } else {
          index -= 1;
          if (index > largest_index) {
            largest_index = index;
            largest_index_line = lines.line();
          }
        }
        if (index > INT_MAX) {
          fail(name, lineAt(lines.line()) + "vertex index " + quoted(position) + " is too large");
        }
        mesh.addCorner(static_cast<int>(index));
        ++corners;
      }
      if (corners < 3) {
        fail(name, lineAt(lines.line()) + "face has " + std::to_string(corners) +
                       " vertices, at least 3 needed");
      }
      mesh.endPolygon();
    }
    // vt, vn, g, o, s, usemtl, mtllib, l, p, ...: nothing to do for a parameterization.
  }
  if (largest_index >= static_cast<long long>(mesh.vertexCount())) {
    fail(name, lineAt(largest_index_line) + "face refers to vertex " +
                   std::to_string(largest_index + 1) + ", but the file has " +
                   std::to_string(mesh.vertexCount()) + " vertices");
  }
  return mesh.build(name);
}

// ---------------------------------------------------------------------------------------------
// PLY

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

MeshData parsePly(std::string_view text, const std::string& name) {
  const PlyHeader header = parsePlyHeader(text, name);
  const std::string_view body = text.substr(header.body_offset);

  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  for (const PlyElement& element : header.elements) {
    const PlyElement** slot = element.name == "vertex" ? &vertex_element
                              : element.name == "face" ? &face_element
                                                       : nullptr;
    if (slot == nullptr) continue;
    if (*slot != nullptr) fail(name, "header declares two '" + element.name + "' elements");
    *slot = &element;
  }
  if (vertex_element == nullptr) fail(name, "header declares no vertex element");
  if (face_element == nullptr || face_element->count == 0) fail(name, "contains no faces");

  int axis_property[3] = {-1, -1, -1};
  for (int p = 0; p < static_cast<int>(vertex_element->properties.size()); ++p) {
    const PlyProperty& property = vertex_element->properties[p];
    for (int axis = 0; axis < 3; ++axis) {
      if (property.name == std::string(1, static_cast<char>('x' + axis)) && !property.is_list) {
        axis_property[axis] = p;
      }
    }
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (axis_property[axis] < 0) {
      fail(name,
           std::string("vertex element has no scalar property ") + static_cast<char>('x' + axis));
    }
  }
  int index_property = -1;
  for (int p = 0; p < static_cast<int>(face_element->properties.size()); ++p) {
    const PlyProperty& property = face_element->properties[p];
    if (property.is_list &&
        (property.name == "vertex_indices" || property.name == "vertex_index")) {
      index_property = p;
      break;
    }
  }
  if (index_property < 0) fail(name, "face element has no vertex_indices list");

  const long long vertex_count = vertex_element->count;
  MeshBuilder mesh;
  const auto reserveFor = [&](const PlyElement& element) {
    const size_t record = std::max<size_t>(1, minRecordBytes(element, header.format));
    return static_cast<size_t>(std::min<unsigned long long>(
        static_cast<unsigned long long>(element.count), body.size() / record + 1));
  };
  mesh.reserveVertices(reserveFor(*vertex_element));
  mesh.reserveTriangles(reserveFor(*face_element));
  PlyValueSource source(body, header, name);
  for (const PlyElement& element : header.elements) {
    if (element.properties.empty()) continue;
    const bool is_vertex = &element == vertex_element;
    const bool is_face = &element == face_element;
    for (long long r = 0; r < element.count; ++r) {
      const auto truncated = [&] {
        fail(name, "file ends after " + std::to_string(r) + " of " + std::to_string(element.count) +
                       " " + elementNoun(element));
      };
      double xyz[3] = {0, 0, 0};
      for (int p = 0; p < static_cast<int>(element.properties.size()); ++p) {
        const PlyProperty& property = element.properties[p];
        double value = 0;
        if (!property.is_list) {
          if (!source.read(property.type, value)) truncated();
          if (is_vertex) {
            for (int axis = 0; axis < 3; ++axis) {
              if (axis_property[axis] == p) xyz[axis] = value;
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
        if (!(is_face && p == index_property)) {
          if (!source.skip(property.type, item_count)) truncated();
          continue;
        }
        const std::string face = "face " + std::to_string(r);
        if (item_count < 3) {
          fail(name, face + " has " + std::to_string(item_count) + " vertices, at least 3 needed");
        }
        mesh.beginPolygon();
        for (unsigned long long c = 0; c < item_count; ++c) {
          if (!source.read(property.type, value)) truncated();
          if (!isIntegral(value) || value < 0 || value >= static_cast<double>(vertex_count) ||
              value > INT_MAX) {
            fail(name, face + " refers to vertex " + numberText(value) + ", but there are " +
                           std::to_string(vertex_count) + " vertices");
          }
          mesh.addCorner(static_cast<int>(value));
        }
        mesh.endPolygon();
      }
      if (is_vertex) mesh.addVertex(xyz[0], xyz[1], xyz[2]);
    }
  }
  return mesh.build(name);
}

MeshData parseMesh(std::string_view bytes, const std::string& format, const std::string& name) {
  if (format == "off") return parseOff(bytes, name);
  if (format == "obj") return parseObj(bytes, name);
  if (format == "ply") return parsePly(bytes, name);
  fail(name, "unsupported mesh format '" + format + "' (expected .off, .obj or .ply)");
}

std::string extensionOf(const std::string& path) {
  std::string ext = lowercase(fs::path(path).extension().string());
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  return ext;
}

// ---------------------------------------------------------------------------------------------
// Writing

// A temporary file beside the target, renamed over it on commit() and removed otherwise, so
// a failed write never leaves a partial output under the target's name.
class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path) : path_(path) {
    static std::atomic<unsigned> counter{0};
    const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
    for (int attempt = 0; attempt < 100 && temp_.empty(); ++attempt) {
      const std::string candidate =
          path + ".tmp" + std::to_string(ticks % 1000000) + "_" + std::to_string(counter++);
      std::error_code ec;
      if (!fs::exists(candidate, ec)) temp_ = candidate;
    }
    if (temp_.empty()) throw ParameterizationError("cannot write " + path + ": no temporary name");
    errno = 0;
    stream_.open(temp_, std::ios::out | std::ios::binary | std::ios::trunc);
    if (!stream_) {
      const std::string reason = errno != 0 ? std::strerror(errno) : "cannot create file";
      temp_.clear();
      throw ParameterizationError("cannot write " + path + ": " + reason);
    }
  }
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  ~AtomicFile() {
    if (temp_.empty()) return;
    stream_.close();
    std::error_code ec;
    fs::remove(temp_, ec);
  }

  std::ofstream& stream() { return stream_; }

  void commit() {
    stream_.flush();
    const bool written = static_cast<bool>(stream_);
    stream_.close();
    if (!written || stream_.fail()) {
      throw ParameterizationError("cannot write " + path_ + ": write failed (disk full?)");
    }
    std::error_code ec;
    fs::rename(temp_, path_, ec);
    if (ec) throw ParameterizationError("cannot write " + path_ + ": " + ec.message());
    temp_.clear();
  }

 private:
  std::string path_;
  std::string temp_;
  std::ofstream stream_;
};

void appendNumber(std::string& out, double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void appendNumber(std::string& out, long long value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// Writes bigger text files in chunks without holding the whole file in memory.
class ChunkedWriter {
 public:
  explicit ChunkedWriter(std::ostream& out) : out_(out) {}
  ~ChunkedWriter() = default;
  std::string& buffer() { return buffer_; }
  void maybeFlush() {
    if (buffer_.size() > (1u << 20)) flush();
  }
  void flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  std::ostream& out_;
  std::string buffer_;
};

void checkMeshForWriting(const std::string& path, const Positions& V, const Triangles& F,
                         const Layout& layout) {
  if (layout.face_uv.rows() != F.rows()) {
    throw ParameterizationError("cannot write " + path + ": texture corners for " +
                                std::to_string(layout.face_uv.rows()) + " faces, the mesh has " +
                                std::to_string(F.rows()));
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (F(f, c) < 0 || F(f, c) >= V.rows()) {
        throw ParameterizationError("cannot write " + path + ": face " + std::to_string(f) +
                                    " refers to a missing vertex");
      }
      if (layout.face_uv(f, c) < 0 || layout.face_uv(f, c) >= layout.uv.rows()) {
        throw ParameterizationError("cannot write " + path + ": face " + std::to_string(f) +
                                    " refers to a missing texture coordinate");
      }
    }
  }
}

void putLittleEndian32(std::string& out, uint32_t bits) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
}

void putFloat(std::string& out, double value) {
  const float f = static_cast<float>(value);
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  putLittleEndian32(out, bits);
}

void putDouble(std::string& out, double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  for (int b = 0; b < 8; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xff));
}

void putBigEndian32(std::string& out, uint32_t value) {
  for (int b = 3; b >= 0; --b) out.push_back(static_cast<char>((value >> (8 * b)) & 0xff));
}

void appendPngChunk(std::string& png, const char type[4], const std::string& data) {
  putBigEndian32(png, static_cast<uint32_t>(data.size()));
  const size_t type_offset = png.size();
  png.append(type, 4);
  png += data;
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32(crc, reinterpret_cast<const Bytef*>(png.data() + type_offset),
              static_cast<uInt>(4 + data.size()));
  putBigEndian32(png, static_cast<uint32_t>(crc));
}

}  // namespace

// -----------------------------------------------------------------------------------------------

bool isReadableMeshPath(const std::string& path) {
  const std::string ext = extensionOf(path);
  return ext == "off" || ext == "obj" || ext == "ply";
}

MeshData readMesh(const std::string& path) {
  const std::string name = fileNameOf(path);
  if (!isReadableMeshPath(path)) {
    fail(name, "unsupported mesh format (expected .off, .obj or .ply)");
  }
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) {
    throw ParameterizationError("cannot open " + path + ": no such file");
  }
  if (!fs::is_regular_file(status)) {
    throw ParameterizationError("cannot open " + path + ": not a regular file");
  }
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const std::string reason = errno != 0 ? std::strerror(errno) : "cannot open file";
    throw ParameterizationError("cannot open " + path + ": " + reason);
  }
  std::string bytes;
  {
    // Read in blocks rather than trusting the reported size.
    char block[1 << 16];
    while (in.read(block, sizeof block) || in.gcount() > 0) {
      bytes.append(block, static_cast<size_t>(in.gcount()));
    }
    if (in.bad()) throw ParameterizationError("cannot read " + path + ": I/O error");
  }
  return parseMesh(bytes, extensionOf(path), name);
}

MeshData readMeshFromMemory(const std::string& bytes, const std::string& format) {
  std::string ext = lowercase(format);
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  return parseMesh(bytes, ext, "<memory>." + ext);
}

void writeObjWithTexture(const std::string& path, const Positions& V, const Triangles& F,
                         const Layout& layout, const std::string& texture_png_filename) {
  checkMeshForWriting(path, V, F, layout);
  const UVs& uv = layout.uv;
  const fs::path obj_path(path);
  const fs::path mtl_path = fs::path(obj_path).replace_extension(".mtl");
  const std::string mtl_name = mtl_path.filename().string();
  const char* const kMaterial = "checker";

  AtomicFile mtl(mtl_path.string());
  mtl.stream() << "# written by straightest_param\n"
               << "newmtl " << kMaterial << "\n"
               << "Ka 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\n"
               << "map_Kd " << texture_png_filename << "\n";

  AtomicFile obj(path);
  ChunkedWriter out(obj.stream());
  std::string& text = out.buffer();
  text += "# written by straightest_param\nmtllib " + mtl_name + "\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    text += "v ";
    appendNumber(text, V(i, 0));
    text += ' ';
    appendNumber(text, V(i, 1));
    text += ' ';
    appendNumber(text, V(i, 2));
    text += '\n';
    out.maybeFlush();
  }
  for (Eigen::Index i = 0; i < uv.rows(); ++i) {
    text += "vt ";
    appendNumber(text, uv(i, 0));
    text += ' ';
    appendNumber(text, uv(i, 1));
    text += '\n';
    out.maybeFlush();
  }
  text += "usemtl ";
  text += kMaterial;
  text += '\n';
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    text += 'f';
    for (int c = 0; c < 3; ++c) {
      // Each corner is "v/vt" (1-based): its vertex and its row of the layout.
      text += ' ';
      appendNumber(text, static_cast<long long>(F(f, c)) + 1);
      text += '/';
      appendNumber(text, static_cast<long long>(layout.face_uv(f, c)) + 1);
    }
    text += '\n';
    out.maybeFlush();
  }
  out.flush();

  mtl.commit();
  try {
    obj.commit();
  } catch (...) {
    std::error_code ec;
    fs::remove(mtl_path, ec);
    throw;
  }
}

void writePly(const std::string& path, const Positions& V, const Triangles& F,
              const Layout& layout) {
  checkMeshForWriting(path, V, F, layout);
  AtomicFile ply(path);
  ChunkedWriter out(ply.stream());
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
    for (int axis = 0; axis < 3; ++axis) putDouble(data, V(i, axis));
    out.maybeFlush();
  }
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    data.push_back(3);
    for (int c = 0; c < 3; ++c) putLittleEndian32(data, static_cast<uint32_t>(F(f, c)));
    data.push_back(6);
    for (int c = 0; c < 3; ++c) {
      putFloat(data, layout.uv(layout.face_uv(f, c), 0));
      putFloat(data, layout.uv(layout.face_uv(f, c), 1));
    }
    if (charts) putLittleEndian32(data, static_cast<uint32_t>(layout.chart[f]));
    out.maybeFlush();
  }
  out.flush();
  ply.commit();
}

void writePng(const std::string& path, int width, int height,
              const std::vector<unsigned char>& rgb) {
  if (width <= 0 || height <= 0 || width > (1 << 16) || height > (1 << 16)) {
    throw ParameterizationError("cannot write " + path + ": bad image size " +
                                std::to_string(width) + "x" + std::to_string(height));
  }
  const size_t row_bytes = static_cast<size_t>(width) * 3;
  if (rgb.size() != row_bytes * static_cast<size_t>(height)) {
    throw ParameterizationError("cannot write " + path + ": pixel buffer has the wrong size");
  }
  // Each scanline is preceded by its filter type; 0 (none) keeps the encoder trivial.
  std::string raw;
  raw.reserve((row_bytes + 1) * static_cast<size_t>(height));
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    raw.append(reinterpret_cast<const char*>(rgb.data()) + y * row_bytes, row_bytes);
  }
  uLongf compressed_size = compressBound(static_cast<uLong>(raw.size()));
  std::string compressed(compressed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(compressed.data()), &compressed_size,
                reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()),
                Z_DEFAULT_COMPRESSION) != Z_OK) {
    throw ParameterizationError("cannot write " + path + ": zlib compression failed");
  }
  compressed.resize(compressed_size);

  std::string header;
  putBigEndian32(header, static_cast<uint32_t>(width));
  putBigEndian32(header, static_cast<uint32_t>(height));
  header +=
      std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, no filter, no interlace

  std::string png("\x89PNG\r\n\x1a\n", 8);
  appendPngChunk(png, "IHDR", header);
  appendPngChunk(png, "IDAT", compressed);
  appendPngChunk(png, "IEND", std::string());

  AtomicFile file(path);
  file.stream().write(png.data(), static_cast<std::streamsize>(png.size()));
  file.commit();
}

void writeTextFile(const std::string& path, const std::string& text) {
  AtomicFile file(path);
  file.stream().write(text.data(), static_cast<std::streamsize>(text.size()));
  file.commit();
}

}  // namespace sdp::io
