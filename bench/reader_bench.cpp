// The project's mesh readers (the io/ library) against vcglib's importers, the code MeshLab itself
// reads OFF, OBJ, PLY (tristrips too) and STL with (tri::io::ImporterOFF/OBJ/PLY/STL of MeshLab
// 2025.07's vcglib; for STL followed by Clean::RemoveDuplicateVertex, as MeshLab's STL import
// with its default "Unify Duplicated Vertices"), on speed and on bad input. bench/readers.py
// drives it.
//   sdp_reader_bench time FILE...        per file: best of 3 reads with each, seconds
//   sdp_reader_bench read ours|vcglib FILE
//       one read; prints "accepted V F", "accepted-invalid V F <why>" (a face index out of range
//       or a coordinate not finite reached the mesh), or "refused <reason>"; a crash or a hang
//       is the driver's to see.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include <vcg/complex/algorithms/clean.h>
#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import_obj.h>
#include <wrap/io_trimesh/import_off.h>
#include <wrap/io_trimesh/import_ply.h>
#include <wrap/io_trimesh/import_stl.h>

#include "best_of_three.h"
#include "io/mesh_io.h"

namespace {

class BenchVertex;
class BenchFace;
struct BenchTypes
    : vcg::UsedTypes<vcg::Use<BenchVertex>::AsVertexType, vcg::Use<BenchFace>::AsFaceType> {};
class BenchVertex : public vcg::Vertex<BenchTypes, vcg::vertex::Coord3d, vcg::vertex::BitFlags> {};
class BenchFace : public vcg::Face<BenchTypes, vcg::face::VertexRef, vcg::face::BitFlags> {};
class BenchMesh : public vcg::tri::TriMesh<std::vector<BenchVertex>, std::vector<BenchFace>> {};

std::string extension(const std::string& path) {
  const size_t dot = path.rfind('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

struct Outcome {
  bool accepted = false;
  int vertices = 0, faces = 0;
  std::string problem;  // accepted: what is invalid in the mesh; refused: the reason
};

Outcome readOurs(const std::string& path) {
  Outcome out;
  try {
    const sdp::io::MeshData mesh = sdp::io::readMesh(path);
    out.accepted = true;
    out.vertices = static_cast<int>(mesh.V.rows());
    out.faces = static_cast<int>(mesh.F.rows());
    if (!mesh.V.allFinite()) out.problem = "a coordinate is not finite";
    if (mesh.F.size() > 0 && (mesh.F.minCoeff() < 0 || mesh.F.maxCoeff() >= mesh.V.rows()))
      out.problem = "a face index is out of range";
  } catch (const std::exception& e) {
    out.problem = e.what();
  }
  return out;
}

Outcome readVcg(const std::string& path) {
  namespace io = vcg::tri::io;
  BenchMesh mesh;
  Outcome out;
  const std::string ext = extension(path);
  int mask = 0;
  int code = 0;
  bool critical = true;
  std::string message;
  if (ext == "off") {
    code = io::ImporterOFF<BenchMesh>::Open(mesh, path.c_str(), mask);
    critical = code != 0;  // ImporterOFF: 0 is success, everything else an error
    message = io::ImporterOFF<BenchMesh>::ErrorMsg(code);
  } else if (ext == "obj") {
    code = io::ImporterOBJ<BenchMesh>::Open(mesh, path.c_str(), mask);
    critical = io::ImporterOBJ<BenchMesh>::ErrorCritical(code);
    message = io::ImporterOBJ<BenchMesh>::ErrorMsg(code);
  } else if (ext == "ply") {
    code = io::ImporterPLY<BenchMesh>::Open(mesh, path.c_str(), mask);
    critical = io::ImporterPLY<BenchMesh>::ErrorCritical(code);
    message = io::ImporterPLY<BenchMesh>::ErrorMsg(code);
    // Tristrips' degenerate joins stay in vcglib's mesh; MeshLab's loader then drops them.
    if (!critical && vcg::tri::Clean<BenchMesh>::RemoveDegenerateFace(mesh) > 0)
      vcg::tri::Allocator<BenchMesh>::CompactEveryVector(mesh);
  } else if (ext == "stl") {
    code = io::ImporterSTL<BenchMesh>::Open(mesh, path.c_str(), mask);
    critical = code != 0;  // ImporterSTL: 0 is success
    message = io::ImporterSTL<BenchMesh>::ErrorMsg(code);
    if (!critical) {
      vcg::tri::Clean<BenchMesh>::RemoveDuplicateVertex(mesh);
      vcg::tri::Allocator<BenchMesh>::CompactEveryVector(mesh);
    }
  } else {
    out.problem = "unknown extension";
    return out;
  }
  if (critical) {
    out.problem = message;
    return out;
  }
  out.accepted = true;
  out.vertices = mesh.vn;
  out.faces = mesh.fn;
  const BenchVertex* first = mesh.vert.empty() ? nullptr : &mesh.vert[0];
  for (const BenchVertex& v : mesh.vert)
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(v.cP()[k])) out.problem = "a coordinate is not finite";
  for (const BenchFace& f : mesh.face)
    for (int k = 0; k < 3; ++k) {
      const BenchVertex* v = f.cV(k);
      if (v == nullptr || first == nullptr || v < first || v >= first + mesh.vert.size())
        out.problem = "a face index is out of range";
    }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 3 && std::strcmp(argv[1], "time") == 0) {
    for (int i = 2; i < argc; ++i) {
      Outcome ours, vcg;
      const double ours_s = sdp::bench::bestOfThreeSeconds([&] { ours = readOurs(argv[i]); });
      const double vcg_s = sdp::bench::bestOfThreeSeconds([&] { vcg = readVcg(argv[i]); });
      std::printf("%s ours %.3f s (%d v, %d f%s) vcglib %.3f s (%d v, %d f%s)\n", argv[i], ours_s,
                  ours.vertices, ours.faces, ours.accepted ? "" : ", refused", vcg_s, vcg.vertices,
                  vcg.faces, vcg.accepted ? "" : ", refused");
    }
    return 0;
  }
  if (argc == 4 && std::strcmp(argv[1], "read") == 0) {
    const std::string reader = argv[2];
    const Outcome out = reader == "ours" ? readOurs(argv[3]) : readVcg(argv[3]);
    if (out.accepted && out.problem.empty())
      std::printf("accepted %d %d\n", out.vertices, out.faces);
    else if (out.accepted)
      std::printf("accepted-invalid %d %d %s\n", out.vertices, out.faces, out.problem.c_str());
    else
      std::printf("refused %s\n", out.problem.c_str());
    return 0;
  }
  std::fprintf(stderr, "usage: sdp_reader_bench time FILE... | read ours|vcglib FILE\n");
  return 2;
}
