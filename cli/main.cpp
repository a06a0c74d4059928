// straightest_param: flattens a disk-shaped mesh patch, or makes an atlas of any mesh (--atlas),
// from the command line (docs/method.md §6, §7).
//
// Contract with scripts: exit 0 and the report JSON on stdout on success; otherwise exactly one
// line "straightest_param: <reason>" on stderr, exit 2 for usage errors and 1 for everything
// else, and no output file left behind.
#include <cctype>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "core/parameterize.h"
#include "filter_straightest_param/filter_definition.h"
#include "io/checkerboard.h"
#include "io/mesh_io.h"

#ifndef SDP_VERSION
#define SDP_VERSION "unknown"
#endif

namespace {

namespace fs = std::filesystem;

constexpr const char* kProgram = "straightest_param";
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// --help: the synopsis, the parameter table's CLI rows, then the CLI's own options.
std::string wrapped(const std::string& text, size_t indent, size_t width) {
  std::string out, line;
  size_t start = 0;
  const auto flush = [&] {
    out += line + "\n" + std::string(indent, ' ');
    line.clear();
  };
  while (start < text.size()) {
    size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(start, end - start);
    if (!line.empty() && indent + line.size() + 1 + word.size() > width) flush();
    line += (line.empty() ? "" : " ") + word;
    start = end + 1;
  }
  out += line + "\n";
  return out;
}

std::string optionHelp(const std::string& option, const std::string& help) {
  constexpr size_t kColumn = 26;
  std::string head = "  " + option;
  head += head.size() + 1 < kColumn ? std::string(kColumn - head.size(), ' ')
                                    : "\n" + std::string(kColumn, ' ');
  return head + wrapped(help, kColumn, 100);
}

std::string optionRows(const std::vector<sdp::filter::ParameterDescription>& rows) {
  using sdp::filter::ParameterType;
  std::string text;
  for (const auto& p : rows) {
    if (!p.inCli()) continue;
    std::string values;
    if (p.type == ParameterType::Enum) {
      for (size_t i = 0; i < p.choices.size(); ++i)
        values += (i ? ", " : "") + p.choices[i].cli_name +
                  (static_cast<int>(i) == p.default_int ? " (default)" : "");
      values += ". ";
    } else if (p.type == ParameterType::Int) {
      values = "Default " + std::to_string(p.default_int) + ". ";
    }
    text +=
        optionHelp(p.cli_flag + (p.cli_value.empty() ? "" : " " + p.cli_value), values + p.help);
  }
  return text;
}

std::string usage() {
  std::string text = R"(usage: straightest_param IN OUT [options]

Flattens a disk-shaped triangle patch to the plane by straightest distances.
IN is a .off, .obj, .ply or .stl mesh (polygons and PLY tristrips are triangulated, STL
corners welded where their coordinates are equal). OUT ending in .obj gets
OBJ + MTL + a checkerboard PNG <stem>_checker.png next to it; .ply gets a binary PLY.
Both carry per-wedge texture coordinates. The report (JSON) is printed to stdout.

With --atlas, IN may be any triangle mesh (closed, any genus, many pieces): it is cut into
charts, each flattened by straightest distances, packed into one texture with a gutter.

options:
)";
  text += optionRows(sdp::filter::parameters());
  text += optionHelp("--atlas",
                     "Make an atlas of charts (any mesh) instead of one patch; the "
                     "options below then apply.");
  text += "\natlas options (with --atlas):\n";
  text += optionRows(sdp::filter::atlasParameters());
  text += "\n";
  text += optionHelp("--uv-storage S",
                     "double, float or float6: make the map one-to-one as that storage holds it "
                     "(float6 = MeshLab: float in memory, 6 decimals in its OBJ). Default: the "
                     "output's, float for .ply, double for .obj.");
  text += optionHelp("--report FILE.json", "Also write the report to FILE.json.");
  text += optionHelp("--quiet", "Do not print the report.");
  text += optionHelp("--progress",
                     "Print the progress a front end's bar gets to stderr, a line per call of its "
                     "callback: `progress STAGE PERCENT% SECONDS`; with --atlas also the bar of "
                     "each stage, as MeshLab shows it: `stage NAME STAGE_PERCENT% RUN_PERCENT% "
                     "SECONDS`.");
  text += optionHelp("--help", "Show this help.");
  text += optionHelp("--version", "Show the version.");
  text += optionHelp("--", "End of options (for file names starting with '-').");
  text += "\nexit status: 0 success, 1 failure (bad mesh, I/O error, ...), 2 bad command line\n";
  return text;
}

// A bad command line: exit status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Arguments {
  std::string input;
  std::string output;
  std::string report_path;  // empty: no report file
  sdp::filter::FilterValues values = sdp::filter::defaultValues();
  bool quiet = false;
  bool progress = false;  // --progress: the progress callback's calls on stderr
  bool atlas = false;     // --atlas: the atlas filter's table and pipeline
  // --uv-storage: the texture coordinates' storage the map is made one-to-one in; by default the
  // output's (PLY float, OBJ double). `float6` is MeshLab's (float in memory, 6 decimals in OBJ).
  std::optional<sdp::UVStorage> storage;
};

// --uv-storage's names and the core's storages.
const std::pair<const char*, sdp::UVStorage> kStorageNames[] = {
    {"double", sdp::UVStorage::Double},
    {"float", sdp::UVStorage::Float},
    {"float6", sdp::UVStorage::FloatAndSixDecimals}};

std::string lowercaseExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Sets one table row from its flag's value, checked against the row's range or choices.
void setParameter(const sdp::filter::ParameterDescription& p, const std::string& value,
                  sdp::filter::FilterValues& values) {
  using sdp::filter::ParameterType;
  if (p.type == ParameterType::Enum) {
    std::string names;
    for (size_t i = 0; i < p.choices.size(); ++i) {
      if (p.choices[i].cli_name == value) {
        values.*p.int_field = static_cast<int>(i);
        return;
      }
      names += (i ? ", " : "") + p.choices[i].cli_name;
    }
    throw UsageError("unknown " + p.cli_flag + " '" + value + "' (expected one of " + names + ")");
  }
  int parsed = 0;
  const char* end = value.data() + value.size();
  const auto [ptr, ec] = std::from_chars(value.data(), end, parsed);
  if (ec != std::errc() || ptr != end || value.empty()) {
    throw UsageError(p.cli_flag + " needs an integer, got '" + value + "'");
  }
  try {
    sdp::filter::checkValue(p, parsed, p.cli_flag);
  } catch (const sdp::ParameterizationError& e) {
    throw UsageError(e.what());
  }
  values.*p.int_field = parsed;
}

const sdp::filter::ParameterDescription* cliParameter(const std::string& flag, bool atlas) {
  for (const auto& p : atlas ? sdp::filter::atlasParameters() : sdp::filter::parameters())
    if (p.inCli() && p.cli_flag == flag) return &p;
  return nullptr;
}

enum class Action { Run, Help, Version };

Action parseArguments(int argc, char** argv, Arguments& args) {
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") break;
    if (arg == "--help" || arg == "-h") return Action::Help;
    if (arg == "--version") return Action::Version;
    if (arg == "--atlas") args.atlas = true;
  }
  if (args.atlas) args.values = sdp::filter::atlasDefaultValues();
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
    if (arg == "--quiet" || arg == "--atlas" || arg == "--progress") {
      args.quiet |= arg == "--quiet";
      args.progress |= arg == "--progress";
      continue;
    }
    if (const auto* p = cliParameter(arg, args.atlas);
        p && p->type == sdp::filter::ParameterType::Bool) {
      args.values.*p->bool_field = true;
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
    if (arg == "--report") {
      args.report_path = value();
      if (args.report_path.empty()) throw UsageError("--report needs a file name");
    } else if (arg == "--uv-storage") {
      const std::string name = value();
      for (const auto& [storage_name, storage] : kStorageNames)
        if (name == storage_name) args.storage = storage;
      if (!args.storage)
        throw UsageError("unknown --uv-storage '" + name + "' (expected double, float, float6)");
    } else if (const auto* p = cliParameter(arg, args.atlas);
               p && p->type != sdp::filter::ParameterType::Bool) {
      setParameter(*p, value(), args.values);
    } else {
      throw UsageError("unknown option " + arg +
                       (!args.atlas && cliParameter(arg, true) ? " (an --atlas option)" : "") +
                       " (see --help)");
    }
  }
  if (positional.size() != 2) {
    throw UsageError(positional.size() < 2 ? "needs IN and OUT mesh files (see --help)"
                                           : "too many arguments: '" + positional[2] + "'");
  }
  args.input = positional[0];
  args.output = positional[1];
  if (!sdp::io::isReadableMeshPath(args.input)) {
    throw UsageError("IN must be a .off, .obj, .ply or .stl file: " + args.input);
  }
  const std::string out_ext = lowercaseExtension(args.output);
  if (out_ext != ".obj" && out_ext != ".ply") {
    throw UsageError("OUT must end in .obj or .ply: " + args.output);
  }
  // The map is certified in the storage named; PLY's texture coordinates are floats.
  if (out_ext == ".ply" && args.storage == sdp::UVStorage::Double)
    throw UsageError(
        "--uv-storage double needs an .obj OUT (PLY stores texture coordinates as float)");
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

// Writes the layout as OUT asks (OBJ + MTL + checkerboard PNG, or PLY with `chart` per face when
// given), and the report; nothing is left behind when any of it fails.
void writeOutputs(const Arguments& args, const sdp::io::MeshData& mesh, const sdp::Layout& layout,
                  const std::string& json, const std::vector<std::string>& warnings) {
  WrittenFiles written;
  const fs::path out(args.output);
  if (lowercaseExtension(args.output) == ".obj") {
    const std::string png_name = out.stem().string() + (args.atlas ? "_atlas.png" : "_checker.png");
    const std::string png_path = (out.parent_path() / png_name).string();
    const int size = args.values.texture_size;
    sdp::io::writePng(png_path, size, size, sdp::checkerboardRGB(size, args.values.checkers));
    written.add(png_path);
    sdp::io::writeObjWithTexture(args.output, mesh.V, mesh.F, layout, png_name);
    written.add(args.output);
    written.add(fs::path(out).replace_extension(".mtl").string());
  } else {
    sdp::io::writePly(args.output, mesh.V, mesh.F, layout);
    written.add(args.output);
  }
  if (!args.report_path.empty()) {
    sdp::io::writeTextFile(args.report_path, json);
    written.add(args.report_path);
  }
  written.keep();
  for (const std::string& warning : warnings) std::cerr << "warning: " << warning << '\n';
  if (!args.quiet) std::cout << json << std::flush;
}

// PLY holds texture coordinates in float, the CLI's OBJ in full double, unless --uv-storage says.
sdp::UVStorage storageFor(const Arguments& args) {
  if (args.storage) return *args.storage;
  return lowercaseExtension(args.output) == ".ply" ? sdp::UVStorage::Float : sdp::UVStorage::Double;
}

// With --progress, a callback that prints each call, with its time, on stderr.
sdp::ProgressCallback progressPrinter(const Arguments& args) {
  if (!args.progress) return {};
  const auto start = std::chrono::steady_clock::now();
  return [start](const char* stage, int percent) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "progress %s %d%% %.2f\n", stage, percent, seconds);
    return true;
  };
}

int runAtlas(const Arguments& args, const sdp::io::MeshData& mesh) {
  sdp::atlas::AtlasOptions options = sdp::filter::toAtlasOptions(args.values);
  options.storage = storageFor(args);
  if (args.progress) {
    options.chart.progress = progressPrinter(args);
    // The stage's own bar too, as MeshLab shows it.
    const auto start = std::chrono::steady_clock::now();
    options.stage_progress = [start](const char* stage, int stage_percent, int run_percent) {
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "stage %s %d%% %d%% %.2f\n", stage, stage_percent, run_percent, seconds);
    };
  }
  sdp::atlas::AtlasResult result = sdp::atlas::makeAtlas(mesh.V, mesh.F, options);
  std::vector<std::string>& notes = result.report.notes;
  notes.insert(notes.begin(), mesh.notes.begin(), mesh.notes.end());
  if (mesh.polygons_triangulated > 0)
    notes.insert(notes.begin(), std::to_string(mesh.polygons_triangulated) +
                                    " polygons with more than 3 vertices were fan-triangulated");
  writeOutputs(args, mesh, result.layout, result.report.toJson(), result.report.warnings);
  return 0;
}

int run(const Arguments& args) {
  const sdp::io::MeshData mesh = sdp::io::readMesh(args.input);
  if (args.atlas) return runAtlas(args, mesh);
  // The written texture coordinates span [0,1] so the checkerboard covers the patch once,
  // unless the caller wants the core's own scale (area-matched for the measured boundary). PLY
  // holds them in single precision, OBJ in full: the core makes the map one-to-one as stored.
  sdp::Options options = sdp::filter::toOptions(args.values);
  options.source_vertex = args.values.source_vertex;  // the file's numbering is the core's
  options.storage.fit_unit_square = !args.values.natural_scale;
  options.storage.precision = storageFor(args);
  if (args.progress) options.progress = progressPrinter(args);
  sdp::Result result = sdp::parameterize(mesh.V, mesh.F, options);
  sdp::Report& report = result.report;
  report.notes.insert(report.notes.begin(), mesh.notes.begin(), mesh.notes.end());
  if (mesh.polygons_triangulated > 0) {
    report.warnings.insert(report.warnings.begin(),
                           std::to_string(mesh.polygons_triangulated) +
                               " polygons with more than 3 vertices were fan-triangulated");
  }
  std::string json = report.toJson();
  if (json.empty() || json.back() != '\n') json += '\n';
  writeOutputs(args, mesh, result.layout, json, report.warnings);
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
        std::cout << usage();
        return 0;
      case Action::Version:
        std::cout << kProgram << ' ' << SDP_VERSION << '\n';
        return 0;
      case Action::Run:
        break;
    }
  } catch (...) {
    printFailure(sdp::filter::currentFailureReason());
    return kExitUsage;
  }

  try {
    return run(args);
  } catch (...) {
    printFailure(sdp::filter::currentFailureReason());
  }
  return kExitFailure;
}
