// End-to-end tests of the straightest_param executable: files in, files + report + exit status
// out (docs/method.md §6).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/atlas/atlas.h"
#include "core/atlas/measure.h"
#include "io/mesh_io.h"
#include "scan_like_mesh.h"
#include "test_mesh_files.h"

namespace fs = std::filesystem;

namespace {

// The meshes that ship with the repository; the larger ones via sdp::test::meshFile.
const fs::path kMeshes = fs::path(SDP_BUNDLED_MESH_DIR);
const std::string kNefertiti = (kMeshes / "disk" / "nefertiti.off").string();

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

std::vector<std::string> linesOf(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string shellQuoted(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// The text after `"key":` in a JSON object (whitespace skipped), up to the next ',' or '}' at
// the same level; empty when the key is missing. Enough for flat scalar values.
std::string jsonValue(const std::string& json, const std::string& key) {
  const size_t at = json.find("\"" + key + "\"");
  if (at == std::string::npos) return "";
  size_t pos = json.find_first_not_of(" \t\r\n", at + key.size() + 2);
  if (pos == std::string::npos || json[pos] != ':') return "";
  pos = json.find_first_not_of(" \t\r\n", pos + 1);
  if (pos == std::string::npos) return "";
  if (json[pos] == '"') {
    const size_t end = json.find('"', pos + 1);
    return json.substr(pos, end == std::string::npos ? std::string::npos : end - pos + 1);
  }
  if (json[pos] == '{' || json[pos] == '[') return json.substr(pos, 1);
  const size_t end = json.find_first_of(",}\n", pos);
  std::string value = json.substr(pos, end - pos);
  while (!value.empty() && std::isspace(static_cast<unsigned char>(value.back()))) {
    value.pop_back();
  }
  return value;
}

struct ToolRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Each test runs the tool in its own folder: out/ for the tool's outputs (must stay empty on
// failure), and the captured stdout/stderr beside it.
class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("sdp_cli_") + info->test_suite_name() + "_" + info->name();
    for (char& c : name) {
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    dir_ =
        fs::temp_directory_path() /
        (name + "_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    out_ = dir_ / "out";
    fs::create_directories(out_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  ToolRun run(const std::vector<std::string>& args) const {
    std::string command = shellQuoted(STRAIGHTEST_PARAM_EXE);
    for (const std::string& arg : args) command += " " + shellQuoted(arg);
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    command += " </dev/null >" + shellQuoted(out.string()) + " 2>" + shellQuoted(err.string());
    ToolRun result;
    const int status = std::system(command.c_str());
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = readFile(out);
    result.err = readFile(err);
    return result;
  }

  std::string outPath(const std::string& name) const { return (out_ / name).string(); }

  std::vector<std::string> outputFiles() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(out_)) {
      names.push_back(entry.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
  }

  // The failure contract: the exit status, one "straightest_param: " line, nothing written.
  void expectFailure(const ToolRun& run, int exit_code, const std::string& reason_part = "") const {
    EXPECT_EQ(run.exit_code, exit_code) << run.err;
    const std::vector<std::string> lines = linesOf(run.err);
    ASSERT_EQ(lines.size(), 1u) << "stderr:\n" << run.err;
    EXPECT_EQ(lines[0].rfind("straightest_param: ", 0), 0u) << lines[0];
    EXPECT_GT(lines[0].size(), std::string("straightest_param: ").size());
    if (!reason_part.empty()) {
      EXPECT_NE(lines[0].find(reason_part), std::string::npos) << lines[0];
    }
    EXPECT_EQ(run.out, "");
    EXPECT_EQ(outputFiles(), std::vector<std::string>{});
  }

  fs::path dir_;
  fs::path out_;
};

void expectReportKeys(const std::string& json) {
  for (const char* key :
       {"l2_stretch", "linf_stretch", "flipped_faces", "fallbacks", "source_vertex", "seconds",
        "vertices", "faces", "weights", "boundary", "stage_seconds"}) {
    EXPECT_FALSE(jsonValue(json, key).empty()) << "report lacks \"" << key << "\":\n" << json;
  }
  EXPECT_EQ(jsonValue(json, "stage_seconds"), "{");
  EXPECT_GE(std::stod(jsonValue(json, "seconds")), 0.0);
  EXPECT_EQ(jsonValue(json, "flipped_faces"), "0");
}

// A 3 x 3 grid of quads (16 vertices, 4 interior): a disk that needs fan-triangulation.
std::string quadGridOff() {
  std::ostringstream off;
  off << "OFF\n16 9 0\n";
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) off << x << " " << y << " " << 0.1 * ((x * y) % 3) << "\n";
  }
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 3; ++x) {
      const int v = 4 * y + x;
      off << "4 " << v << " " << v + 1 << " " << v + 5 << " " << v + 4 << "\n";
    }
  }
  return off.str();
}

}  // namespace

TEST_F(CliTest, NefertitiToObjWritesMeshMaterialTextureAndReport) {
  const std::string obj = outPath("nefertiti.obj");
  const std::string report = outPath("report.json");
  const ToolRun r = run({kNefertiti, obj, "--report", report, "--texture-size", "128"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const std::string& line : linesOf(r.err)) {
    EXPECT_EQ(line.rfind("warning: ", 0), 0u) << line;
  }
  EXPECT_EQ(outputFiles(), (std::vector<std::string>{"nefertiti.mtl", "nefertiti.obj",
                                                     "nefertiti_checker.png", "report.json"}));

  const std::string obj_text = readFile(obj);
  int vt_lines = 0, textured_faces = 0;
  for (const std::string& line : linesOf(obj_text)) {
    vt_lines += line.rfind("vt ", 0) == 0;
    textured_faces += line.rfind("f ", 0) == 0 && std::count(line.begin(), line.end(), '/') == 3;
  }
  EXPECT_EQ(vt_lines, 299);
  EXPECT_EQ(textured_faces, 562);
  EXPECT_NE(obj_text.find("mtllib nefertiti.mtl"), std::string::npos);
  EXPECT_NE(readFile(outPath("nefertiti.mtl")).find("map_Kd nefertiti_checker.png"),
            std::string::npos);

  const std::string png = readFile(outPath("nefertiti_checker.png"));
  ASSERT_GE(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(png.substr(16, 8), std::string("\0\0\0\x80\0\0\0\x80", 8));  // 128 x 128

  const sdp::io::MeshData back = sdp::io::readMesh(obj);
  EXPECT_EQ(back.V.rows(), 299);
  EXPECT_EQ(back.F.rows(), 562);

  expectReportKeys(r.out);
  EXPECT_EQ(jsonValue(r.out, "vertices"), "299");
  EXPECT_EQ(jsonValue(r.out, "faces"), "562");
  EXPECT_EQ(jsonValue(r.out, "weights"), "\"straightest\"");
  EXPECT_EQ(jsonValue(r.out, "boundary"), "\"measured\"");
  EXPECT_EQ(readFile(report), r.out);
}

TEST_F(CliTest, NefertitiToPlyQuietly) {
  const std::string ply = outPath("flat.ply");
  const ToolRun r = run({kNefertiti, ply, "--weights", "ltd", "--boundary", "circle", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(outputFiles(), std::vector<std::string>{"flat.ply"});
  const std::string bytes = readFile(ply);
  EXPECT_NE(bytes.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(bytes.find("property list uchar float texcoord\n"), std::string::npos);
  const sdp::io::MeshData back = sdp::io::readMesh(ply);
  EXPECT_EQ(back.V.rows(), 299);
  EXPECT_EQ(back.F.rows(), 562);
}

class CliWeights : public CliTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(CliWeights, ReportsTheSchemeAskedFor) {
  const ToolRun r = run({kNefertiti, outPath("m.ply"), "--weights", GetParam(), "--boundary",
                         "circle", "--source", "-1", "--stretch-iterations=0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectReportKeys(r.out);
  EXPECT_EQ(jsonValue(r.out, "weights"), std::string("\"") + GetParam() + "\"");
  EXPECT_EQ(jsonValue(r.out, "boundary"), "\"circle\"");
}

INSTANTIATE_TEST_SUITE_P(AllSchemes, CliWeights,
                         ::testing::Values("straightest", "ltd", "floater", "mean_value",
                                           "uniform"));

class CliBoundaries : public CliTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(CliBoundaries, ReportsTheBoundaryAskedFor) {
  const ToolRun r = run({kNefertiti, outPath("m.obj"), "--boundary", GetParam(), "--texture-size",
                         "16", "--checkers", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectReportKeys(r.out);
  EXPECT_EQ(jsonValue(r.out, "boundary"), std::string("\"") + GetParam() + "\"");
}

INSTANTIATE_TEST_SUITE_P(AllShapes, CliBoundaries,
                         ::testing::Values("measured", "circle", "square"));

TEST_F(CliTest, SourceOptionsReachTheCore) {
  ToolRun r = run({kNefertiti, outPath("a.ply"), "--source-rule", "centroid"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string automatic = jsonValue(r.out, "source_vertex");
  ASSERT_FALSE(automatic.empty());
  EXPECT_NE(automatic, "-1");  // the measured boundary has a source

  r = run({kNefertiti, outPath("b.ply"), "--source", automatic});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(jsonValue(r.out, "source_vertex"), automatic);
}

TEST_F(CliTest, StretchIterationsRun) {
  const ToolRun r = run({kNefertiti, outPath("m.ply"), "--stretch-iterations", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  expectReportKeys(r.out);
  EXPECT_NE(jsonValue(r.out, "free_boundary_steps"), "0");  // the boundary moves by default
}

TEST_F(CliTest, FixedBoundaryKeepsTheBoundary) {
  const ToolRun r =
      run({kNefertiti, outPath("m.ply"), "--stretch-iterations", "2", "--fixed-boundary"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(jsonValue(r.out, "free_boundary_steps"), "0");
  EXPECT_EQ(jsonValue(r.out, "l2_stretch"), jsonValue(r.out, "l2_stretch_fixed_boundary"));
}

TEST_F(CliTest, QuadMeshIsTriangulatedWithAWarning) {
  const fs::path input = dir_ / "grid.off";
  std::ofstream(input) << quadGridOff();
  const ToolRun r = run({input.string(), outPath("grid.obj"), "--boundary", "circle"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = linesOf(r.err);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "warning: 9 polygons with more than 3 vertices were fan-triangulated");
  EXPECT_EQ(jsonValue(r.out, "faces"), "18");
}

// Whether a patch with holes is flattened (holes filled) or refused is the core's policy; either
// way the tool keeps its contract, and the triangulation warning comes first on success.
TEST_F(CliTest, QuadMeshWithHolesSucceedsOrFailsCleanly) {
  SDP_MESH_OR_SKIP(input, "holes/halftunnel_quads.off");
  const ToolRun r = run({input, outPath("tunnel.obj"), "--texture-size", "16"});
  if (r.exit_code != 0) {
    expectFailure(r, 1);
    return;
  }
  const std::vector<std::string> lines = linesOf(r.err);
  ASSERT_FALSE(lines.empty());
  EXPECT_EQ(lines[0], "warning: 784 polygons with more than 3 vertices were fan-triangulated");
  for (const std::string& line : lines) EXPECT_EQ(line.rfind("warning: ", 0), 0u) << line;
  expectReportKeys(r.out);
  EXPECT_EQ(outputFiles(),
            (std::vector<std::string>{"tunnel.mtl", "tunnel.obj", "tunnel_checker.png"}));
}

TEST_F(CliTest, ReadsObjAndPlyInput) {
  const std::string ply = outPath("first.ply");
  ASSERT_EQ(run({kNefertiti, ply, "--quiet"}).exit_code, 0);
  const ToolRun from_ply = run({ply, outPath("second.obj"), "--texture-size", "16"});
  ASSERT_EQ(from_ply.exit_code, 0) << from_ply.err;
  const ToolRun from_obj = run({outPath("second.obj"), outPath("third.ply")});
  ASSERT_EQ(from_obj.exit_code, 0) << from_obj.err;
  EXPECT_EQ(jsonValue(from_obj.out, "vertices"), "299");
}

class CliInvalidMesh : public CliTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(CliInvalidMesh, FailsWithOneLineAndNoOutput) {
  SDP_MESH_OR_SKIP(input, GetParam());
  const std::string report = outPath("report.json");
  expectFailure(run({input, outPath("m.obj"), "--report", report}), 1);
  expectFailure(run({input, outPath("m.ply"), "--report", report}), 1);
}

INSTANTIATE_TEST_SUITE_P(SharedFiles, CliInvalidMesh,
                         ::testing::Values("invalid/truncated.off", "invalid/nan_vertex.off",
                                           "invalid/nonmanifold_edge.off",
                                           "invalid/two_components.off", "invalid/bumpy.off",
                                           "invalid/3holes.off"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = fs::path(info.param).stem().string();
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

TEST_F(CliTest, TruncatedFileReasonNamesTheProblem) {
  const ToolRun r = run({(kMeshes / "invalid" / "truncated.off").string(), outPath("m.obj")});
  expectFailure(r, 1, "truncated.off: file ends after 67 of 299 vertices");
}

TEST_F(CliTest, BadWeightsIsAUsageError) {
  const ToolRun r = run({kNefertiti, outPath("m.obj"), "--weights", "bogus"});
  expectFailure(r, 2, "'bogus'");
  EXPECT_NE(r.err.find("mean_value"), std::string::npos) << r.err;  // lists the valid names
}

TEST_F(CliTest, CommandLineMistakesAreUsageErrors) {
  const std::string obj = outPath("m.obj");
  const std::vector<std::vector<std::string>> mistakes = {
      {},
      {kNefertiti},
      {kNefertiti, obj, "extra.obj"},
      {kNefertiti, outPath("m.stl")},
      {outPath("in.3ds"), obj},
      {kNefertiti, obj, "--bogus"},
      {kNefertiti, obj, "--weights"},
      {kNefertiti, obj, "--boundary", "hexagon"},
      {kNefertiti, obj, "--source-rule", "random"},
      {kNefertiti, obj, "--source", "abc"},
      {kNefertiti, obj, "--source", "-2"},
      {kNefertiti, obj, "--stretch-iterations", "-1"},
      {kNefertiti, obj, "--stretch-iterations", "1.5"},
      {kNefertiti, obj, "--checkers", "0"},
      {kNefertiti, obj, "--texture-size", "99999999"},
      {kNefertiti, obj, "--report", ""},
      {kNefertiti, obj, "--", "--quiet"},  // after "--" it is a third file name
  };
  for (const auto& args : mistakes) {
    std::string joined;
    for (const auto& a : args) joined += a + " ";
    SCOPED_TRACE(joined);
    expectFailure(run(args), 2);
  }
}

TEST_F(CliTest, DoubleDashEndsTheOptions) {
  const ToolRun r = run({"--quiet", "--", kNefertiti, outPath("m.ply")});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(outputFiles(), std::vector<std::string>{"m.ply"});
}

TEST_F(CliTest, MissingInputFails) {
  expectFailure(run({(dir_ / "missing.off").string(), outPath("m.obj")}), 1, "missing.off");
}

TEST_F(CliTest, SourceOutOfRangeFails) {
  expectFailure(run({kNefertiti, outPath("m.obj"), "--source", "100000"}), 1);
}

TEST_F(CliTest, UnwritableOutputLeavesNothingBehind) {
  const std::string report = outPath("report.json");
  const ToolRun r = run({kNefertiti, outPath("no_such_folder/m.obj"), "--report", report});
  expectFailure(r, 1, "no_such_folder");
  // The report folder exists, yet no report is written for a failed run.
  EXPECT_FALSE(fs::exists(report));
  // A report that cannot be written takes the mesh outputs with it.
  expectFailure(run({kNefertiti, outPath("m.ply"), "--report", outPath("none/r.json")}), 1,
                "r.json");
}

TEST_F(CliTest, FailureKeepsAnExistingOutputUntouched) {
  std::ofstream(outPath("m.obj")) << "previous";
  const ToolRun r = run({(kMeshes / "invalid" / "two_components.off").string(), outPath("m.obj")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(linesOf(r.err).size(), 1u) << r.err;
  EXPECT_EQ(readFile(outPath("m.obj")), "previous");
  EXPECT_EQ(outputFiles(), std::vector<std::string>{"m.obj"});
}

TEST_F(CliTest, HelpAndVersion) {
  const ToolRun help = run({"--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_EQ(help.out.rfind("usage: straightest_param IN OUT", 0), 0u) << help.out;
  for (const char* option :
       {"--weights", "--boundary", "--source", "--source-rule", "--stretch-iterations", "--report",
        "--checkers", "--texture-size", "--quiet", "--version"}) {
    EXPECT_NE(help.out.find(option), std::string::npos) << option;
  }
  EXPECT_EQ(help.err, "");
  const ToolRun version = run({"--version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out.rfind("straightest_param ", 0), 0u) << version.out;
  EXPECT_EQ(linesOf(version.out).size(), 1u);
}

namespace {

// A closed octahedron, split once (18 vertices, 32 faces): no boundary, so only --atlas takes it.
std::string closedOff() {
  std::ostringstream off;
  const double v[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                       {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  off << "OFF\n6 8 0\n";
  for (const auto& p : v) off << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const auto& t : f) off << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
  return off.str();
}

}  // namespace

TEST_F(CliTest, ProgressPrintsTheCallbacksCallsFromZeroToAHundred) {
  const std::string in = (dir_ / "closed.off").string();
  std::ofstream(in) << closedOff();
  for (const bool atlas : {true, false}) {
    std::vector<std::string> args = {in, outPath("a.ply"), "--progress", "--quiet"};
    if (atlas)
      args.push_back("--atlas");
    else
      args[0] = kNefertiti;
    const ToolRun r = run(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::vector<int> percents;
    for (const std::string& line : linesOf(r.err)) {
      char stage[64];
      int percent = -1;
      double seconds = -1;
      if (std::sscanf(line.c_str(), "progress %63s %d%% %lf", stage, &percent, &seconds) == 3) {
        EXPECT_GE(seconds, 0) << line;
        percents.push_back(percent);
      }
    }
    ASSERT_GE(percents.size(), 3u) << r.err;
    if (atlas) {
      EXPECT_EQ(percents.front(), 0);
      EXPECT_TRUE(std::is_sorted(percents.begin(), percents.end())) << r.err;
    }
    EXPECT_EQ(percents.back(), 100) << r.err;
    if (!atlas) continue;
    // The atlas's stage bars (what MeshLab shows): every stage in run order, each bar moving
    // only forward, the last full.
    std::vector<std::string> stages;
    int last_stage_percent = -1, last_run_percent = -1;
    for (const std::string& line : linesOf(r.err)) {
      char stage[64];
      int stage_percent = -1, run_percent = -1;
      double seconds = -1;
      if (std::sscanf(line.c_str(), "stage %63s %d%% %d%% %lf", stage, &stage_percent, &run_percent,
                      &seconds) != 4)
        continue;
      if (stages.empty() || stages.back() != stage) {
        stages.push_back(stage);
      } else {
        EXPECT_GT(stage_percent, last_stage_percent) << line;
      }
      EXPECT_GE(run_percent, last_run_percent) << line;
      EXPECT_LE(stage_percent, 100) << line;
      last_stage_percent = stage_percent, last_run_percent = run_percent;
    }
    std::vector<std::string> expected;
    for (const sdp::atlas::AtlasStage& stage : sdp::atlas::kAtlasStages)
      expected.push_back(stage.name);
    EXPECT_EQ(stages, expected) << r.err;
    EXPECT_EQ(last_stage_percent, 100);
    EXPECT_EQ(last_run_percent, 100);
  }
}

TEST_F(CliTest, AtlasOfAClosedMeshWritesTexturedObjAndReport) {
  const std::string in = (dir_ / "closed.off").string();
  std::ofstream(in) << closedOff();
  // Without --atlas the patch filter refuses it and names the atlas.
  expectFailure(run({in, outPath("p.obj")}), 1, "--atlas");
  const ToolRun r = run(
      {in, outPath("a.obj"), "--atlas", "--texture-size", "256", "--report", outPath("r.json")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(outputFiles(), (std::vector<std::string>{"a.mtl", "a.obj", "a_atlas.png", "r.json"}));
  for (const char* key :
       {"charts", "seam", "packing_efficiency", "l2_stretch", "linf_stretch", "flipped_faces",
        "overlapping_charts", "seconds", "stage_seconds", "stage_cpu_seconds", "texels_per_unit",
        "non_manifold_edges", "chart_table"})
    EXPECT_FALSE(jsonValue(r.out, key).empty()) << key << "\n" << r.out;
  EXPECT_EQ(jsonValue(r.out, "flipped_faces"), "0");
  EXPECT_EQ(jsonValue(r.out, "overlapping_charts"), "0");
  EXPECT_EQ(jsonValue(r.out, "texture_size"), "256");
  EXPECT_EQ(jsonValue(r.out, "gutter"), "2");
  EXPECT_GE(std::stoi(jsonValue(r.out, "charts")), 2);  // closed: at least one cut
  int vt = 0, faces = 0;
  for (const std::string& line : linesOf(readFile(outPath("a.obj")))) {
    vt += line.rfind("vt ", 0) == 0;
    faces += line.rfind("f ", 0) == 0 && std::count(line.begin(), line.end(), '/') == 3;
  }
  EXPECT_GT(vt, 6);  // seams split: more texture coordinates than vertices
  EXPECT_EQ(faces, 8);
  EXPECT_EQ(readFile(outPath("r.json")), r.out);
}

TEST_F(CliTest, AtlasPlyCarriesTheChartPerFace) {
  const ToolRun r = run({(kMeshes / "invalid" / "two_components.off").string(), outPath("a.ply"),
                         "--atlas", "--gutter", "4", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string bytes = readFile(outPath("a.ply"));
  EXPECT_NE(bytes.find("property list uchar float texcoord\nproperty int chart\n"),
            std::string::npos);
}

TEST_F(CliTest, AtlasOptionsNeedAtlasAndBadInputFailsCleanly) {
  expectFailure(run({kNefertiti, outPath("m.obj"), "--gutter", "2"}), 2, "--atlas option");
  expectFailure(run({kNefertiti, outPath("m.obj"), "--atlas", "--gutter", "99"}), 2, "--gutter");
  expectFailure(
      run({(kMeshes / "invalid" / "nan_vertex.off").string(), outPath("m.obj"), "--atlas"}), 1,
      "not finite");
  expectFailure(
      run({(kMeshes / "invalid" / "truncated.off").string(), outPath("m.ply"), "--atlas"}), 1,
      "truncated.off");
}

namespace {

// An atlas the CLI wrote to `path`, read back and measured from the file (gutter 2): every one
// of `faces` faces has texture coordinates, no pixel is covered twice, the gutter is kept, every
// UV is in [0,1]^2, and the charts are the `charts` the report gave. The measures go to
// `measures` for the caller's own checks.
void expectAtlasAsStored(const std::string& path, Eigen::Index faces, int texture_size, int charts,
                         sdp::atlas::AtlasMeasures* measures = nullptr) {
  SCOPED_TRACE(path);
  const sdp::io::MeshData stored = sdp::io::readMesh(path);
  ASSERT_EQ(stored.F.rows(), faces);
  ASSERT_EQ(stored.texcoords.face_uv.rows(), stored.F.rows());
  EXPECT_EQ(stored.faces_without_texcoords, 0);
  const sdp::atlas::AtlasMeasures m =
      sdp::atlas::measureAtlas(stored.V, stored.F, stored.texcoords, texture_size, 2);
  EXPECT_EQ(m.overlapping_pixels, 0);
  EXPECT_EQ(m.gutter_violations, 0);
  EXPECT_EQ(m.outside_faces, 0);
  EXPECT_EQ(m.charts, charts);
  if (measures != nullptr) *measures = m;
}

}  // namespace

// Every everyday input kind of resources/meshes/inputs (scripts/make-input-meshes.py): polygon
// meshes, STL binary and ASCII, PLY tristrips, faces wound against their neighbours. Each gets
// an atlas that is one-to-one as stored, read back from the written file and measured there:
// every face charted, no pixel covered twice, the gutter kept, every UV in [0,1]^2.
class CliInputKinds : public CliTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(CliInputKinds, AtlasIsOneToOneAsStoredInObjAndPly) {
  const std::string in = (kMeshes / "inputs" / GetParam()).string();
  const sdp::io::MeshData input = sdp::io::readMesh(in);
  for (const char* out_name : {"a.obj", "a.ply"}) {
    const ToolRun r = run({in, outPath(out_name), "--atlas", "--texture-size", "1024"});
    ASSERT_EQ(r.exit_code, 0) << out_name << ": " << r.err;
    EXPECT_EQ(jsonValue(r.out, "flipped_faces"), "0") << out_name;
    EXPECT_EQ(jsonValue(r.out, "overlapping_charts"), "0") << out_name;
    expectAtlasAsStored(outPath(out_name), input.F.rows(), 1024,
                        std::stoi(jsonValue(r.out, "charts")));
  }
}

INSTANTIATE_TEST_SUITE_P(Inputs, CliInputKinds,
                         ::testing::Values("cube_quads.off", "cube_triangles_quads.off",
                                           "cube_triangles_quads_triangle.off",
                                           "prism_hexagons.off", "torus_quads.off",
                                           "torus_binary.stl", "torus_ascii.stl",
                                           "torus_tristrips.ply", "torus_random_winding.off"));

TEST_F(CliTest, StlAndTristripsReadAsTheSameMeshAsTheirSource) {
  const std::string dir = (kMeshes / "inputs").string();
  for (const char* name : {"torus_binary.stl", "torus_ascii.stl", "torus_tristrips.ply"}) {
    const ToolRun r = run(
        {dir + "/" + name, outPath("a.ply"), "--atlas", "--quiet", "--report", outPath("r.json")});
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    const std::string report = readFile(outPath("r.json"));
    EXPECT_EQ(jsonValue(report, "vertices"), "384") << name;
    EXPECT_EQ(jsonValue(report, "faces"), "768") << name;
    EXPECT_EQ(jsonValue(report, "components"), "1") << name;
    EXPECT_EQ(jsonValue(report, "inconsistent_edges"), "0") << name;
  }
  // A file of another kind is a usage error that names STL among the readable ones.
  fs::remove_all(out_);
  fs::create_directories(out_);
  std::ofstream(dir_ / "m.3ds") << "x";
  expectFailure(run({(dir_ / "m.3ds").string(), outPath("a.ply")}), 2, ".stl");
}

TEST_F(CliTest, UvStorageChoosesThePrecisionTheMapIsCertifiedIn) {
  const std::string torus = (kMeshes / "closed" / "torus.off").string();
  const auto storage = [&](const std::vector<std::string>& extra, const std::string& out) {
    std::vector<std::string> args = {torus, outPath(out), "--atlas", "--texture-size", "256"};
    args.insert(args.end(), extra.begin(), extra.end());
    const ToolRun r = run(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return jsonValue(r.out, "storage");
  };
  EXPECT_EQ(storage({}, "a.ply"), "\"float\"");  // the output's own
  EXPECT_EQ(storage({}, "a.obj"), "\"double\"");
  EXPECT_EQ(storage({"--uv-storage", "float6"}, "b.obj"), "\"float, 6 decimals\"");
  EXPECT_EQ(storage({"--uv-storage=float"}, "c.obj"), "\"float\"");
  fs::remove_all(out_);
  fs::create_directories(out_);
  expectFailure(run({torus, outPath("e.obj"), "--atlas", "--uv-storage", "half"}), 2,
                "--uv-storage");
  // PLY holds floats: a map certified in double would not be one-to-one as stored.
  expectFailure(run({torus, outPath("d.ply"), "--atlas", "--uv-storage", "double"}), 2,
                "PLY stores texture coordinates as float");
}

#if defined(__SANITIZE_ADDRESS__)  // GCC
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)  // Clang
constexpr bool kAddressSanitizer = __has_feature(address_sanitizer);
#else
constexpr bool kAddressSanitizer = false;
#endif

// A scan-like mesh (scan_like_mesh.h: the bundled torus subdivided to 49k faces, noise along the
// normals, holes, debris) gets an atlas in every storage a front end uses: float (PLY, MeshLab),
// float with 6 decimals (OBJ as MeshLab writes it) and double (OBJ). Each is read back from the
// written file and measured there; and noise does not multiply the charts of its noise-free twin.
TEST_F(CliTest, ScanLikeMeshIsOneToOneInEveryStorage) {
  const sdp::io::MeshData torus = sdp::io::readMesh((kMeshes / "closed" / "torus.off").string());
  int twin_charts = 0;
  for (const double sigma : {0.0, 0.15}) {
    sdp::Positions V = torus.V;
    sdp::Triangles F = torus.F;
    sdp::test::ScanLikeOptions options;
    options.sigma = sigma;
    if (kAddressSanitizer) options.subdivisions = 2;  // 12k faces: that build is ~10x slower
    sdp::test::makeScanLike(V, F, options);
    const std::string in = outPath(sigma > 0 ? "scan.off" : "twin.off");
    ASSERT_TRUE(sdp::test::writeOff(in, V, F));
    std::vector<std::pair<std::string, std::vector<std::string>>> runs = {{"twin.ply", {}}};
    if (sigma > 0)
      runs = {{"float.ply", {}}, {"float6.obj", {"--uv-storage", "float6"}}, {"double.obj", {}}};
    for (const auto& [out_name, extra] : runs) {
      std::vector<std::string> args = {in, outPath(out_name), "--atlas", "--texture-size", "4096"};
      args.insert(args.end(), extra.begin(), extra.end());
      const ToolRun r = run(args);
      ASSERT_EQ(r.exit_code, 0) << out_name << ": " << r.err;
      const int charts = std::stoi(jsonValue(r.out, "charts"));
      if (sigma == 0) {
        twin_charts = charts;
        continue;
      }
      sdp::atlas::AtlasMeasures m;
      expectAtlasAsStored(outPath(out_name), F.rows(), 4096, charts, &m);
      if (HasFatalFailure()) return;
      EXPECT_EQ(m.flipped_faces, 0) << out_name;
      EXPECT_EQ(m.mirrored_charts, 0) << out_name;
      EXPECT_LE(m.l2, 1.05) << out_name;
      EXPECT_LE(charts, 1.5 * twin_charts) << out_name << ": " << twin_charts << " without noise";
    }
  }
}
