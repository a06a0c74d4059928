// OBJ in (positions, `vt` texture coordinates, polygons with `v/vt/vn` corners) and out (with
// its .mtl, one `vt` per layout row).
#include <climits>
#include <filesystem>
#include <string>

#include "io/scan.h"
#include "io/write.h"

namespace sdp::io {
namespace detail {
namespace {

struct ForwardReference {
  long long index = -1;
  int line = 0;
};

// A corner's vertex: a 1-based or relative (-1: the last defined) OBJ index, 0-based; a forward
// reference is checked when the file ends (OBJ allows them).
int objVertexIndex(std::string_view token, size_t defined_count, ForwardReference& largest,
                   int line, const std::string& name, std::string_view corner) {
  const long long defined = static_cast<long long>(defined_count);
  long long index = 0;
  if (!parseInteger(token, index)) {
    fail(name, lineAt(line) + "cannot read " + quoted(corner) + " as a face corner");
  }
  if (index == 0) fail(name, lineAt(line) + "vertex index 0 (OBJ counts from 1)");
  if (index < 0) {
    if (-index > defined) {
      fail(name, lineAt(line) + "relative index " + std::to_string(index) +
                     " reaches before the first vertex");
    }
    index += defined;
  } else {
    index -= 1;
    if (index > largest.index) largest = {index, line};
  }
  if (index > INT_MAX) fail(name, lineAt(line) + "vertex index " + quoted(token) + " is too large");
  return static_cast<int>(index);
}

// A corner's texture coordinate row, 0-based, or -1 when the reference cannot be resolved: the
// mesh is still read (texture coordinates are not what a parameterization needs), and the
// corner counts as one without (MeshBuilder::build drops forward references past the end).
int objTexcoordIndex(std::string_view token, size_t defined_count) {
  const long long defined = static_cast<long long>(defined_count);
  long long index = 0;
  if (!parseInteger(token, index) || index == 0 || -index > defined) return -1;
  index = index < 0 ? index + defined : index - 1;
  return index > INT_MAX ? -1 : static_cast<int>(index);
}

}  // namespace

MeshData parseObj(std::string_view text, const std::string& name) {
  LineReader lines(text, true);
  MeshBuilder mesh;
  std::string_view line, token;
  // Largest 0-based forward reference to a position, checked at the end.
  ForwardReference largest_vertex;
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
    } else if (token == "vt") {
      // "vt u [v [w]]": a missing v is 0, w is dropped.
      double uv[2] = {0, 0};
      for (int axis = 0; axis < 2; ++axis) {
        if (!tokens.next(token)) {
          if (axis == 0) fail(name, lineAt(lines.line()) + "texture coordinate has no u");
          break;
        }
        if (!parseDouble(token, uv[axis])) {
          fail(name, lineAt(lines.line()) + "cannot read " + quoted(token) + " as a number");
        }
      }
      mesh.addTexcoord(uv[0], uv[1]);
    } else if (token == "f") {
      int corners = 0;
      mesh.beginPolygon();
      while (tokens.next(token)) {
        // "v", "v/vt", "v/vt/vn" or "v//vn": the position and the texture coordinate.
        const size_t slash = token.find('/');
        const std::string_view position = token.substr(0, slash);
        const int vertex =
            objVertexIndex(position, mesh.vertexCount(), largest_vertex, lines.line(), name, token);
        int texcoord = -1;
        if (slash != std::string_view::npos) {
          const std::string_view rest = token.substr(slash + 1);
          const std::string_view texture = rest.substr(0, rest.find('/'));
          if (!texture.empty()) texcoord = objTexcoordIndex(texture, mesh.texcoordCount());
        }
        mesh.addCorner(vertex, texcoord);
        ++corners;
      }
      if (corners < 3) {
        fail(name, lineAt(lines.line()) + "face has " + std::to_string(corners) +
                       " vertices, at least 3 needed");
      }
      mesh.endPolygon();
    }
    // vn, g, o, s, usemtl, mtllib, l, p, ...: nothing to do for a parameterization.
  }
  if (largest_vertex.index >= static_cast<long long>(mesh.vertexCount())) {
    fail(name, lineAt(largest_vertex.line) + "face refers to vertex " +
                   std::to_string(largest_vertex.index + 1) + ", but the file has " +
                   std::to_string(mesh.vertexCount()) + " vertices");
  }
  return mesh.build(name);
}

}  // namespace detail

void writeObjWithTexture(const std::string& path, const Positions& V, const Triangles& F,
                         const Layout& layout, const std::string& texture_png_filename) {
  detail::checkMeshForWriting(path, V, F, layout);
  const UVs& uv = layout.uv;
  const std::filesystem::path obj_path(path);
  const std::filesystem::path mtl_path = std::filesystem::path(obj_path).replace_extension(".mtl");
  const std::string mtl_name = mtl_path.filename().string();
  const char* const kMaterial = "checker";

  detail::AtomicFile mtl(mtl_path.string());
  mtl.stream() << "# written by straightest_param\n"
               << "newmtl " << kMaterial << "\n"
               << "Ka 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\n"
               << "map_Kd " << texture_png_filename << "\n";

  detail::AtomicFile obj(path);
  detail::ChunkedWriter out(obj.stream());
  std::string& text = out.buffer();
  text += "# written by straightest_param\nmtllib " + mtl_name + "\n";
  for (Eigen::Index i = 0; i < V.rows(); ++i) {
    text += "v ";
    detail::appendNumber(text, V(i, 0));
    text += ' ';
    detail::appendNumber(text, V(i, 1));
    text += ' ';
    detail::appendNumber(text, V(i, 2));
    text += '\n';
    out.maybeFlush();
  }
  for (Eigen::Index i = 0; i < uv.rows(); ++i) {
    text += "vt ";
    detail::appendNumber(text, uv(i, 0));
    text += ' ';
    detail::appendNumber(text, uv(i, 1));
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
      detail::appendNumber(text, static_cast<long long>(F(f, c)) + 1);
      text += '/';
      detail::appendNumber(text, static_cast<long long>(layout.face_uv(f, c)) + 1);
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
    std::filesystem::remove(mtl_path, ec);
    throw;
  }
}

}  // namespace sdp::io
