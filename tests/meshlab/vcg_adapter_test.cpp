// The vcg adapters on a plain vcglib mesh with optional (ocf) components, like MeshLab's CMeshO:
// built once against the vcglib of each MeshLab version in meshlab-builds.tsv.
#include <gtest/gtest.h>

#include <vcg/complex/complex.h>

#include "vcg_adapters/mesh_run.h"
#include "vcg_adapters/patch_adapter.h"

namespace {

class TestVertex;
class TestFace;
struct TestUsedTypes
    : vcg::UsedTypes<vcg::Use<TestVertex>::AsVertexType, vcg::Use<TestFace>::AsFaceType> {};
class TestVertex : public vcg::Vertex<TestUsedTypes, vcg::vertex::InfoOcf, vcg::vertex::Coord3f,
                                      vcg::vertex::BitFlags, vcg::vertex::TexCoordfOcf> {};
class TestFace
    : public vcg::Face<TestUsedTypes, vcg::face::InfoOcf, vcg::face::VertexRef, vcg::face::BitFlags,
                       vcg::face::QualityfOcf, vcg::face::WedgeTexCoordfOcf> {};
class TestMesh : public vcg::tri::TriMesh<vcg::vertex::vector_ocf<TestVertex>,
                                          vcg::face::vector_ocf<TestFace>> {};

namespace adapter = sdp::vcg_adapter;

// What the MeshLab shims run with: the product's defaults, fitted and stored as MeshLab stores.
sdp::Options meshLabOptions() {
  sdp::Options options = sdp::productDefaults();
  adapter::setMeshLabStorage(options);
  return options;
}

// An n x n vertex grid on a gently curved sheet (a disk), counter-clockwise triangles.
void makeGrid(TestMesh& m, int n, float x0 = 0) {
  auto vi = vcg::tri::Allocator<TestMesh>::AddVertices(m, n * n);
  std::vector<TestMesh::VertexPointer> v;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i, ++vi) {
      const float x = x0 + i / float(n - 1), y = j / float(n - 1);
      vi->P() = vcg::Point3f(x, y, 0.2f * x * x);
      v.push_back(&*vi);
    }
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      auto a = v[j * n + i], b = v[j * n + i + 1], c = v[(j + 1) * n + i + 1],
           d = v[(j + 1) * n + i];
      vcg::tri::Allocator<TestMesh>::AddFace(m, a, b, c);
      vcg::tri::Allocator<TestMesh>::AddFace(m, a, c, d);
    }
  }
}

int liveFaces(const TestMesh& m) {
  int n = 0;
  for (const auto& f : m.face) n += !f.IsD();
  return n;
}

TEST(VcgAdapter, ExtractSkipsDeletedElementsAndKeepsMaps) {
  TestMesh m;
  makeGrid(m, 5);
  // A stray triangle, then deleted: it must not reach the core.
  auto extra = vcg::tri::Allocator<TestMesh>::AddVertices(m, 3);
  for (int k = 0; k < 3; ++k) (extra + k)->P() = vcg::Point3f(5.f + k, 5.f, 0.f);
  auto stray = vcg::tri::Allocator<TestMesh>::AddFace(m, &*extra, &*(extra + 1), &*(extra + 2));
  vcg::tri::Allocator<TestMesh>::DeleteFace(m, *stray);
  vcg::tri::Allocator<TestMesh>::DeleteVertex(m, *(extra + 1));

  const adapter::PatchInput in = adapter::extractPatch(m, false);
  EXPECT_EQ(in.positions.rows(), 25);
  EXPECT_EQ(in.triangles.rows(), 32);
  EXPECT_EQ(in.coreVertexOf(26), -1);  // deleted
  EXPECT_EQ(in.coreVertexOf(25), -1);  // only used by the deleted face
  for (int i = 0; i < 25; ++i) {
    EXPECT_EQ(in.coreVertexOf(i), i);
    EXPECT_EQ(in.meshVertexOf(i), i);
    EXPECT_FLOAT_EQ(in.positions(i, 0), m.vert[i].P()[0]);
  }
}

TEST(VcgAdapter, SelectedFacesOnly) {
  TestMesh m;
  makeGrid(m, 5);
  EXPECT_THROW(adapter::extractPatch(m, true), sdp::ParameterizationError);
  for (int f = 0; f < 8; ++f) m.face[f].SetS();  // the first row of quads
  const adapter::PatchInput in = adapter::extractPatch(m, true);
  EXPECT_EQ(in.triangles.rows(), 8);
  EXPECT_EQ(in.positions.rows(), 10);
  EXPECT_EQ(in.meshVertexOf(5), 5);  // second grid row starts at mesh vertex 5
  EXPECT_EQ(in.coreVertexOf(12), -1);
}

TEST(VcgAdapter, RunWritesWedgeUVsQualityAndEnablesComponents) {
  TestMesh m;
  makeGrid(m, 7);
  ASSERT_FALSE(vcg::tri::HasPerWedgeTexCoord(m));
  ASSERT_FALSE(vcg::tri::HasPerFaceQuality(m));

  sdp::Options options = meshLabOptions();
  options.boundary = sdp::BoundaryShape::Circle;
  const adapter::MeshRun run = adapter::runOnMesh(m, options, false, -1);
  EXPECT_FALSE(vcg::tri::HasPerWedgeTexCoord(m)) << "running must not touch the mesh";

  adapter::WriteOptions write;
  write.vertex_texcoords = true;
  const auto stored =
      adapter::prepareLayout<TestMesh>(run.input, run.result.layout, run.result.face_stretch);
  // What the mesh will hold is the core's stored layout exactly (floats, certified there).
  ASSERT_EQ(stored.u.size(), static_cast<size_t>(run.result.layout.uv.rows()));
  for (size_t i = 0; i < stored.u.size(); ++i) {
    EXPECT_EQ(static_cast<double>(stored.u[i]), run.result.layout.uv(i, 0));
    EXPECT_EQ(static_cast<double>(stored.v[i]), run.result.layout.uv(i, 1));
  }
  adapter::applyResult(m, run.input, stored, write);

  ASSERT_TRUE(vcg::tri::HasPerWedgeTexCoord(m));
  ASSERT_TRUE(vcg::tri::HasPerFaceQuality(m));
  ASSERT_TRUE(vcg::tri::HasPerVertexTexCoord(m));
  for (const auto& f : m.face) {
    // Copies: cWT() of some vcglib versions returns a temporary.
    const vcg::Point2f a = f.cWT(0).P(), b = f.cWT(1).P(), c = f.cWT(2).P();
    EXPECT_GT((b - a) ^ (c - a), 0.f) << "counter-clockwise, not flipped";
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(f.cWT(k).N(), 0);
      EXPECT_GE(f.cWT(k).U(), 0.f);
      EXPECT_LE(f.cWT(k).U(), 1.f);
      EXPECT_EQ(f.cWT(k).U(), f.cV(k)->cT().U()) << "per-vertex equals per-wedge";
    }
    EXPECT_GT(f.cQ(), 0.f);
  }
}

TEST(VcgAdapter, SingleSelectedVertexBecomesTheSource) {
  TestMesh m;
  makeGrid(m, 7);
  const int centre = 3 * 7 + 2;  // interior, not the automatic choice (the middle, 24)
  m.vert[centre].SetS();
  EXPECT_EQ(adapter::singleSelectedVertex(m), centre);
  const adapter::MeshRun run = adapter::runOnMesh(m, meshLabOptions(), false, 1);
  EXPECT_EQ(run.result.report.source_vertex, centre) << "the selection wins, in mesh numbering";

  m.vert[centre + 1].SetS();  // two selected: no override
  EXPECT_EQ(adapter::singleSelectedVertex(m), -1);
}

TEST(VcgAdapter, SourceOutsideThePatchIsRefused) {
  TestMesh m;
  makeGrid(m, 5);
  EXPECT_THROW(adapter::runOnMesh(m, meshLabOptions(), false, 1000), sdp::ParameterizationError);
}

TEST(VcgAdapter, FailureLeavesTheMeshUntouched) {
  TestMesh m;
  makeGrid(m, 4);
  makeGrid(m, 4, 3.f);  // a second component: not a disk
  const int faces = liveFaces(m);
  try {
    adapter::runOnMesh(m, meshLabOptions(), false, -1);
    FAIL() << "two components must be refused";
  } catch (const sdp::ParameterizationError& e) {
    EXPECT_NE(std::string(e.what()), "");
  }
  EXPECT_EQ(liveFaces(m), faces);
  EXPECT_FALSE(vcg::tri::HasPerWedgeTexCoord(m));
  EXPECT_FALSE(vcg::tri::HasPerFaceQuality(m));
}

}  // namespace
