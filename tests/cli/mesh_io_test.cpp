// Mesh readers and writers of the io/ library (io/mesh_io.h).
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "io/checkerboard.h"
#include "io/mesh_io.h"
#include "test_mesh_files.h"

namespace fs = std::filesystem;
using sdp::ParameterizationError;
using sdp::io::MeshData;
using sdp::io::readMeshFromMemory;

namespace {

// The meshes that ship with the repository; the larger ones via sdp::test::meshFile.
const fs::path kMeshes = fs::path(SDP_BUNDLED_MESH_DIR);

// Runs `read`, expects a ParameterizationError whose one-line message contains every part.
void expectError(const std::function<void()>& read, const std::vector<std::string>& parts) {
  try {
    read();
    ADD_FAILURE() << "no error; expected one mentioning '" << parts.front() << "'";
  } catch (const ParameterizationError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    for (const std::string& part : parts) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "message '" << message << "' lacks '" << part << "'";
    }
  }
}

void expectOffError(const std::string& text, const std::vector<std::string>& parts) {
  expectError([&] { readMeshFromMemory(text, "off"); }, parts);
}
void expectObjError(const std::string& text, const std::vector<std::string>& parts) {
  expectError([&] { readMeshFromMemory(text, "obj"); }, parts);
}
void expectPlyError(const std::string& text, const std::vector<std::string>& parts) {
  expectError([&] { readMeshFromMemory(text, "ply"); }, parts);
}

std::vector<int> faceRow(const MeshData& mesh, int f) {
  return {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
}

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A unit square split in two triangles plus a quad on top: 6 vertices, 2 triangles, 1 quad.
constexpr const char* kSquareAndQuadOff =
    "OFF\n6 3 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 2 0\n1 2 0\n3 0 1 2\n3 0 2 3\n4 3 2 5 4\n";

// A temporary folder per test, removed afterwards.
class TempDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("sdp_mesh_io_") + info->test_suite_name() + "_" + info->name();
    for (char& c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    dir_ =
        fs::temp_directory_path() /
        (name + "_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::vector<std::string> filesInDir() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }
  fs::path dir_;
};

// A small mesh with texture coordinates for the writers.
struct TexturedMesh {
  sdp::Positions V;
  sdp::Triangles F;
  sdp::UVs uv;
  sdp::Layout layout() const { return sdp::Layout::perVertex(uv, F); }
};

TexturedMesh makeTexturedMesh() {
  TexturedMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 1, 0, 0.25, 1, 1, -0.5, 0, 1, 1e-7, 0.5, 0.5, 0.123456789012345;
  m.F.resize(4, 3);
  m.F << 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4;
  m.uv.resize(5, 2);
  m.uv << 0, 0, 1, 0, 1, 1, 0, 1, 0.5, 0.3333333333333333;
  return m;
}

// ------------------------------------------------------------------------------------------
// Binary PLY construction

class PlyBuilder {
 public:
  explicit PlyBuilder(bool big_endian) : big_endian_(big_endian) {}
  PlyBuilder& header(const std::string& lines) {
    bytes_ = "ply\nformat " +
             std::string(big_endian_ ? "binary_big_endian" : "binary_little_endian") + " 1.0\n" +
             lines + "end_header\n";
    return *this;
  }
  template <typename T>
  PlyBuilder& put(T value) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    const bool host_little = [] {
      const uint16_t probe = 1;
      unsigned char first;
      std::memcpy(&first, &probe, 1);
      return first == 1;
    }();
    if (host_little == big_endian_) std::reverse(raw, raw + sizeof(T));
    bytes_.append(reinterpret_cast<const char*>(raw), sizeof(T));
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  bool big_endian_;
  std::string bytes_;
};

}  // namespace

// ------------------------------------------------------------------------------------------
// OFF

TEST(OffReader, ReadsTrianglesAndFanTriangulatesQuads) {
  const MeshData mesh = readMeshFromMemory(kSquareAndQuadOff, "off");
  ASSERT_EQ(mesh.V.rows(), 6);
  ASSERT_EQ(mesh.F.rows(), 4);
  EXPECT_EQ(mesh.polygons_triangulated, 1);
  EXPECT_EQ(mesh.V(5, 0), 1.0);
  EXPECT_EQ(mesh.V(5, 1), 2.0);
  EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(faceRow(mesh, 2), (std::vector<int>{3, 2, 5}));
  EXPECT_EQ(faceRow(mesh, 3), (std::vector<int>{3, 5, 4}));
}

TEST(OffReader, AcceptsHeaderVariantsCommentsAndExtraColumns) {
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const std::vector<std::string> variants = {
      "OFF\n3 1 0\n" + body,
      "OFF 3 1 0\n" + body,
      "OFF\n3 1\n" + body,  // no edge count
      "3 1 0\n" + body,     // no keyword
      "# made by hand\nOFF # keyword\n\n# counts follow\n3 1 0\n" + body,
      "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n",
      "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n",
      "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
      "STCNOFF\n3 1 0\n0 0 0 0 0 1 1 1 1 1 0 0\n1 0 0 0 0 1 1 1 1 1 0 0\n"
      "0 1 0 0 0 1 1 1 1 1 0 0\n3 0 1 2\n",
      "nOFF\n3\n3 1 0\n" + body,
      "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0.9 0.1 0.1\n",  // per-face color
      "OFF\n3 1 0\n+0 0.0e0 -0\n1. 0 0\n0 1 0\n3 0 1 2",         // no final newline
  };
  for (const std::string& text : variants) {
    SCOPED_TRACE(text);
    const MeshData mesh = readMeshFromMemory(text, "off");
    ASSERT_EQ(mesh.V.rows(), 3);
    ASSERT_EQ(mesh.F.rows(), 1);
    EXPECT_EQ(mesh.V(1, 0), 1.0);
    EXPECT_EQ(mesh.V(2, 1), 1.0);
    EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(mesh.polygons_triangulated, 0);
  }
}

TEST(OffReader, ReadsNanAndInfinityAsIs) {
  const MeshData mesh =
      readMeshFromMemory("OFF\n3 1 0\nnan 0 0\n1 -inf 0\n0 1 1e999\n3 0 1 2\n", "off");
  EXPECT_TRUE(std::isnan(mesh.V(0, 0)));
  EXPECT_TRUE(std::isinf(mesh.V(1, 1)) && mesh.V(1, 1) < 0);
  EXPECT_TRUE(std::isinf(mesh.V(2, 2)) && mesh.V(2, 2) > 0);
}

TEST(OffReader, RejectsBadFacesWithALineNumber) {
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
                 {"line 6", "2 vertices", "at least 3"});
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
                 {"line 6", "refers to vertex 7", "3 vertices"});
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", {"refers to vertex -1"});
  expectOffError("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n3 0 1 2\n",
                 {"line 6", "lists 4 vertices but gives 3"});
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 x\n", {"line 6", "'x'", "vertex index"});
}

TEST(OffReader, RejectsUnparsableNumbers) {
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0.5.5 0\n0 1 0\n3 0 1 2\n", {"line 4", "'0.5.5'"});
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0,5 0\n0 1 0\n3 0 1 2\n", {"line 4", "'0,5'"});
  expectOffError("OFF\nthree 1 0\n", {"vertex count", "'three'"});
  expectOffError("OFF\n3 1 0\n0 0\n1 0 0\n0 1 0\n3 0 1 2\n", {"line 3", "vertex 0 has 2"});
}

TEST(OffReader, NamesTruncationInTheSharedFile) {
  expectError([] { sdp::io::readMesh((kMeshes / "invalid" / "truncated.off").string()); },
              {"truncated.off: ", "file ends after 67 of 299 vertices"});
}

TEST(OffReader, NamesTruncationInFacesAndMissingCounts) {
  expectOffError("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", {"file ends after 1 of 2 faces"});
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1", {"file ends after 0 of 1 faces"});
  expectOffError("OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n", {"file ends after 3 of 4 vertices"});
  expectOffError("OFF\n", {"no vertex/face counts"});
  expectOffError("", {"empty"});
  expectOffError("# only a comment\n", {"empty"});
}

TEST(OffReader, RejectsAbsurdCountsWithoutAllocating) {
  const auto start = std::chrono::steady_clock::now();
  expectOffError("OFF\n1000000000000 1 0\n0 0 0\n",
                 {"file ends after 1 of 1000000000000 vertices"});
  expectOffError("OFF\n3 1000000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                 {"file ends after 1 of 1000000000000 faces"});
  expectOffError("OFF\n99999999999999999999 1 0\n", {"vertex count"});
  expectOffError("OFF\n-3 1 0\n", {"negative vertex count"});
  expectOffError("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n", {"faces"});
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(OffReader, RejectsUnsupportedVariantsAndEmptyMeshes) {
  expectOffError("OFF BINARY\n", {"binary OFF"});
  expectOffError("4OFF\n3 1 0\n", {"4D OFF"});
  expectOffError("nOFF\n2\n3 1 0\n", {"only 3D"});
  expectOffError("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", {"no faces"});
}

TEST(OffReader, LoadsTheBundledMeshes) {
  const MeshData nefertiti = sdp::io::readMesh((kMeshes / "disk" / "nefertiti.off").string());
  EXPECT_EQ(nefertiti.V.rows(), 299);
  EXPECT_EQ(nefertiti.F.rows(), 562);
  EXPECT_EQ(nefertiti.polygons_triangulated, 0);
  EXPECT_TRUE(nefertiti.V.allFinite());

  // Syntactically fine; the core rejects them for what they are.
  const MeshData nan_mesh = sdp::io::readMesh((kMeshes / "invalid" / "nan_vertex.off").string());
  EXPECT_TRUE(std::isnan(nan_mesh.V(4, 1)));
  for (const char* name : {"nonmanifold_edge.off", "two_components.off"}) {
    EXPECT_NO_THROW(sdp::io::readMesh((kMeshes / "invalid" / name).string())) << name;
  }
}

TEST(OffReader, LoadsTheExtraMeshes) {
  SDP_MESH_OR_SKIP(bumpy, "invalid/bumpy.off");
  EXPECT_NO_THROW(sdp::io::readMesh(bumpy));
  SDP_MESH_OR_SKIP(tunnel, "holes/halftunnel_quads.off");
  const MeshData quads = sdp::io::readMesh(tunnel);
  EXPECT_EQ(quads.V.rows(), 831);
  EXPECT_EQ(quads.F.rows(), 2 * 784);
  EXPECT_EQ(quads.polygons_triangulated, 784);
  EXPECT_GE(quads.F.minCoeff(), 0);
  EXPECT_LT(quads.F.maxCoeff(), 831);
}

// ------------------------------------------------------------------------------------------
// OBJ

TEST(ObjReader, ReadsAllCornerFormsAndTriangulatesPolygons) {
  const MeshData mesh = readMeshFromMemory(
      "# comment\nmtllib x.mtl\no thing\ng group\ns 1\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0 0.5 0.5 0.5\nv 0 1 0 1.0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nvp 0.5\nusemtl m\n"
      "f 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\nf 1/1 2/2 3/3 4/3\nf 4 3 2\nl 1 2\n",
      "obj");
  ASSERT_EQ(mesh.V.rows(), 4);
  ASSERT_EQ(mesh.F.rows(), 5);
  EXPECT_EQ(mesh.polygons_triangulated, 1);
  EXPECT_EQ(mesh.V(2, 1), 1.0);
  EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(faceRow(mesh, 1), (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(faceRow(mesh, 2), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(faceRow(mesh, 3), (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(faceRow(mesh, 4), (std::vector<int>{3, 2, 1}));
}

TEST(ObjReader, ResolvesNegativeIndicesAgainstTheVerticesSoFar) {
  const MeshData mesh = readMeshFromMemory(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3/-3 -2/-2 -1/-1\nf 1 -1 3\n", "obj");
  ASSERT_EQ(mesh.F.rows(), 3);
  EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(faceRow(mesh, 1), (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(faceRow(mesh, 2), (std::vector<int>{0, 3, 2}));
}

TEST(ObjReader, AllowsFacesBeforeTheirVertices) {
  const MeshData mesh = readMeshFromMemory("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "obj");
  EXPECT_EQ(mesh.F.rows(), 1);
}

TEST(ObjReader, RejectsBadFacesAndNumbers) {
  const std::string v3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  expectObjError(v3 + "f 1 2 0\n", {"line 4", "index 0"});
  expectObjError(v3 + "f 1 2 9\n", {"line 4", "vertex 9", "3 vertices"});
  expectObjError(v3 + "f -4 1 2\n", {"line 4", "relative index -4"});
  expectObjError(v3 + "f 1 2\n", {"line 4", "2 vertices", "at least 3"});
  expectObjError(v3 + "f 1 2 three\n", {"line 4", "'three'"});
  expectObjError(v3 + "f 1 2 /3\n", {"line 4", "'/3'"});
  expectObjError("v 0 0 zero\n", {"line 1", "'zero'"});
  expectObjError("v 0 0\n", {"line 1", "2 coordinates"});
  expectObjError(v3 + "f 1 2 99999999999\n", {"too large"});
  expectObjError(v3, {"no faces"});
  expectObjError("", {"no faces"});
}

TEST(ObjReader, ReadsNanTokens) {
  const MeshData mesh = readMeshFromMemory("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "obj");
  EXPECT_TRUE(std::isnan(mesh.V(0, 0)));
}

// ------------------------------------------------------------------------------------------
// PLY

TEST(PlyReader, ReadsAsciiAndSkipsOtherProperties) {
  const MeshData mesh = readMeshFromMemory(
      "ply\nformat ascii 1.0\ncomment hello\nobj_info made by hand\n"
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty uchar red\nproperty list uchar float weights\n"
      "element face 2\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
      "property list uchar float texcoord\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n"
      "0 0 0 1 255 0\n1 0 0 1 255 2 0.5 0.5\n1 1 0.5 1 0 1 7\n0 1 nan 1 3 0\n"
      "9 3 0 1 2 6 0 0 1 0 1 1\n0 4 0 2 3 1 0\n"
      "0 1\n",
      "ply");
  ASSERT_EQ(mesh.V.rows(), 4);
  ASSERT_EQ(mesh.F.rows(), 3);
  EXPECT_EQ(mesh.polygons_triangulated, 1);
  EXPECT_EQ(mesh.V(2, 2), 0.5);
  EXPECT_TRUE(std::isnan(mesh.V(3, 2)));
  EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(faceRow(mesh, 1), (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(faceRow(mesh, 2), (std::vector<int>{0, 3, 1}));
}

TEST(PlyReader, AcceptsVertexIndexAndPropertyOrder) {
  const MeshData mesh = readMeshFromMemory(
      "ply\r\nformat ascii 1.0\r\nelement face 1\r\nproperty list uint8 uint32 vertex_index\r\n"
      "element vertex 3\r\nproperty double z\r\nproperty double y\r\nproperty double x\r\n"
      "end_header\r\n3 2 1 0\r\n0 0 0\r\n0 0 1\r\n0 1 0\r\n",
      "ply");
  ASSERT_EQ(mesh.V.rows(), 3);
  EXPECT_EQ(mesh.V(1, 0), 1.0);
  EXPECT_EQ(mesh.V(2, 1), 1.0);
  EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{2, 1, 0}));
}

TEST(PlyReader, ReadsBinaryLittleAndBigEndianOfEveryType) {
  for (const bool big_endian : {false, true}) {
    SCOPED_TRACE(big_endian ? "big endian" : "little endian");
    PlyBuilder ply(big_endian);
    ply.header(
        "element vertex 4\nproperty double x\nproperty float y\nproperty short z\n"
        "property uchar red\nproperty list ushort int8 extra\n"
        "element face 2\nproperty int16 flags\nproperty list uchar uint16 vertex_indices\n"
        "property list int uint texcoord\n");
    const double xs[] = {0, 1.5, 1, -0.25};
    const float ys[] = {0, 0, 1, 1};
    const int16_t zs[] = {0, -3, 7, 32767};
    for (int i = 0; i < 4; ++i) {
      ply.put(xs[i]).put(ys[i]).put(zs[i]).put(uint8_t{200}).put(uint16_t{2});
      ply.put(int8_t{-1}).put(int8_t{1});
    }
    ply.put(int16_t{5}).put(uint8_t{3}).put(uint16_t{0}).put(uint16_t{1}).put(uint16_t{2});
    ply.put(int32_t{1}).put(uint32_t{9});
    ply.put(int16_t{5}).put(uint8_t{4}).put(uint16_t{0}).put(uint16_t{2}).put(uint16_t{3});
    ply.put(uint16_t{1}).put(int32_t{0});
    const MeshData mesh = readMeshFromMemory(ply.bytes(), "ply");
    ASSERT_EQ(mesh.V.rows(), 4);
    ASSERT_EQ(mesh.F.rows(), 3);
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(mesh.V(i, 0), xs[i]);
      EXPECT_EQ(mesh.V(i, 1), ys[i]);
      EXPECT_EQ(mesh.V(i, 2), zs[i]);
    }
    EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(faceRow(mesh, 1), (std::vector<int>{0, 2, 3}));
    EXPECT_EQ(faceRow(mesh, 2), (std::vector<int>{0, 3, 1}));
    EXPECT_EQ(mesh.polygons_triangulated, 1);
  }
}

TEST(PlyReader, ReadsSignedAndUnsignedIndexTypes) {
  for (const char* type : {"int", "uint", "int32", "short", "ushort", "char", "uchar", "uint8"}) {
    SCOPED_TRACE(type);
    PlyBuilder ply(false);
    ply.header(std::string("element vertex 3\nproperty float x\nproperty float y\n") +
               "property float z\nelement face 1\nproperty list uchar " + type +
               " vertex_indices\n");
    for (int i = 0; i < 3; ++i) ply.put(float(i)).put(float(i * i)).put(0.0f);
    ply.put(uint8_t{3});
    const std::string name = type;
    for (int i = 0; i < 3; ++i) {
      if (name == "int" || name == "uint" || name == "int32") {
        ply.put(int32_t(2 - i));
      } else if (name == "short" || name == "ushort") {
        ply.put(int16_t(2 - i));
      } else {
        ply.put(int8_t(2 - i));
      }
    }
    const MeshData mesh = readMeshFromMemory(ply.bytes(), "ply");
    EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{2, 1, 0}));
    EXPECT_EQ(mesh.V(2, 1), 4.0);
  }
}

TEST(PlyReader, NamesTruncationAndBadIndices) {
  PlyBuilder ply(false);
  ply.header(
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\n");
  for (int i = 0; i < 9; ++i) ply.put(float(i));
  ply.put(uint8_t{3}).put(int32_t{0}).put(int32_t{1}).put(int32_t{2});
  const std::string complete_first_face = ply.bytes();
  ply.put(uint8_t{3}).put(int32_t{0});
  expectPlyError(ply.bytes(), {"file ends after 1 of 2 faces"});
  expectPlyError(complete_first_face.substr(0, complete_first_face.size() - 20),
                 {"file ends after 2 of 3 vertices"});

  PlyBuilder bad_index(false);
  bad_index.header(
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\n");
  for (int i = 0; i < 9; ++i) bad_index.put(float(i));
  bad_index.put(uint8_t{3}).put(int32_t{0}).put(int32_t{3}).put(int32_t{2});
  expectPlyError(bad_index.bytes(), {"face 0 refers to vertex 3", "3 vertices"});

  const std::string ascii_header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  expectPlyError(ascii_header + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n", {"face 0 has 2 vertices"});
  expectPlyError(ascii_header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n", {"refers to vertex -1"});
  expectPlyError(ascii_header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 1.5\n", {"refers to vertex 1.5"});
  expectPlyError(ascii_header + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", {"line 11", "'zero'"});
  expectPlyError(ascii_header + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n", {"file ends after 0 of 1 faces"});
}

TEST(PlyReader, RejectsAbsurdCountsAndListLengthsQuickly) {
  const auto start = std::chrono::steady_clock::now();
  expectPlyError(
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0123456789",
      {"file ends after 0 of 4000000000 vertices"});
  expectPlyError(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 99999999999\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
      {"file ends after 1 of 99999999999 faces"});
  PlyBuilder ply(false);
  ply.header(
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uint int vertex_indices\n");
  for (int i = 0; i < 9; ++i) ply.put(float(i));
  ply.put(uint32_t{0xFFFFFFFFu}).put(int32_t{0}).put(int32_t{1}).put(int32_t{2});
  expectPlyError(ply.bytes(), {"file ends after 0 of 1 faces"});
  // An element without properties is counted but never read.
  EXPECT_NO_THROW(readMeshFromMemory(
      "ply\nformat ascii 1.0\nelement nothing 999999999999\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
      "ply"));
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(PlyReader, RejectsMalformedHeaders) {
  const std::string elements =
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  expectPlyError("plz\n", {"not a PLY file"});
  expectPlyError("ply\nformat ascii 1.0\n" + elements, {"no end_header"});
  expectPlyError("ply\nformat ebcdic 1.0\n" + elements + "end_header\n", {"unknown format"});
  expectPlyError("ply\n" + elements + "end_header\n" + body, {"no format line"});
  expectPlyError("ply\nformat ascii 1.0\nproperty float x\n", {"line 3", "before any element"});
  expectPlyError("ply\nformat ascii 1.0\nelement vertex 3\nproperty float128 x\n",
                 {"line 4", "unknown property type 'float128'"});
  expectPlyError("ply\nformat ascii 1.0\nelement vertex 3\nproperty list float int x\n",
                 {"not an integer type"});
  expectPlyError("ply\nformat ascii 1.0\nelement vertex -3\n", {"element count '-3'"});
  expectPlyError("ply\nformat ascii 1.0\nbogus line\n", {"line 3", "'bogus'"});
  expectPlyError(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n",
      {"no scalar property z"});
  expectPlyError(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int corners\nend_header\n" +
          body,
      {"no vertex_indices"});
  expectPlyError(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
      {"no faces"});
  expectPlyError(
      "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n3 0 1 2\n",
      {"no vertex element"});
}

// ------------------------------------------------------------------------------------------
// Dispatch by file name

TEST_F(TempDirTest, ReadMeshDispatchesOnTheExtensionInAnyCase) {
  fs::copy_file(kMeshes / "disk" / "nefertiti.off", dir_ / "Nefertiti.OFF");
  EXPECT_EQ(sdp::io::readMesh((dir_ / "Nefertiti.OFF").string()).V.rows(), 299);
  std::ofstream(dir_ / "tri.Obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(sdp::io::readMesh((dir_ / "tri.Obj").string()).F.rows(), 1);
  std::ofstream(dir_ / "tri.STL") << "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                     "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  EXPECT_EQ(sdp::io::readMesh((dir_ / "tri.STL").string()).F.rows(), 1);
  std::ofstream(dir_ / "tri.3ds") << "x";
  expectError([&] { sdp::io::readMesh((dir_ / "tri.3ds").string()); },
              {"tri.3ds", "unsupported mesh format", ".stl"});
  const std::string missing = (dir_ / "missing.off").string();
  expectError([&] { sdp::io::readMesh(missing); }, {missing, "cannot open"});
  fs::create_directory(dir_ / "folder.off");
  expectError([&] { sdp::io::readMesh((dir_ / "folder.off").string()); }, {"not a regular file"});
  expectError([] { readMeshFromMemory("", "3ds"); }, {"unsupported mesh format '3ds'"});
  EXPECT_EQ(readMeshFromMemory(kSquareAndQuadOff, ".OFF").F.rows(), 4);
  EXPECT_TRUE(sdp::io::isReadableMeshPath("a/b.PLY"));
  EXPECT_FALSE(sdp::io::isReadableMeshPath("a/b.ply.gz"));
}

// ------------------------------------------------------------------------------------------
// STL and PLY tristrips

// Binary STL of `triangles` (each 9 floats), with `header` as the 80-byte header's start.
std::string binaryStl(const std::vector<std::array<float, 9>>& triangles,
                      const std::string& header = "binary") {
  std::string bytes = header;
  bytes.resize(80, ' ');
  const uint32_t count = static_cast<uint32_t>(triangles.size());
  bytes.append(reinterpret_cast<const char*>(&count), 4);  // the test machine is little-endian
  for (const auto& t : triangles) {
    const float normal[3] = {0, 0, 1};
    bytes.append(reinterpret_cast<const char*>(normal), 12);
    bytes.append(reinterpret_cast<const char*>(t.data()), 36);
    bytes.append(2, '\0');
  }
  return bytes;
}

TEST(StlReader, WeldsEqualCornersInBinaryEvenWithSolidInTheHeader) {
  // Two triangles of a square sharing the diagonal; -0 welds with +0; the header says "solid".
  const std::vector<std::array<float, 9>> square = {{0, 0, 0, 1, 0, 0, 1, 1, 0},
                                                    {-0.0f, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (const std::string& header : {std::string("binary"), std::string("solid square")}) {
    const MeshData mesh = readMeshFromMemory(binaryStl(square, header), "stl");
    ASSERT_EQ(mesh.V.rows(), 4) << header;
    ASSERT_EQ(mesh.F.rows(), 2);
    EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(faceRow(mesh, 1), (std::vector<int>{0, 2, 3}));
    EXPECT_TRUE(mesh.notes.empty());
  }
}

TEST(StlReader, ReadsAsciiWithSeveralSolidsAndDropsWeldedTriangles) {
  const std::string text =
      "solid a b\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n"
      "   vertex 1 1 0\n  endloop\n endfacet\nendsolid a b\nsolid\nfacet normal 0 0 1\nouter "
      "loop\nvertex 0 0 0\nvertex 1.0 1 0\nvertex 0 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 0\nvertex 0 1 0\nendloop\n"
      "endfacet\nendsolid\n";
  const MeshData mesh = readMeshFromMemory(text, "stl");
  ASSERT_EQ(mesh.V.rows(), 4);
  ASSERT_EQ(mesh.F.rows(), 2);
  EXPECT_EQ(faceRow(mesh, 1), (std::vector<int>{0, 2, 3}));
  ASSERT_EQ(mesh.notes.size(), 1u);
  EXPECT_NE(mesh.notes[0].find("1 STL triangles with two equal corners"), std::string::npos);
}

TEST(StlReader, AsciiAndBinaryOfTheBundledTorusAreTheSameMesh) {
  const MeshData binary = sdp::io::readMesh((kMeshes / "inputs" / "torus_binary.stl").string());
  const MeshData ascii = sdp::io::readMesh((kMeshes / "inputs" / "torus_ascii.stl").string());
  const MeshData off = sdp::io::readMesh((kMeshes / "closed" / "torus.off").string());
  // Welded back to the torus's vertices (numbered by first use), the faces in file order.
  EXPECT_EQ(binary.V.rows(), off.V.rows());
  ASSERT_EQ(binary.F.rows(), off.F.rows());
  double largest_gap = 0;
  for (Eigen::Index f = 0; f < off.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      largest_gap =
          std::max(largest_gap,
                   (binary.V.row(binary.F(f, k)) - off.V.row(off.F(f, k))).cwiseAbs().maxCoeff());
  EXPECT_LT(largest_gap, 1e-6);  // float coordinates
  EXPECT_EQ(ascii.F, binary.F);
  EXPECT_EQ(ascii.V, binary.V);  // the ASCII file holds the same floats as decimals
}

TEST(StlReader, NamesTruncationAndBadTokens) {
  const std::string full = binaryStl({{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 1, 0, 0, 0, 1}});
  // One byte short: not the size its count says, and not "solid": read as binary, truncated.
  expectError([&] { readMeshFromMemory(full.substr(0, full.size() - 1), "stl"); },
              {"file ends after 1 of 2 triangles"});
  expectError([&] { readMeshFromMemory(full.substr(0, 40), "stl"); }, {"84-byte header"});
  expectError([] { readMeshFromMemory("", "stl"); }, {"file is empty"});
  expectError([] { readMeshFromMemory(binaryStl({}), "stl"); }, {"contains no faces"});
  expectError([] { readMeshFromMemory("solid\nfacet\nouter loop\nvertex 0 0 x\n", "stl"); },
              {"line 4", "cannot read 'x'"});
  expectError([] { readMeshFromMemory("solid\nfacet\nouter loop\nvertex 0 0 0\n", "stl"); },
              {"file ends inside facet 0"});
  expectError([] { readMeshFromMemory("solid\nvertex 0 0 0\n", "stl"); }, {"outside a facet"});
  expectError([] { readMeshFromMemory("solid\nfacet\nvertex 0 0 0\nendfacet\n", "stl"); },
              {"facet 0 has 1 vertices"});
  expectError([] { readMeshFromMemory("solid\nbanana\n", "stl"); }, {"line 2", "'banana'"});
}

TEST(PlyReader, ReadsTristripsWithRestartsAndAlternatingWinding) {
  // Two strips over a 2 x 1 grid of squares (bottom row 0 1 2, top row 3 4 5): 0 1 3 4, then
  // after the -1 restart 1 2 4 5, each giving two triangles wound the same way (the second's
  // first two corners swapped).
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
      "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
      "end_header\n0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n"
      "9 0 1 3 4 -1 1 2 4 5\n";
  const MeshData mesh = readMeshFromMemory(ply, "ply");
  ASSERT_EQ(mesh.F.rows(), 4);
  EXPECT_EQ(faceRow(mesh, 0), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(faceRow(mesh, 1), (std::vector<int>{3, 1, 4}));
  EXPECT_EQ(faceRow(mesh, 2), (std::vector<int>{1, 2, 4}));
  EXPECT_EQ(faceRow(mesh, 3), (std::vector<int>{4, 2, 5}));
  EXPECT_TRUE(mesh.notes.empty());
  // The same strips joined by repeated vertices instead of -1: the same triangles, and the
  // degenerate joins counted.
  std::string joined = ply;
  joined.replace(joined.find("9 0 1 3 4 -1 1 2 4 5"), 20, "10 0 1 3 4 4 1 1 2 4 5");
  const MeshData bridged = readMeshFromMemory(joined, "ply");
  ASSERT_EQ(bridged.F.rows(), 4);
  EXPECT_EQ(bridged.F, mesh.F);
  ASSERT_EQ(bridged.notes.size(), 1u);
  EXPECT_NE(bridged.notes[0].find("4 degenerate tristrip triangles"), std::string::npos);
  // A bad index is named with its strip.
  std::string bad = ply;
  bad.replace(bad.find("9 0 1 3 4 -1"), 12, "9 0 1 3 9 -1");
  expectError([&] { readMeshFromMemory(bad, "ply"); }, {"tristrip 0 refers to vertex 9"});
}

TEST(PlyReader, TristripsOfTheBundledTorusGiveBackItsTriangles) {
  const MeshData strips = sdp::io::readMesh((kMeshes / "inputs" / "torus_tristrips.ply").string());
  const MeshData off = sdp::io::readMesh((kMeshes / "closed" / "torus.off").string());
  ASSERT_EQ(strips.F.rows(), off.F.rows());
  // The same triangles, each with the same winding (as rotations of its corners), in strip order.
  auto canonical = [](const MeshData& m) {
    std::vector<std::array<int, 3>> faces;
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
      std::array<int, 3> t = {m.F(f, 0), m.F(f, 1), m.F(f, 2)};
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      faces.push_back(t);
    }
    std::sort(faces.begin(), faces.end());
    return faces;
  };
  EXPECT_EQ(canonical(strips), canonical(off));
  ASSERT_EQ(strips.notes.size(), 1u);  // the generator joins some strips by repeated vertices
}

// ------------------------------------------------------------------------------------------
// Writers

TEST_F(TempDirTest, ObjRoundTripKeepsPositionsFacesAndTextureCoordinates) {
  const TexturedMesh m = makeTexturedMesh();
  const fs::path obj = dir_ / "patch.obj";
  sdp::io::writeObjWithTexture(obj.string(), m.V, m.F, m.layout(), "patch_checker.png");
  EXPECT_EQ(filesInDir(), (std::vector<std::string>{"patch.mtl", "patch.obj"}));

  const MeshData back = sdp::io::readMesh(obj.string());
  EXPECT_EQ(back.V, m.V);  // shortest round-trip formatting: exact
  EXPECT_EQ(back.F, m.F);

  std::ifstream in(obj);
  std::string line;
  std::vector<std::vector<double>> vt;
  bool mtllib = false, usemtl = false;
  int faces_with_texture = 0;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "vt") {
      double u, v;
      words >> u >> v;
      vt.push_back({u, v});
    } else if (key == "mtllib") {
      std::string name;
      words >> name;
      mtllib = name == "patch.mtl";
    } else if (key == "usemtl") {
      usemtl = true;
    } else if (key == "f") {
      std::string corner;
      int matching = 0;
      while (words >> corner) {
        const size_t slash = corner.find('/');
        matching +=
            slash != std::string::npos && corner.substr(0, slash) == corner.substr(slash + 1);
      }
      faces_with_texture += matching == 3;
    }
  }
  EXPECT_TRUE(mtllib);
  EXPECT_TRUE(usemtl);
  EXPECT_EQ(faces_with_texture, m.F.rows());
  ASSERT_EQ(vt.size(), static_cast<size_t>(m.uv.rows()));
  for (size_t i = 0; i < vt.size(); ++i) {
    EXPECT_EQ(vt[i][0], m.uv(i, 0));
    EXPECT_EQ(vt[i][1], m.uv(i, 1));
  }
  const std::string mtl = readFile(dir_ / "patch.mtl");
  EXPECT_NE(mtl.find("newmtl "), std::string::npos);
  EXPECT_NE(mtl.find("map_Kd patch_checker.png\n"), std::string::npos);
}

// Vertex 4 (the centre) carries another coordinate in face 3 than in the others.
static sdp::Layout seamLayout(const TexturedMesh& m) {
  sdp::Layout layout = m.layout();
  layout.uv.conservativeResize(6, 2);
  layout.uv.row(5) << 0.75, 0.25;
  layout.face_uv(3, 2) = 5;
  return layout;
}

// A seam: vertex 4 (the centre) carries another coordinate in face 3 than in the others; the OBJ
// writes one vt per layout row and `f v/vt` with the row, the PLY each corner's own value.
TEST_F(TempDirTest, WritersKeepASeamPerCorner) {
  const TexturedMesh m = makeTexturedMesh();
  const sdp::Layout layout = seamLayout(m);
  const fs::path obj = dir_ / "seam.obj", ply = dir_ / "seam.ply";
  sdp::io::writeObjWithTexture(obj.string(), m.V, m.F, layout, "t.png");
  sdp::io::writePly(ply.string(), m.V, m.F, layout);

  std::ifstream in(obj);
  std::string line, last_face;
  int vt = 0, v = 0;
  while (std::getline(in, line)) {
    vt += line.rfind("vt ", 0) == 0;
    v += line.rfind("v ", 0) == 0;
    if (line.rfind("f ", 0) == 0) last_face = line;
  }
  EXPECT_EQ(v, 5);
  EXPECT_EQ(vt, 6);
  EXPECT_EQ(last_face, "f 4/4 1/1 5/6");

  const std::string bytes = readFile(ply);
  const size_t body = bytes.find("end_header\n") + 11 + 5 * 3 * 8;
  // Face 3's record: count, 3 ints, count, 6 floats; its last corner's u at the end but one.
  const size_t record = 1 + 12 + 1 + 24;
  float u = 0;
  std::memcpy(&u, bytes.data() + body + 3 * record + record - 8, 4);
  EXPECT_EQ(u, 0.75f);
}

// The readers give the seam back: the OBJ's rows and corners as written, the PLY's per-corner
// values (in float, as written), so a tool's atlas can be scored from its file.
TEST_F(TempDirTest, ReadersGiveBackASeamPerCorner) {
  const TexturedMesh m = makeTexturedMesh();
  const sdp::Layout layout = seamLayout(m);
  const fs::path obj = dir_ / "seam.obj", ply = dir_ / "seam.ply";
  sdp::io::writeObjWithTexture(obj.string(), m.V, m.F, layout, "t.png");
  sdp::io::writePly(ply.string(), m.V, m.F, layout);

  const MeshData from_obj = sdp::io::readMesh(obj.string());
  EXPECT_EQ(from_obj.F, m.F);
  EXPECT_EQ(from_obj.texcoords.uv, layout.uv);
  EXPECT_EQ(from_obj.texcoords.face_uv, layout.face_uv);
  EXPECT_EQ(from_obj.faces_without_texcoords, 0);

  const MeshData from_ply = sdp::io::readMesh(ply.string());
  EXPECT_EQ(from_ply.F, m.F);
  ASSERT_EQ(from_ply.texcoords.face_uv.rows(), m.F.rows());
  for (int f = 0; f < m.F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      for (int axis = 0; axis < 2; ++axis) {
        const float written = static_cast<float>(layout.corner(f, k)[axis]);
        EXPECT_EQ(from_ply.texcoords.corner(f, k)[axis], static_cast<double>(written))
            << "face " << f << " corner " << k;
      }
    }
  }
}

// Polygons keep each corner's coordinate through the fan; corners without one, and references
// that cannot be resolved, read as -1 and leave the mesh readable.
TEST(ObjReader, TexcoordsFollowTheFanAndMissingOnesAreCounted) {
  const MeshData mesh = readMeshFromMemory(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
      "f 1/1 2/2 3/3 4/4\nf 1 2 3\nf 1/9 2/2 3/3\n",
      "obj");
  ASSERT_EQ(mesh.F.rows(), 4);
  ASSERT_EQ(mesh.texcoords.face_uv.rows(), 4);
  EXPECT_EQ(mesh.texcoords.uv.rows(), 4);
  EXPECT_EQ(mesh.texcoords.face_uv.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.texcoords.face_uv.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(mesh.texcoords.face_uv.row(2), Eigen::RowVector3i(-1, -1, -1));
  EXPECT_EQ(mesh.texcoords.face_uv.row(3), Eigen::RowVector3i(-1, 1, 2));
  EXPECT_EQ(mesh.faces_without_texcoords, 2);
  EXPECT_EQ(readMeshFromMemory("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "obj").texcoords.uv.rows(),
            0);
}

TEST(PlyReader, PerVertexTexcoordsBecomeTheCornersOfEachFace) {
  const MeshData mesh = readMeshFromMemory(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float s\nproperty float t\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 0.5 0\n0 1 0 0 0.5\n"
      "3 0 1 2\n",
      "ply");
  ASSERT_EQ(mesh.texcoords.uv.rows(), 3);
  EXPECT_EQ(mesh.texcoords.face_uv.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.texcoords.uv(1, 0), 0.5);
  EXPECT_EQ(mesh.texcoords.uv(2, 1), 0.5);
}

TEST_F(TempDirTest, PlyRoundTripKeepsMeshAndPerWedgeTexcoords) {
  const TexturedMesh m = makeTexturedMesh();
  const fs::path ply = dir_ / "patch.ply";
  sdp::io::writePly(ply.string(), m.V, m.F, m.layout());
  EXPECT_EQ(filesInDir(), (std::vector<std::string>{"patch.ply"}));

  const MeshData back = sdp::io::readMesh(ply.string());
  EXPECT_EQ(back.V, m.V);  // positions are written in double
  EXPECT_EQ(back.F, m.F);

  const std::string bytes = readFile(ply);
  const std::string end = "end_header\n";
  const size_t body = bytes.find(end);
  ASSERT_NE(body, std::string::npos);
  const std::string header = bytes.substr(0, body);
  EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(header.find("property double x\nproperty double y\nproperty double z\n"),
            std::string::npos);
  EXPECT_NE(header.find("property list uchar int vertex_indices\n"
                        "property list uchar float texcoord\n"),
            std::string::npos);
  // Faces follow 5 vertices of 24 bytes: [3][3 x int32][6][6 x float32] each.
  size_t at = body + end.size() + 5 * 24;
  ASSERT_EQ(bytes.size(), at + 4 * (1 + 12 + 1 + 24));
  const auto readLe32 = [&](size_t offset) {
    uint32_t bits = 0;
    for (int b = 0; b < 4; ++b) bits |= uint32_t(uint8_t(bytes[offset + b])) << (8 * b);
    return bits;
  };
  for (int f = 0; f < 4; ++f) {
    ASSERT_EQ(bytes[at], 3);
    at += 13;
    ASSERT_EQ(bytes[at], 6);
    at += 1;
    for (int c = 0; c < 3; ++c) {
      for (int axis = 0; axis < 2; ++axis) {
        const uint32_t bits = readLe32(at);
        float value;
        std::memcpy(&value, &bits, 4);
        EXPECT_EQ(value, static_cast<float>(m.uv(m.F(f, c), axis))) << f << " " << c;
        at += 4;
      }
    }
  }
}

TEST_F(TempDirTest, WritersReplaceExistingFilesAndLeaveNothingOnFailure) {
  const TexturedMesh m = makeTexturedMesh();
  std::ofstream(dir_ / "old.ply") << "old contents";
  sdp::io::writePly((dir_ / "old.ply").string(), m.V, m.F, m.layout());
  EXPECT_EQ(sdp::io::readMesh((dir_ / "old.ply").string()).F.rows(), 4);

  const std::string missing = (dir_ / "no_such_folder" / "out.obj").string();
  expectError([&] { sdp::io::writeObjWithTexture(missing, m.V, m.F, m.layout(), "t.png"); },
              {"cannot write", "out"});
  expectError(
      [&] {
        sdp::io::writePly((dir_ / "no_such_folder" / "o.ply").string(), m.V, m.F, m.layout());
      },
      {"cannot write", "o.ply"});
  expectError(
      [&] {
        sdp::io::writePng((dir_ / "no_such_folder" / "t.png").string(), 1, 1, {0, 0, 0});
      },
      {"cannot write", "t.png"});
  EXPECT_EQ(filesInDir(), (std::vector<std::string>{"old.ply"}));

  sdp::UVs short_uv = m.uv.topRows(2);
  expectError(
      [&] {
        sdp::io::writePly((dir_ / "bad.ply").string(), m.V, m.F,
                          sdp::Layout::perVertex(short_uv, m.F));
      },
      {"missing texture coordinate"});
  expectError(
      [&] {
        sdp::io::writePng((dir_ / "bad.png").string(), 2, 2, {0, 0, 0});
      },
      {"wrong size"});
  EXPECT_EQ(filesInDir(), (std::vector<std::string>{"old.ply"}));

  sdp::io::writeTextFile((dir_ / "report.json").string(), "{}\n");
  EXPECT_EQ(readFile(dir_ / "report.json"), "{}\n");
}

namespace {

struct PngChunk {
  std::string type;
  std::string data;
};

// Splits a PNG into chunks, checking the signature and every CRC.
std::vector<PngChunk> pngChunks(const std::string& png) {
  std::vector<PngChunk> chunks;
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  size_t at = 8;
  const auto be32 = [&](size_t offset) {
    uint32_t value = 0;
    for (int b = 0; b < 4; ++b) value = (value << 8) | uint8_t(png[offset + b]);
    return value;
  };
  while (at + 12 <= png.size()) {
    const uint32_t length = be32(at);
    if (at + 12 + length > png.size()) break;
    PngChunk chunk{png.substr(at + 4, 4), png.substr(at + 8, length)};
    const uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(png.data() + at + 4), 4 + length);
    EXPECT_EQ(be32(at + 8 + length), static_cast<uint32_t>(crc)) << chunk.type;
    chunks.push_back(chunk);
    at += 12 + length;
  }
  EXPECT_EQ(at, png.size());
  return chunks;
}

}  // namespace

TEST_F(TempDirTest, PngHasSignatureSizeValidChunksAndThePixels) {
  const int width = 7, height = 3;
  std::vector<unsigned char> rgb(width * height * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<unsigned char>(i * 37 + 11);
  const fs::path path = dir_ / "image.png";
  sdp::io::writePng(path.string(), width, height, rgb);

  const std::vector<PngChunk> chunks = pngChunks(readFile(path));
  ASSERT_EQ(chunks.size(), 3u);
  EXPECT_EQ(chunks[0].type, "IHDR");
  EXPECT_EQ(chunks[1].type, "IDAT");
  EXPECT_EQ(chunks[2].type, "IEND");
  ASSERT_EQ(chunks[0].data.size(), 13u);
  EXPECT_EQ(chunks[0].data.substr(0, 8), std::string("\0\0\0\x07\0\0\0\x03", 8));
  EXPECT_EQ(chunks[0].data.substr(8), std::string("\x08\x02\0\0\0", 5));

  std::string raw(height * (1 + width * 3), '\0');
  uLongf raw_size = raw.size();
  ASSERT_EQ(
      uncompress(reinterpret_cast<Bytef*>(raw.data()), &raw_size,
                 reinterpret_cast<const Bytef*>(chunks[1].data.data()), chunks[1].data.size()),
      Z_OK);
  ASSERT_EQ(raw_size, raw.size());
  for (int y = 0; y < height; ++y) {
    const size_t row = y * (1 + width * 3);
    EXPECT_EQ(raw[row], 0) << "filter type of row " << y;
    EXPECT_EQ(0, std::memcmp(raw.data() + row + 1, rgb.data() + y * width * 3, width * 3));
  }
}

TEST_F(TempDirTest, CheckerboardPngIsSmall) {
  const int size = 256;
  const fs::path path = dir_ / "checker.png";
  sdp::io::writePng(path.string(), size, size, sdp::checkerboardRGB(size, 8));
  const std::string png = readFile(path);
  const std::vector<PngChunk> chunks = pngChunks(png);
  ASSERT_FALSE(chunks.empty());
  EXPECT_EQ(chunks[0].data.substr(0, 8), std::string("\0\0\x01\0\0\0\x01\0", 8));
  EXPECT_LT(png.size(), size_t{size * size * 3 / 10});  // flat squares compress well
}

// ------------------------------------------------------------------------------------------
// Robustness: mutated inputs end in a mesh or a ParameterizationError, never anything else.

namespace {

std::string mutate(std::string bytes, std::mt19937& random) {
  std::uniform_int_distribution<int> pick(0, 5);
  const int edits = 1 + pick(random);
  for (int e = 0; e < edits && !bytes.empty(); ++e) {
    std::uniform_int_distribution<size_t> position(0, bytes.size() - 1);
    const size_t at = position(random);
    static const char* const kTokens[] = {"-1", "4294967295", "nan", "1e308", "99999999999999",
                                          "\n", " ",          "#",   "/",     "0",
                                          "-",  "list",       "3"};
    switch (pick(random)) {
      case 0:
        bytes[at] = static_cast<char>(random());
        break;
      case 1:
        bytes.resize(at);
        break;
      case 2:
        bytes.insert(at, kTokens[random() % (sizeof kTokens / sizeof *kTokens)]);
        break;
      case 3:
        bytes.erase(at, 1 + random() % 8);
        break;
      case 4:
        bytes.insert(at, bytes.substr(position(random), 1 + random() % 16));
        break;
      default:
        bytes[at] = static_cast<char>(bytes[at] ^ (1 << (random() % 8)));
        break;
    }
  }
  return bytes;
}

}  // namespace

TEST(ReaderRobustness, MutatedFilesGiveAMeshOrAnError) {
  const TexturedMesh m = makeTexturedMesh();
  const fs::path dir =
      fs::temp_directory_path() /
      ("sdp_mesh_io_fuzz_" +
       std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
  fs::create_directories(dir);
  sdp::io::writeObjWithTexture((dir / "m.obj").string(), m.V, m.F, m.layout(), "t.png");
  sdp::io::writePly((dir / "m.ply").string(), m.V, m.F, m.layout());
  const std::vector<std::pair<std::string, std::string>> seeds = {
      {"off", kSquareAndQuadOff},
      {"off", "COFF 3 1\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 1 1 1\n3 0 1 2 1\n"},
      {"obj", readFile(dir / "m.obj")},
      {"obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3/1/1 -2//2 -1\n"},
      {"ply", readFile(dir / "m.ply")},
      {"ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
       "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
  };
  fs::remove_all(dir);

  std::mt19937 random(12345);
  int meshes = 0, errors = 0;
  for (const auto& [format, seed] : seeds) {
    for (int i = 0; i < 400; ++i) {
      const std::string bytes = mutate(seed, random);
      try {
        const MeshData mesh = readMeshFromMemory(bytes, format);
        ++meshes;
        ASSERT_GT(mesh.F.rows(), 0);
        ASSERT_GE(mesh.F.minCoeff(), 0);
        ASSERT_LT(mesh.F.maxCoeff(), mesh.V.rows());
      } catch (const ParameterizationError& e) {
        ++errors;
        const std::string message = e.what();
        ASSERT_EQ(message.find('\n'), std::string::npos) << message;
        ASSERT_EQ(message.rfind("<memory>." + format + ": ", 0), 0u) << message;
      }
    }
  }
  EXPECT_GT(meshes, 0);
  EXPECT_GT(errors, 0);
}
