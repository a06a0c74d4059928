// STL in, binary and ASCII. STL stores each triangle with its own three corners, so the reader
// welds corners whose coordinates are exactly equal (as MeshLab's import does with "Unify
// Duplicated Vertices") into one vertex, numbered in the order the file first names them.
// Triangles that lose a corner to the weld (two equal corners) are dropped and counted.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>

#include "io/scan.h"

namespace sdp::io::detail {
namespace {

constexpr size_t kBinaryHeaderBytes = 80;
constexpr size_t kBinaryTriangleBytes = 50;  // normal, 3 corners (12 floats), 2 attribute bytes
// The smallest ASCII facet: "facet\nouter loop\nvertex 0 0 0\n" x3 "endloop\nendfacet\n".
constexpr size_t kMinAsciiFacetBytes = 60;

// Welds corners by their exact coordinates; -0 and +0 are one value.
class CornerWelder {
 public:
  explicit CornerWelder(MeshBuilder& mesh) : mesh_(mesh) {}

  int vertexOf(double x, double y, double z) {
    Key key{bitsOf(x), bitsOf(y), bitsOf(z)};
    const auto [it, inserted] = index_.try_emplace(key, static_cast<int>(mesh_.vertexCount()));
    if (inserted) mesh_.addVertex(x, y, z);
    return it->second;
  }

  void reserve(size_t corners) { index_.reserve(corners / 4); }

 private:
  struct Key {
    uint64_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
      h ^= (k.y + 0x632BE59BD9B4E019ull + (h << 6) + (h >> 2));
      h ^= (k.z + 0x85EBCA77C2B2AE63ull + (h << 6) + (h >> 2));
      return static_cast<size_t>(h ^ (h >> 31));
    }
  };
  static uint64_t bitsOf(double value) {
    if (value == 0) value = 0;  // -0 welds with +0
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return bits;
  }

  MeshBuilder& mesh_;
  std::unordered_map<Key, int, KeyHash> index_;
};

// Adds one welded polygon; false (nothing added) when two of its corners weld together.
bool addWeldedPolygon(MeshBuilder& mesh, const int* corners, size_t count) {
  for (size_t a = 0; a < count; ++a) {
    for (size_t b = a + 1; b < count; ++b) {
      if (corners[a] == corners[b]) return false;
    }
  }
  mesh.beginPolygon();
  for (size_t c = 0; c < count; ++c) mesh.addCorner(corners[c]);
  mesh.endPolygon();
  return true;
}

float readFloat32(const char* p) {
  uint32_t bits = 0;
  for (int b = 0; b < 4; ++b)
    bits |= static_cast<uint32_t>(static_cast<unsigned char>(p[b])) << (8 * b);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

uint32_t binaryTriangleCount(std::string_view bytes) {
  uint32_t count = 0;
  for (int b = 0; b < 4; ++b) {
    count |= static_cast<uint32_t>(static_cast<unsigned char>(bytes[kBinaryHeaderBytes + b]))
             << (8 * b);
  }
  return count;
}

// A file is binary when its size is exactly what its triangle count says; otherwise it is ASCII
// when it starts with "solid" (binary writers put "solid" in the header too, hence the size test).
bool isBinaryStl(std::string_view bytes) {
  if (bytes.size() >= kBinaryHeaderBytes + 4) {
    const uint64_t expected =
        kBinaryHeaderBytes + 4 + uint64_t{kBinaryTriangleBytes} * binaryTriangleCount(bytes);
    if (expected == bytes.size()) return true;
  }
  LineReader lines(bytes.substr(0, std::min<size_t>(bytes.size(), 256)), false);
  std::string_view line, first;
  return !(lines.nextContent(line) && LineTokens(line).next(first) && first == "solid");
}

void dropNote(MeshData& mesh, size_t dropped) {
  if (dropped == 0) return;
  mesh.notes.push_back(std::to_string(dropped) +
                       " STL triangles with two equal corners were dropped");
}

MeshData parseBinaryStl(std::string_view bytes, const std::string& name) {
  if (bytes.size() < kBinaryHeaderBytes + 4) {
    fail(name, "binary STL ends in its 84-byte header");
  }
  const uint64_t count = binaryTriangleCount(bytes);
  const uint64_t available = (bytes.size() - kBinaryHeaderBytes - 4) / kBinaryTriangleBytes;
  if (available < count) {
    fail(name, "file ends after " + std::to_string(available) + " of " + std::to_string(count) +
                   " triangles");
  }
  MeshBuilder mesh;
  CornerWelder welder(mesh);
  mesh.reserveTriangles(static_cast<size_t>(count));
  welder.reserve(3 * static_cast<size_t>(count));
  size_t dropped = 0;
  const char* record = bytes.data() + kBinaryHeaderBytes + 4;
  for (uint64_t t = 0; t < count; ++t, record += kBinaryTriangleBytes) {
    int corners[3];
    for (int c = 0; c < 3; ++c) {
      const char* p = record + 12 + 12 * c;  // after the facet normal
      corners[c] = welder.vertexOf(readFloat32(p), readFloat32(p + 4), readFloat32(p + 8));
    }
    if (!addWeldedPolygon(mesh, corners, 3)) ++dropped;
  }
  if (mesh.triangleCount() == 0) {
    fail(name, count == 0 ? "contains no faces" : "every triangle has two equal corners");
  }
  MeshData data = mesh.build(name);
  dropNote(data, dropped);
  return data;
}

MeshData parseAsciiStl(std::string_view text, const std::string& name) {
  LineReader lines(text, false);
  MeshBuilder mesh;
  CornerWelder welder(mesh);
  const size_t plausible =
      plausibleCount(static_cast<long long>(text.size()), text.size(), kMinAsciiFacetBytes);
  mesh.reserveTriangles(plausible);
  std::vector<int> corners;
  bool in_facet = false;
  size_t facets = 0, dropped = 0;
  std::string_view line, token;
  while (lines.next(line)) {
    LineTokens tokens(line);
    if (!tokens.next(token)) continue;
    const std::string at = lineAt(lines.line());
    if (token == "facet") {
      if (in_facet) fail(name, at + "'facet' before the previous facet's 'endfacet'");
      in_facet = true;
      corners.clear();
    } else if (token == "vertex") {
      if (!in_facet) fail(name, at + "'vertex' outside a facet");
      double xyz[3];
      for (double& value : xyz) {
        if (!tokens.next(token)) fail(name, at + "a vertex needs 3 coordinates");
        if (!parseDouble(token, value)) {
          fail(name, at + "cannot read " + quoted(token) + " as a number");
        }
      }
      corners.push_back(welder.vertexOf(xyz[0], xyz[1], xyz[2]));
    } else if (token == "endfacet") {
      if (!in_facet) fail(name, at + "'endfacet' without a facet");
      if (corners.size() < 3) {
        fail(name, at + "facet " + std::to_string(facets) + " has " +
                       std::to_string(corners.size()) + " vertices, at least 3 needed");
      }
      if (!addWeldedPolygon(mesh, corners.data(), corners.size())) ++dropped;
      in_facet = false;
      ++facets;
    } else if (token != "solid" && token != "endsolid" && token != "outer" && token != "endloop") {
      fail(name, at + "unexpected line starting with " + quoted(token));
    }
  }
  if (in_facet) fail(name, "file ends inside facet " + std::to_string(facets));
  if (mesh.triangleCount() == 0) {
    fail(name, facets == 0 ? "contains no faces" : "every facet has two equal corners");
  }
  MeshData data = mesh.build(name);
  dropNote(data, dropped);
  return data;
}

}  // namespace

MeshData parseStl(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) fail(name, "file is empty");
  return isBinaryStl(bytes) ? parseBinaryStl(bytes, name) : parseAsciiStl(bytes, name);
}

}  // namespace sdp::io::detail
