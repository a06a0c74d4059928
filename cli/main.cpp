// straightest_param: flattens a disk-shaped mesh patch from the command line (docs/method.md §6).
//
// Contract with scripts: exit 0 and the report JSON on stdout on success; otherwise exactly one
// line "straightest_param: <reason>" on stderr, exit 2 for usage errors and 1 for everything
// else, and no output file left behind.
#include <cctype>
#include <charconv>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <limits>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "checkerboard.h"
#include "core/parameterize.h"
#include "mesh_io.h"

#ifndef SDP_VERSION
#define SDP_VERSION "unknown"
#endif

namespace {

namespace fs = std::filesystem;

constexpr const char* kProgram = "straightest_param";
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

constexpr const char* kUsage =
    R"(usage: straightest_param IN OUT [options]

Flattens a disk-shaped triangle patch to the plane by straightest distances.
IN is a .off, .obj or .ply mesh (polygons are fan-triangulated). OUT ending in .obj gets
OBJ + MTL + a checkerboard PNG <stem>_checker.png next to it; .ply gets a binary PLY.
Both carry per-wedge texture coordinates. The report (JSON) is printed to stdout.

options:
  --weights W             straightest (default), ltd, floater, mean_value, uniform
  --boundary B            measured (default), circle, square
  --source N              source vertex index of the measured boundary (default: automatic)
  --source-rule R         automatic source: farthest (from the boundary, default) or centroid
                          (nearest the centroid of the boundary vertices)
  --stretch-iterations K  most stretch-minimizing refinement steps per stage (default 10;
                          0: the paper's linear map). A stage also ends at a step that lowers
                          the L2 stretch by less than 0.1%, or when the time budget is used
  --time-budget F         refinement may take F times the linear map's time, at least 1.5 s
                          (default 2; 0: no time limit, the same map on every machine)
  --fixed-boundary        refinement keeps the measured boundary where it is (default: after
                          the reweighting, K checked steps that let it move too, then on patches
                          up to 50k vertices K Newton steps on the stretch; circle and square
                          boundaries always stay)
  --outer-vertex N        patches with holes: a vertex on the loop to use as the outer
                          boundary (default: the longest loop; the others are filled virtually)
  --report FILE.json      also write the report to FILE.json
  --checkers N            checkerboard squares per side (default 16)
  --texture-size PX       checkerboard PNG width and height in pixels (default 1024)
  --natural-scale         write UVs at the solver's scale (measured: area equal to the
                          mesh's) instead of fitted into [0,1]
  --quiet                 do not print the report
  --help                  show this help
  --version               show the version
  --                      end of options (for file names starting with '-')

exit status: 0 success, 1 failure (bad mesh, I/O error, ...), 2 bad command line
)";

// A bad command line: exit status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Arguments {
  std::string input;
  std::string output;
  std::string report_path;  // empty: no report file
  sdp::Options options = sdp::productDefaults();
  int checkers = 16;
  int texture_size = 1024;
  bool quiet = false;
  bool natural_scale = false;
};

std::string lowercaseExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

int parseIntOption(const std::string& option, const std::string& value, int low, int high) {
  int parsed = 0;
  const char* end = value.data() + value.size();
  const auto [ptr, ec] = std::from_chars(value.data(), end, parsed);
  if (ec != std::errc() || ptr != end || value.empty()) {
    throw UsageError(option + " needs an integer, got '" + value + "'");
  }
  if (parsed < low || parsed > high) {
    throw UsageError(option + " must be between " + std::to_string(low) + " and " +
                     std::to_string(high) + ", got " + value);
  }
  return parsed;
}

std::string namesOf(const char* (*name)(int), int count) {
  std::string names;
  for (int i = 0; i < count; ++i) names += std::string(i ? ", " : "") + name(i);
  return names;
}

const char* weightName(int i) {
  return sdp::weightSchemeName(static_cast<sdp::WeightScheme>(i));
}
const char* boundaryName(int i) {
  return sdp::boundaryShapeName(static_cast<sdp::BoundaryShape>(i));
}

enum class Action { Run, Help, Version };

Action parseArguments(int argc, char** argv, Arguments& args) {
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    if (arg == "--help" || arg == "-h") return Action::Help;
    if (arg == "--version") return Action::Version;
  }
  bool options_ended = false;  // after "--" every argument is a file name
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (options_ended || arg.size() < 2 || arg[0] != '-') {
      positional.push_back(arg);
      continue;
    }
    if (arg == "--") {
      options_ended = true;
      continue;
    }
    if (arg == "--quiet") {
      args.quiet = true;
      continue;
    }
    if (arg == "--natural-scale") {
      args.natural_scale = true;
      continue;
    }
    if (arg == "--fixed-boundary") {
      args.options.free_boundary = false;
      continue;
    }
    // "--name value" or "--name=value".
    std::optional<std::string> inline_value;
    if (const size_t eq = arg.find('='); eq != std::string::npos) {
      inline_value = arg.substr(eq + 1);
      arg.resize(eq);
    }
    const auto value = [&]() -> std::string {
      if (inline_value) return *inline_value;
      if (i + 1 >= argc) throw UsageError(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--weights") {
      const std::string v = value();
      const auto weights = sdp::parseWeightScheme(v);
      if (!weights) {
        throw UsageError("unknown --weights '" + v + "' (expected one of " +
                         namesOf(weightName, sdp::kWeightSchemeCount) + ")");
      }
      args.options.weights = *weights;
    } else if (arg == "--boundary") {
      const std::string v = value();
      const auto boundary = sdp::parseBoundaryShape(v);
      if (!boundary) {
        throw UsageError("unknown --boundary '" + v + "' (expected one of " +
                         namesOf(boundaryName, sdp::kBoundaryShapeCount) + ")");
      }
      args.options.boundary = *boundary;
    } else if (arg == "--source-rule") {
      const std::string v = value();
      const auto rule = sdp::parseSourceRule(v);
      if (!rule)
        throw UsageError("unknown --source-rule '" + v + "' (expected farthest or centroid)");
      args.options.source_rule = *rule;
    } else if (arg == "--source") {
      args.options.source_vertex =
          parseIntOption(arg, value(), -1, std::numeric_limits<int>::max());
    } else if (arg == "--outer-vertex") {
      args.options.outer_boundary_vertex =
          parseIntOption(arg, value(), -1, std::numeric_limits<int>::max());
    } else if (arg == "--stretch-iterations") {
      args.options.stretch_iterations = parseIntOption(arg, value(), 0, 1000);
    } else if (arg == "--time-budget") {
      args.options.refine_time_factor = parseIntOption(arg, value(), 0, 1000);
    } else if (arg == "--report") {
      args.report_path = value();
      if (args.report_path.empty()) throw UsageError("--report needs a file name");
    } else if (arg == "--checkers") {
      args.checkers = parseIntOption(arg, value(), 1, 512);
    } else if (arg == "--texture-size") {
      args.texture_size = parseIntOption(arg, value(), 8, 8192);
    } else {
      throw UsageError("unknown option " + arg + " (see --help)");
    }
  }
  if (positional.size() != 2) {
    throw UsageError(positional.size() < 2 ? "needs IN and OUT mesh files (see --help)"
                                           : "too many arguments: '" + positional[2] + "'");
  }
  args.input = positional[0];
  args.output = positional[1];
  if (!sdp::io::isReadableMeshPath(args.input)) {
    throw UsageError("IN must be a .off, .obj or .ply file: " + args.input);
  }
  const std::string out_ext = lowercaseExtension(args.output);
  if (out_ext != ".obj" && out_ext != ".ply") {
    throw UsageError("OUT must end in .obj or .ply: " + args.output);
  }
  return Action::Run;
}

// Files this run has written; removed again unless the whole run succeeds, so that a failure
// never leaves a half set of outputs (an OBJ without its texture, a report without a mesh).
class WrittenFiles {
 public:
  WrittenFiles() = default;
  WrittenFiles(const WrittenFiles&) = delete;
  WrittenFiles& operator=(const WrittenFiles&) = delete;
  ~WrittenFiles() {
    for (const std::string& path : paths_) {
      std::error_code ec;
      fs::remove(path, ec);
    }
  }
  void add(const std::string& path) { paths_.push_back(path); }
  void keep() { paths_.clear(); }

 private:
  std::vector<std::string> paths_;
};

int run(const Arguments& args) {
  const sdp::io::MeshData mesh = sdp::io::readMesh(args.input);
  // The written texture coordinates span [0,1] so the checkerboard covers the patch once,
  // unless the caller wants the core's own scale (area-matched for the measured boundary). PLY
  // holds them in single precision, OBJ in full: the core makes the map one-to-one as stored.
  sdp::Options options = args.options;
  options.fit_unit_square = !args.natural_scale;
  options.storage =
      lowercaseExtension(args.output) == ".ply" ? sdp::UVStorage::Float : sdp::UVStorage::Double;
  sdp::Result result = sdp::parameterize(mesh.V, mesh.F, options);
  sdp::Report& report = result.report;
  if (mesh.polygons_triangulated > 0) {
    report.warnings.insert(report.warnings.begin(),
                           std::to_string(mesh.polygons_triangulated) +
                               " polygons with more than 3 vertices were fan-triangulated");
  }
  std::string json = report.toJson();
  if (json.empty() || json.back() != '\n') json += '\n';
  WrittenFiles written;
  const fs::path out(args.output);
  if (lowercaseExtension(args.output) == ".obj") {
    const std::string png_name = out.stem().string() + "_checker.png";
    const std::string png_path = (out.parent_path() / png_name).string();
    sdp::io::writePng(png_path, args.texture_size, args.texture_size,
                      sdp::checkerboardRGB(args.texture_size, args.checkers));
    written.add(png_path);
    sdp::io::writeObjWithTexture(args.output, mesh.V, mesh.F, result.uv, png_name);
    written.add(args.output);
    written.add(fs::path(out).replace_extension(".mtl").string());
  } else {
    sdp::io::writePly(args.output, mesh.V, mesh.F, result.uv);
    written.add(args.output);
  }
  if (!args.report_path.empty()) {
    sdp::io::writeTextFile(args.report_path, json);
    written.add(args.report_path);
  }
  written.keep();

  for (const std::string& warning : report.warnings) {
    std::cerr << "warning: " << warning << '\n';
  }
  if (!args.quiet) std::cout << json << std::flush;
  return 0;
}

// The single stderr line of a failure; embedded line breaks would break the one-line contract.
void printFailure(std::string reason) {
  for (char& c : reason) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  if (reason.empty()) reason = "unknown error";
  std::cerr << kProgram << ": " << reason << std::endl;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  try {
    switch (parseArguments(argc, argv, args)) {
      case Action::Help:
        std::cout << kUsage;
        return 0;
      case Action::Version:
        std::cout << kProgram << ' ' << SDP_VERSION << '\n';
        return 0;
      case Action::Run:
        break;
    }
  } catch (const UsageError& e) {
    printFailure(e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    printFailure(e.what());
    return kExitUsage;
  }

  try {
    return run(args);
  } catch (const sdp::ParameterizationError& e) {
    printFailure(e.what());
  } catch (const std::bad_alloc&) {
    printFailure("out of memory");
  } catch (const std::exception& e) {
    printFailure(e.what());
  } catch (...) {
    printFailure("unknown error");
  }
  return kExitFailure;
}
