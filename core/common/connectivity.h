// The connectivity of any triangle mesh, reported, never refused: the first step of a run
// (docs/method.md §1). A disk patch is one case (one component, one boundary loop, genus 0,
// manifold and consistently oriented); closed models, higher genus, many pieces, non-manifold
// edges and vertices and inconsistent orientation are described by the same counts, which an
// atlas needs to cut the mesh into charts and the patch filter to explain a refusal.
//
// Numbering: faces and vertices as in F (input numbering). Half-edge h = 3 f + k runs from
// corner k of face f to corner (k + 1) % 3.
#pragma once

#include <functional>
#include <vector>

#include "layout.h"

namespace sdp {

struct Connectivity {
  int vertices = 0;  // referenced by some face
  int faces = 0;
  int edges = 0;  // distinct undirected edges
  // Per half-edge: the half-edge of the other face across its edge when the edge has exactly
  // two faces (running the opposite way when the two agree in orientation), else -1 (a boundary
  // edge, or a non-manifold edge with three or more faces).
  std::vector<int> twin;
  std::vector<int> component;  // per face: its piece, faces joined across two-face edges
  int components = 0;
  int boundary_edges = 0;         // edges with one face
  int boundary_loops = 0;         // connected chains of boundary edges
  int non_manifold_edges = 0;     // edges with three or more faces
  int non_manifold_vertices = 0;  // vertices whose faces form two or more fans
  int inconsistent_edges = 0;     // two-face edges whose faces run the same way along them
  int degenerate_faces = 0;       // a vertex repeated within the face
  // Per component: Euler characteristic V - E + F and boundary loops; the genus follows as
  // (2 - chi - loops) / 2 for a manifold, orientable component.
  std::vector<int> euler_characteristic, component_loops;

  // One component, one boundary loop, genus 0, no non-manifold element, consistently oriented.
  bool isDisk() const;
  // Inner boundary loops (holes) when the mesh is a disk with holes (as isDisk, with one or more
  // boundary loops): loops - 1; -1 when it is not.
  int diskHoles() const;
  // The genus of component c (meaningful when it is manifold and orientable).
  int genus(int c) const { return (2 - euler_characteristic[c] - component_loops[c]) / 2; }
};

// `vertex_count` bounds the indices of F (each in [0, vertex_count)). `step`, when given, is
// called between the analysis's steps, on the calling thread (seconds at millions of faces: a
// front end's progress bar).
Connectivity analyzeConnectivity(const Triangles& F, int vertex_count,
                                 const std::function<void()>& step = {});

// A half-edge h = 3 f + k by its undirected edge: its lower and higher end vertex.
struct HalfEdgeKey {
  int low, high, half_edge;
};
// Every half-edge whose two ends differ, ordered by (low, high, half_edge), so the half-edges of
// one edge are neighbours; in linear time (a counting sort on the lower end). `vertex_count`
// bounds the indices of F.
std::vector<HalfEdgeKey> sortedHalfEdges(const Triangles& F, int vertex_count);
// Calls run(begin, end) for each run [begin, end) of the sorted keys that share one edge (equal
// low and high ends), in order.
template <class Run>
void forEachEdgeRun(const std::vector<HalfEdgeKey>& keys, Run&& run) {
  for (size_t i = 0; i < keys.size();) {
    size_t j = i + 1;
    while (j < keys.size() && keys[j].low == keys[i].low && keys[j].high == keys[i].high) ++j;
    run(i, j);
    i = j;
  }
}
// The half-edges alone on their edge (the faces' border, each as its face runs), in the order of
// sortedHalfEdges.
std::vector<HalfEdgeKey> borderHalfEdges(const Triangles& F, int vertex_count);

// Which faces to turn over (reverse their winding) so that faces joined across two-face edges
// agree, per face 1 = turn over. Faces are walked breadth-first from each piece's first face; in
// each piece the side kept is the one most of its faces already have (ties keep the first face's),
// so a consistently wound mesh turns none. A non-orientable piece (a Moebius strip) keeps the
// edges where the walk meets itself inconsistent.
std::vector<char> coherentOrientation(const Triangles& F, const Connectivity& connectivity);

}  // namespace sdp
