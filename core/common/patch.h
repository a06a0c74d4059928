// The patch every step speaks: referenced vertices, triangles, and the derived topology the
// later steps need (ordered 1-rings, the boundary loop, face adjacency for plane walks, virtual
// hole fills). The paper's topology check builds it (core/paper/patch_topology.h).
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

namespace sdp {

struct Patch {
  // Compacted: only vertices referenced by a face, in input order; centred and divided by
  // `unit` (the input's largest extent), so every patch has size about 1.
  std::vector<Eigen::Vector3d> position;
  double unit = 1;
  std::vector<std::array<int, 3>> face;  // local vertex indices, input face order
  std::vector<int> input_vertex;         // local -> input vertex index
  std::vector<int> local_vertex;         // input -> local vertex index, -1 if unreferenced

  // Ordered 1-rings in CSR form. For vertex v the neighbours ring_vertex[ring_begin[v] ..
  // ring_begin[v+1]) go counter-clockwise; ring_face[k] is the face (v, ring_vertex[k],
  // ring_vertex[k+1]) (cyclic for interior vertices; a boundary vertex has one face fewer than
  // neighbours and its ring_face entry at the last neighbour is -1).
  std::vector<int> ring_begin;
  std::vector<int> ring_vertex;
  std::vector<int> ring_face;
  std::vector<char> on_boundary;

  // face_across[f][c]: the face across the edge face[f][c] -> face[f][(c+1)%3], or -1.
  std::vector<std::array<int, 3>> face_across;

  // Boundary vertices in the order that keeps the faces on the left (counter-clockwise when
  // the faces are counter-clockwise). With holes: the outer loop.
  std::vector<int> boundary_loop;

  // Holes are filled virtually for the solve: each inner loop gets a fan to a virtual centre
  // vertex. Virtual vertices come after the real ones (input_vertex -1), virtual faces after the
  // input faces, so [0, real_vertex_count) and [0, real_face_count) are the user's mesh.
  int real_vertex_count = 0;
  int real_face_count = 0;
  int holes_filled = 0;

  int vertexCount() const { return static_cast<int>(position.size()); }
  bool isVirtual(int v) const { return v >= real_vertex_count; }
  int faceCount() const { return static_cast<int>(face.size()); }
  int ringSize(int v) const { return ring_begin[v + 1] - ring_begin[v]; }
  int interiorCount() const { return vertexCount() - static_cast<int>(boundary_loop.size()); }
};

using LocalUVs = std::vector<Eigen::Vector2d>;  // one per patch vertex

}  // namespace sdp
