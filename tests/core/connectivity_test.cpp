// analyzeConnectivity (core/common/connectivity.h) reports what a mesh is instead of refusing it:
// disks, closed models of any genus, many pieces, non-manifold edges and vertices, inconsistent
// orientation. Counts from the meshes' README (../shared/meshes) and small meshes built here.
#include <gtest/gtest.h>

#include "core/common/connectivity.h"
#include "io/mesh_io.h"
#include "test_mesh_files.h"

namespace sdp {
namespace {

Connectivity ofFile(const std::string& path) {
  const io::MeshData m = io::readMesh(path);
  return analyzeConnectivity(m.F, static_cast<int>(m.V.rows()));
}

Connectivity of(std::initializer_list<std::array<int, 3>> faces, int vertices) {
  Triangles F(static_cast<Eigen::Index>(faces.size()), 3);
  int f = 0;
  for (const auto& t : faces) F.row(f++) << t[0], t[1], t[2];
  return analyzeConnectivity(F, vertices);
}

TEST(Connectivity, NefertitiIsADisk) {
  SDP_MESH_OR_SKIP(path, "disk/nefertiti.off");
  const Connectivity c = ofFile(path);
  EXPECT_TRUE(c.isDisk());
  EXPECT_EQ(c.components, 1);
  EXPECT_EQ(c.boundary_loops, 1);
  EXPECT_EQ(c.genus(0), 0);
  EXPECT_EQ(c.vertices - c.edges + c.faces, 1);
}

TEST(Connectivity, BeetleHasElevenBoundaryLoops) {
  SDP_MESH_OR_SKIP(path, "holes/beetle.off");
  const Connectivity c = ofFile(path);
  EXPECT_EQ(c.components, 1);
  EXPECT_EQ(c.boundary_loops, 11);
  EXPECT_EQ(c.genus(0), 0);
  EXPECT_FALSE(c.isDisk());
}

TEST(Connectivity, ClosedModelsOfEveryGenus) {
  for (const auto& [file, genus] : {std::pair<const char*, int>{"closed/bunny.off", 0},
                                    {"closed/fertility.off", 4},
                                    {"invalid/3holes.off", 3}}) {
    SCOPED_TRACE(file);
    SDP_MESH_OR_SKIP(path, file);
    const Connectivity c = ofFile(path);
    EXPECT_EQ(c.components, 1);
    EXPECT_EQ(c.boundary_loops, 0);
    EXPECT_EQ(c.boundary_edges, 0);
    EXPECT_EQ(c.non_manifold_edges, 0);
    EXPECT_EQ(c.inconsistent_edges, 0);
    EXPECT_EQ(c.genus(0), genus);
  }
}

TEST(Connectivity, TwoComponentsAndANonManifoldEdge) {
  SDP_MESH_OR_SKIP(two, "invalid/two_components.off");
  const Connectivity c = ofFile(two);
  EXPECT_EQ(c.components, 2);
  EXPECT_EQ(c.boundary_loops, 2);
  SDP_MESH_OR_SKIP(fin, "invalid/nonmanifold_edge.off");
  EXPECT_EQ(ofFile(fin).non_manifold_edges, 1);
}

// The CAD-like truck: the meshes' README counts 54 non-manifold edges; its pieces, split at
// those edges, are more than its 50 vertex-connected components.
TEST(Connectivity, TruckIsReportedNotRefused) {
  SDP_MESH_OR_SKIP(path, "closed/truck.obj");
  const Connectivity c = ofFile(path);
  EXPECT_EQ(c.non_manifold_edges, 54);
  EXPECT_GE(c.components, 50);
  EXPECT_GT(c.boundary_loops, 0);
  EXPECT_FALSE(c.isDisk());
}

TEST(Connectivity, BorderHalfEdgesAreTheEdgesOfOneFaceEach) {
  // A square of two triangles (0 1 2, 0 2 3): the diagonal is shared, the four sides are the
  // border, each as its face runs, in (low, high) order.
  Triangles F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  const std::vector<HalfEdgeKey> border = borderHalfEdges(F, 4);
  int steps = 0;  // a front end's progress bar is called between the analysis's steps
  EXPECT_TRUE(analyzeConnectivity(F, 4, [&] { ++steps; }).isDisk());
  EXPECT_EQ(steps, 3);
  ASSERT_EQ(border.size(), 4u);
  const int expected[4][3] = {{0, 1, 0}, {0, 3, 5}, {1, 2, 1}, {2, 3, 4}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(border[i].low, expected[i][0]) << i;
    EXPECT_EQ(border[i].high, expected[i][1]) << i;
    EXPECT_EQ(border[i].half_edge, expected[i][2]) << i;
  }
}

TEST(Connectivity, SmallCases) {
  // Two triangles touching at vertex 0 only: two pieces and a non-manifold vertex.
  const Connectivity bowtie = of({{0, 1, 2}, {0, 3, 4}}, 5);
  EXPECT_EQ(bowtie.components, 2);
  EXPECT_EQ(bowtie.non_manifold_vertices, 1);
  // A square whose second triangle runs the wrong way along the diagonal.
  const Connectivity flipped = of({{0, 1, 2}, {0, 2, 3}}, 4);
  EXPECT_EQ(flipped.inconsistent_edges, 0);
  const Connectivity wrong = of({{0, 1, 2}, {0, 3, 2}}, 4);
  EXPECT_EQ(wrong.inconsistent_edges, 1);
  EXPECT_FALSE(wrong.isDisk());
  // A tetrahedron: closed, genus 0; a repeated vertex is a degenerate face.
  const Connectivity tetra = of({{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}, 4);
  EXPECT_EQ(tetra.boundary_loops, 0);
  EXPECT_EQ(tetra.euler_characteristic[0], 2);
  EXPECT_EQ(of({{0, 1, 1}}, 2).degenerate_faces, 1);
  // Three triangles on one edge.
  EXPECT_EQ(of({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}, 5).non_manifold_edges, 1);
}

}  // namespace
}  // namespace sdp
