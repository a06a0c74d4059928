#include <gtest/gtest.h>

#include "core/paper/patch_topology.h"
#include "core/parameterize.h"
#include "test_meshes.h"

namespace sdp {
namespace {

std::string reasonFor(const Positions& V, const Triangles& F) {
  try {
    buildPatch(V, F);
  } catch (const ParameterizationError& e) {
    return e.what();
  }
  return "";
}

Positions points(int n) {
  Positions V(n, 3);
  for (int i = 0; i < n; ++i) V.row(i) << i, (i * i) % 7, (i * 3) % 5;
  return V;
}

TEST(Topology, DiskRingsAndBoundaryLoop) {
  const test::Mesh m = test::planarGrid(3);
  const Patch p = buildPatch(m.V, m.F);
  EXPECT_EQ(p.boundary_loop.size(), 12u);
  EXPECT_EQ(p.interiorCount(), 4);
  // The loop keeps the faces on its left: counter-clockwise in the xy plane.
  double twice_area = 0;
  for (size_t k = 0; k < p.boundary_loop.size(); ++k) {
    const auto& a = p.position[p.boundary_loop[k]];
    const auto& b = p.position[p.boundary_loop[(k + 1) % p.boundary_loop.size()]];
    twice_area += a.x() * b.y() - a.y() * b.x();
  }
  EXPECT_GT(twice_area, 0);
  // Every ring face really is (v, ring[k], ring[k+1]).
  for (int v = 0; v < p.vertexCount(); ++v)
    for (int k = p.ring_begin[v]; k < p.ring_begin[v + 1]; ++k) {
      const int f = p.ring_face[k];
      if (f < 0) continue;
      const int next =
          k + 1 < p.ring_begin[v + 1] ? p.ring_vertex[k + 1] : p.ring_vertex[p.ring_begin[v]];
      const auto& t = p.face[f];
      const int c = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
      EXPECT_EQ(t[(c + 1) % 3], p.ring_vertex[k]);
      EXPECT_EQ(t[(c + 2) % 3], next);
    }
}

TEST(Topology, RejectsWithOneLineReasons) {
  Triangles tetra(4, 3);
  tetra << 0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2;
  EXPECT_NE(reasonFor(points(4), tetra).find("closed"), std::string::npos);

  Triangles two(2, 3);
  two << 0, 1, 2, 3, 4, 5;
  EXPECT_NE(reasonFor(points(6), two).find("2 connected components"), std::string::npos);

  Triangles fin(3, 3);  // edge (0, 1) in three faces
  fin << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  EXPECT_NE(reasonFor(points(5), fin).find("non-manifold edge"), std::string::npos);

  Triangles dup(2, 3);
  dup << 0, 1, 2, 1, 2, 0;
  EXPECT_NE(reasonFor(points(3), dup).find("duplicates"), std::string::npos);

  Triangles flipped(2, 3);
  flipped << 0, 1, 2, 0, 1, 3;
  EXPECT_NE(reasonFor(points(4), flipped).find("oriented inconsistently"), std::string::npos);

  Triangles bowtie(2, 3);  // two triangles sharing only vertex 0 -> two components here
  bowtie << 0, 1, 2, 0, 3, 4;
  EXPECT_FALSE(reasonFor(points(5), bowtie).empty());

  Triangles range(1, 3);
  range << 0, 1, 7;
  EXPECT_NE(reasonFor(points(3), range).find("refers to vertex 7"), std::string::npos);

  Triangles repeated(1, 3);
  repeated << 0, 1, 1;
  EXPECT_NE(reasonFor(points(3), repeated).find("same vertex twice"), std::string::npos);

  Positions nan = points(3);
  nan(1, 2) = std::nan("");
  Triangles one(1, 3);
  one << 0, 1, 2;
  EXPECT_NE(reasonFor(nan, one).find("non-finite"), std::string::npos);

  EXPECT_NE(reasonFor(points(3), Triangles(0, 3)).find("no faces"), std::string::npos);
}

TEST(Topology, RejectsAnnulusAndNonManifoldVertex) {
  // An annulus: the regular fan without its centre faces' inner part -> two boundary loops.
  test::Mesh outer = test::regularFan(8);
  Positions V(16, 3);
  Triangles F(16, 3);
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * M_PI * k / 8;
    V.row(k) << std::cos(a), std::sin(a), 0;
    V.row(8 + k) << 2 * std::cos(a), 2 * std::sin(a), 0;
    const int i0 = k, i1 = (k + 1) % 8, o0 = 8 + k, o1 = 8 + (k + 1) % 8;
    F.row(2 * k) << i0, o0, o1;
    F.row(2 * k + 1) << i0, o1, i1;
  }
  PatchOptions no_fill;
  no_fill.fill_holes = false;
  try {
    buildPatch(V, F, no_fill);
    ADD_FAILURE() << "annulus accepted without filling";
  } catch (const ParameterizationError& e) {
    EXPECT_NE(std::string(e.what()).find("2 boundary loops"), std::string::npos);
  }
  // Filled: one virtual centre, eight fan faces, the outer (longer) loop is the boundary.
  const Patch filled = buildPatch(V, F);
  EXPECT_EQ(filled.holes_filled, 1);
  EXPECT_EQ(filled.real_vertex_count, 16);
  EXPECT_EQ(filled.vertexCount(), 17);
  EXPECT_EQ(filled.real_face_count, 16);
  EXPECT_EQ(filled.faceCount(), 24);
  for (int b : filled.boundary_loop) EXPECT_GE(b, 8);
  // The user may pick the other loop as the outer one.
  PatchOptions inner_outer;
  inner_outer.outer_vertex = 0;
  for (int b : buildPatch(V, F, inner_outer).boundary_loop) EXPECT_LT(b, 8);

  // Two fans glued at their centre vertex: connected through edges? No -- through the vertex
  // only, but a shared edge keeps it one piece here: a vertex with two fans.
  Positions W(7, 3);
  W << 0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 1, 1, 1, -1, -1, 1;
  Triangles G(4, 3);
  G << 0, 1, 2, 0, 2, 5, 0, 3, 4, 0, 4, 6;
  EXPECT_FALSE(reasonFor(W, G).empty());
}

TEST(Topology, UnreferencedVerticesAreIgnored) {
  test::Mesh m = test::planarGrid(3);
  Positions V(m.V.rows() + 2, 3);
  V << m.V, Eigen::RowVector3d(std::nan(""), 0, 0), Eigen::RowVector3d(5, 5, 5);
  const Patch p = buildPatch(V, m.F);
  EXPECT_EQ(p.vertexCount(), m.V.rows());
  EXPECT_EQ(p.local_vertex[V.rows() - 1], -1);
}

}  // namespace
}  // namespace sdp
