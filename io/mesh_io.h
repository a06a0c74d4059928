// Mesh files, for the command line tool, the tests, the fuzzer and the bench: OFF, OBJ, PLY
// (faces or tristrips) and STL (binary or ASCII, corners welded) in, with per-corner texture
// coordinates where the file has them; OBJ+MTL+PNG or PLY out. One file per format
// (io/off.cpp, obj.cpp, ply.cpp, stl.cpp, png.cpp); io/checkerboard.h is the texture.
// Readers take untrusted bytes (a fuzzer drives them): every problem is a ParameterizationError
// with a one-line reason naming the file, never a crash, a hang or an allocation larger than the
// input justifies. Writers replace their target atomically (temporary file + rename).
#pragma once

#include <string>
#include <vector>

#include "core/parameterize.h"

namespace sdp::io {

struct MeshData {
  sdp::Positions V;
  sdp::Triangles F;
  int polygons_triangulated = 0;  // input faces with more than 3 corners, fan-triangulated
  // What else the reader changed on the way in, one sentence each (STL corners welded into
  // degenerate triangles, PLY tristrips' degenerate joins), for the report's notes.
  std::vector<std::string> notes;
  // The file's texture coordinates, per triangle corner: texcoords.uv #U×2 and
  // texcoords.face_uv #F×3 (row of uv, -1 at a corner the file gives none), as another tool
  // stored them, seams included. From OBJ `vt` and `f v/vt`, PLY face `texcoord` lists (u0 v0
  // u1 v1 ..., MeshLab's wedge coordinates) or PLY per-vertex s/t, u/v or texture_u/texture_v.
  // Empty (0 rows) when the file has none.
  Layout texcoords;
  int faces_without_texcoords = 0;  // faces with a corner at -1, when texcoords is not empty
};

// Dispatches on the extension (.off, .obj, .ply, .stl, any letter case). The reason of an error
// starts with the file name, e.g. "truncated.off: file ends after 66 of 299 vertices".
MeshData readMesh(const std::string& path);

// `format` is "off", "obj", "ply" or "stl" (any case, a leading dot allowed).
MeshData readMeshFromMemory(const std::string& bytes, const std::string& format);

// True when readMesh knows the extension of `path`.
bool isReadableMeshPath(const std::string& path);

// OBJ with one `vt` per row of layout.uv and `f v/vt` corners (face_uv: per-wedge texture
// coordinates as MeshLab reads them, seams included), plus `<stem>.mtl` next to it whose
// material maps `texture_png_filename` (a file name relative to the OBJ's folder).
void writeObjWithTexture(const std::string& path, const sdp::Positions& V, const sdp::Triangles& F,
                         const sdp::Layout& layout, const std::string& texture_png_filename);

// Binary little-endian PLY: vertex double x y z; face `list uchar int vertex_indices` and
// `list uchar float texcoord` (u0 v0 u1 v1 u2 v2 from the layout's corners), MeshLab's
// per-wedge texture coordinates; with layout.chart (an atlas), `int chart` per face.
void writePly(const std::string& path, const sdp::Positions& V, const sdp::Triangles& F,
              const sdp::Layout& layout);

// 8-bit RGB PNG; `rgb` holds width * height * 3 bytes, top row first.
void writePng(const std::string& path, int width, int height,
              const std::vector<unsigned char>& rgb);

// Writes `text` to `path` atomically (used for the JSON report).
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace sdp::io
