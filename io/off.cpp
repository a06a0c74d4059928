// OFF (Geomview's Object File Format) in; positions and polygons only.
#include <climits>
#include <string>

#include "io/scan.h"

namespace sdp::io::detail {
namespace {

// The smallest lines "0 0 0\n" and "3 0 1 2\n" bound the header's counts by the data.
constexpr size_t kMinOffVertexBytes = 6;
constexpr size_t kMinOffFaceBytes = 8;

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

}  // namespace

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

}  // namespace sdp::io::detail
