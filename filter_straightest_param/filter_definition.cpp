#include "filter_definition.h"

#include <cstdio>
#include <exception>
#include <limits>
#include <new>

#include "core/common/error.h"

namespace sdp::filter {

const char* const kFilterName = "Parametrization: Straightest Distances";
const char* const kPythonFilterName = "compute_texcoord_parametrization_straightest_distances";

std::string filterHelp() {
  return "Flattens a disk-shaped patch onto the plane with per-wedge texture coordinates that "
         "never fold, following <i>Parameterization of 3D Surface Patches by Straightest "
         "Distances</i> (Lee, Kim, Lee): a convex-combination map, one-to-one by Tutte/Floater, "
         "then by default refined to lower stretch in checked steps (Stretch iterations 0 gives "
         "the paper's map). The map is checked as MeshLab stores it (float, 6 decimals in OBJ). "
         "The patch must have one boundary loop and no handles. A checkerboard texture is written "
         "next to the mesh and attached; per-face quality holds the stretch (1 = no distortion), "
         "so <i>Colorize by Quality</i> shows where the map stretches. The log lists L2 and "
         "L&infin; stretch, flipped faces (always 0), fallbacks, the source vertex and the time.";
}

namespace {

constexpr int kIntMax = std::numeric_limits<int>::max();

ParameterDescription row(std::string name, std::string flag, std::string value, std::string label,
                         std::string help, ParameterType type) {
  ParameterDescription p;
  p.name = std::move(name);
  p.cli_flag = std::move(flag);
  p.cli_value = std::move(value);
  p.label = std::move(label);
  p.help = std::move(help);
  p.type = type;
  return p;
}

ParameterDescription enumRow(std::string name, std::string flag, std::string value,
                             std::string label, std::string help, std::vector<Choice> choices,
                             int FilterValues::*field) {
  ParameterDescription p = row(std::move(name), std::move(flag), std::move(value), std::move(label),
                               std::move(help), ParameterType::Enum);
  p.choices = std::move(choices);
  p.max = static_cast<int>(p.choices.size()) - 1;
  p.int_field = field;
  return p;
}

ParameterDescription intRow(std::string name, std::string flag, std::string value,
                            std::string label, std::string help, int default_value, int min,
                            int max, int FilterValues::*field) {
  ParameterDescription p = row(std::move(name), std::move(flag), std::move(value), std::move(label),
                               std::move(help), ParameterType::Int);
  p.default_int = default_value;
  p.min = min;
  p.max = max;
  p.int_field = field;
  return p;
}

ParameterDescription boolRow(std::string name, std::string flag, std::string label,
                             std::string help, bool FilterValues::*field) {
  ParameterDescription p = row(std::move(name), std::move(flag), "", std::move(label),
                               std::move(help), ParameterType::Bool);
  p.bool_field = field;
  return p;
}

ParameterDescription stringRow(std::string name, std::string label, std::string help,
                               std::string default_value, std::string FilterValues::*field) {
  ParameterDescription p =
      row(std::move(name), "", "", std::move(label), std::move(help), ParameterType::String);
  p.default_string = std::move(default_value);
  p.string_field = field;
  return p;
}

// Choices named as the core names them, labelled as MeshLab shows them.
template <class Row, size_t N>
std::vector<Choice> choicesOf(const std::array<Row, N>& table) {
  std::vector<Choice> choices;
  for (const Row& row : table) choices.push_back({row.name, row.label});
  return choices;
}

}  // namespace

const std::vector<ParameterDescription>& parameters() {
  static const std::vector<ParameterDescription> list = {
      enumRow("weights", "--weights", "W", "Interior weights",
              "How each interior vertex is placed between its neighbours. Straightest distances "
              "(the paper's cutting planes) usually stretches least; LTD and Floater are the "
              "classic shape-preserving maps; Mean value is smooth; Uniform ignores geometry "
              "(most robust, most stretch).",
              choicesOf(sdp::kWeightSchemes), &FilterValues::weights),
      enumRow("boundary", "--boundary", "B", "Boundary shape",
              "Where the boundary goes. Measured follows the patch's own outline (straightest "
              "distances from a source vertex) and lowers stretch near the border; Circle and "
              "Square fix it to a shape (Square suits geometry images).",
              choicesOf(sdp::kBoundaryShapes), &FilterValues::boundary),
      intRow("sourcevertex", "--source", "N", "Source vertex",
             "Centre of the measured boundary (an interior vertex): -1 picks one automatically; "
             "otherwise a vertex index. In MeshLab a single selected vertex overrides this.",
             -1, -1, kIntMax, &FilterValues::source_vertex),
      enumRow("", "--source-rule", "R", "Automatic source vertex",
              "How the automatic source vertex is picked: the interior vertex farthest from the "
              "boundary along edges, or the one nearest the centroid of the boundary vertices.",
              choicesOf(sdp::kSourceRules), &FilterValues::source_rule),
      intRow("stretchiterations", "--stretch-iterations", "K", "Stretch iterations",
             "Most refinement steps per stage; 0 gives the paper's linear map. Refinement "
             "re-solves with weights that pull less towards stretched areas, then (Measured "
             "boundary) lets the outline move in checked steps and takes Newton steps on the "
             "stretch itself; the map never folds. A stage stops early once "
             "a step gains under 0.1% of L2 stretch, and refinement stops after twice the "
             "linear map's work (counted, not timed, so the same map on every run). Circle and "
             "Square boundaries stay as they are.",
             sdp::kDefaultStretchIterations, 0, 100, &FilterValues::stretch_iterations),
      intRow("", "--time-budget", "F", "Refinement work budget",
             "Refinement may do F times the linear map's work (at least what small patches need "
             "to converge); 0: no limit. Work is counted from sizes and iterations, not timed: "
             "the same map on every run, machine and load.",
             static_cast<int>(sdp::kDefaultRefineWorkFactor), 0, 1000, &FilterValues::time_budget),
      intRow("", "--time-limit", "S", "Refinement time limit",
             "Also stop refining after S seconds of wall-clock time; 0: none. The map then "
             "depends on the machine's speed and load.",
             0, 0, 86400, &FilterValues::time_limit),
      boolRow("", "--fixed-boundary", "Fixed boundary",
              "Refinement keeps the measured boundary where it is (circle and square always "
              "stay).",
              &FilterValues::fixed_boundary),
      intRow("", "--outer-vertex", "N", "Outer boundary vertex",
             "Patches with holes: a vertex on the loop to use as the outer boundary; -1: the "
             "longest loop (the others are filled virtually).",
             -1, -1, kIntMax, &FilterValues::outer_vertex),
      boolRow("selectedonly", "", "Selected faces only",
              "Parameterize only the selected faces (they must form one disk-shaped patch); "
              "other faces keep their texture coordinates.",
              &FilterValues::selected_only),
      stringRow("texturename", "Texture file name",
                "Name of the checkerboard image written next to the mesh file and attached as "
                "its texture.",
                "straightest_checker.png", &FilterValues::texture_name),
      intRow("checkers", "--checkers", "N", "Checkerboard squares",
             "Squares per side of the checkerboard; more squares show finer distortion.", 16, 1,
             512, &FilterValues::checkers),
      intRow("texturesize", "--texture-size", "PX", "Texture size (pixels)",
             "Width and height of the checkerboard image.", 1024, 16, 8192,
             &FilterValues::texture_size),
      boolRow("", "--natural-scale", "Natural scale",
              "Write the UVs at the solver's scale (measured boundary: the mesh's area) instead "
              "of fitted into [0,1].",
              &FilterValues::natural_scale),
  };
  return list;
}

namespace {
// `values` with every field of the table's rows at its row's default.
FilterValues withDefaults(const std::vector<ParameterDescription>& table, FilterValues values) {
  for (const ParameterDescription& p : table) {
    if (p.int_field) values.*p.int_field = p.default_int;
    if (p.bool_field) values.*p.bool_field = p.default_int != 0;
    if (p.string_field) values.*p.string_field = p.default_string;
  }
  return values;
}
}  // namespace

FilterValues defaultValues() {
  return withDefaults(parameters(), FilterValues{});
}

void checkValue(const ParameterDescription& p, int value, const std::string& who) {
  if (value >= p.min && value <= p.max) return;
  if (p.type == ParameterType::Enum)
    throw ParameterizationError("unknown " + who + " choice " + std::to_string(value));
  throw ParameterizationError(who + " must be between " + std::to_string(p.min) + " and " +
                              std::to_string(p.max) + ", got " + std::to_string(value));
}

sdp::Options toOptions(const FilterValues& values) {
  for (const ParameterDescription& p : parameters()) {
    if (p.int_field) checkValue(p, values.*p.int_field, p.inMeshLab() ? p.name : p.cli_flag);
  }
  if (values.texture_name.empty()) throw ParameterizationError("the texture file name is empty");
  // source_vertex stays -1: values.source_vertex is in the front end's numbering, which the
  // front end maps to the core's (the CLI: the same; MeshLab: vcg_adapters/mesh_run.h).
  sdp::Options options = sdp::productDefaults();
  options.weights = static_cast<WeightScheme>(values.weights);
  options.boundary = static_cast<BoundaryShape>(values.boundary);
  options.source_rule = static_cast<SourceRule>(values.source_rule);
  options.stretch_iterations = values.stretch_iterations;
  options.refine_work_factor = values.time_budget;
  options.time_limit_seconds = values.time_limit;
  options.free_boundary = !values.fixed_boundary;
  options.outer_boundary_vertex = values.outer_vertex;
  return options;
}

std::string currentFailureReason() {
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return "not enough memory";
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown error";
  }
}

namespace {

std::string formatted(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

}  // namespace

std::vector<std::string> reportLines(const sdp::Report& r, const std::vector<std::string>& notes) {
  std::vector<std::string> lines;
  std::string what = "Straightest distances: " + std::to_string(r.vertices) + " vertices, " +
                     std::to_string(r.faces) + " faces, weights " + r.weights + ", boundary " +
                     r.boundary;
  if (!r.boundary_used.empty() && r.boundary_used != r.boundary) {
    what += " (used " + r.boundary_used + ")";
  }
  lines.push_back(what);
  std::string summary;
  for (const sdp::ReportField& field : sdp::reportFields()) {
    if (!field.summary) continue;
    summary += (summary.empty() ? "" : ", ") + std::string(field.log_label) + " " +
               formatted(field.log_format, field.number(r));
  }
  lines.push_back(summary);
  if (r.fallbacks.total() > 0) {
    std::string line = "fallbacks:";
    for (const sdp::FallbackKind& kind : sdp::kFallbackKinds)
      line += std::string(kind.id == sdp::kFallbackKinds[0].id ? " " : ", ") + kind.log_label +
              " " + std::to_string(r.fallbacks[kind.id]);
    lines.push_back(line);
  }
  if (r.stretch_iterations_run > 0) {
    lines.push_back("stretch refinement: " + std::to_string(r.stretch_iterations_run) +
                    " iterations, kept iteration " + std::to_string(r.best_iteration) +
                    ", linear L2 " + formatted("%.4f", r.l2_stretch_linear) + ", stopped by " +
                    r.refinement_stop);
    if (r.free_boundary_steps > 0)
      lines.push_back("free boundary: " + std::to_string(r.free_boundary_steps) +
                      " steps, L2 on the fixed boundary " +
                      formatted("%.4f", r.l2_stretch_fixed_boundary));
  }
  for (const std::string& note : notes) lines.push_back(note);
  for (const std::string& note : r.notes) lines.push_back(note);
  for (const std::string& warning : r.warnings) lines.push_back("warning: " + warning);
  return lines;
}

namespace {

std::string code(const std::string& s) {
  return "`" + s + "`";
}

std::string defaultText(const ParameterDescription& p) {
  switch (p.type) {
    case ParameterType::Enum:
      return code(p.choices[p.default_int].cli_name);
    case ParameterType::Int:
      return std::to_string(p.default_int);
    case ParameterType::Bool:
      return p.default_int ? "true" : "false";
    case ParameterType::String:
      return code(p.default_string);
  }
  return "";
}

std::string valuesText(const ParameterDescription& p) {
  switch (p.type) {
    case ParameterType::Enum: {
      std::string text;
      for (const Choice& c : p.choices) {
        const std::string label = p.inMeshLab() ? ": " + c.label : "";
        text += (text.empty() ? "" : "; ") + code(c.cli_name) + label;
      }
      return text;
    }
    case ParameterType::Int:
      return std::to_string(p.min) + " … " +
             (p.max == std::numeric_limits<int>::max() ? std::string("any vertex")
                                                       : std::to_string(p.max));
    case ParameterType::Bool:
      return p.inMeshLab() ? "true, false" : "switch";
    case ParameterType::String:
      return "a file name";
  }
  return "";
}

std::string parameterTable(const std::vector<ParameterDescription>& list) {
  std::string out = "| `.mlx` / pymeshlab | CLI | default | values | what it does |\n";
  out += "| --- | --- | --- | --- | --- |\n";
  for (const ParameterDescription& p : list) {
    out += "| " + (p.inMeshLab() ? code(p.name) : "—") + " | " +
           (p.inCli() ? code(p.cli_flag + (p.cli_value.empty() ? "" : " " + p.cli_value)) : "—") +
           " | " + defaultText(p) + " | " + valuesText(p) + " | " + p.help + " |\n";
  }
  return out;
}

}  // namespace

std::string markdownTable(const std::string& which) {
  if (which == "parameters") return parameterTable(parameters());
  if (which == "atlas-parameters") return parameterTable(atlasParameters());
  std::string out =
      "| key | in the pymeshlab dict and the log line | meaning |\n"
      "| --- | --- | --- |\n";
  if (which == "report") {
    for (const sdp::ReportField& f : sdp::reportFields())
      out += "| " + code(f.key) + " | " + (f.summary ? "yes" : "") + " | " + f.meaning + " |\n";
  } else if (which == "atlas-report") {
    for (const sdp::atlas::AtlasSummaryField& f : sdp::atlas::atlasSummaryFields())
      out += "| " + code(f.key) + " | yes | " + f.meaning + " |\n";
    for (const sdp::atlas::AtlasDetailField& f : sdp::atlas::atlasDetailFields())
      out += "| " + code(f.key) + " |  | " + f.meaning + " |\n";
  } else {
    throw ParameterizationError("no table named " + which);
  }
  return out;
}

// ---- The atlas filter ----

const char* const kAtlasFilterName = "Parametrization: Straightest Distances Atlas";
const char* const kAtlasPythonFilterName =
    "compute_texcoord_parametrization_straightest_distances_atlas";

std::string atlasHelp() {
  return "Cuts any triangle mesh (closed, any genus, many pieces, non-manifold or inconsistently "
         "oriented parts) into disk-shaped charts, flattens each by straightest distances with "
         "the patch filter's pipeline (one-to-one by construction, refined to low stretch), and "
         "packs them at one texel density into one texture with a gutter between charts. The "
         "result is checked as MeshLab stores it: no flipped face, no chart overlapping another, "
         "every gutter kept. Per-wedge texture coordinates (seams split), a per-face attribute "
         "<i>chart</i>, per-face quality = stretch, and a checkerboard texture are written; the "
         "mesh's vertices, faces, colours and selection are not changed. The log lists charts, "
         "seam length, packing efficiency, L2 and L&infin; stretch and the time.";
}

const std::vector<ParameterDescription>& atlasParameters() {
  static const std::vector<ParameterDescription> list = {
      intRow("texturesize", "--texture-size", "PX", "Texture size (pixels)",
             "Width and height of the texture the charts are packed for; the gutter is counted "
             "in its texels. To bake colours, give a face about 5 texels: 2048 suits meshes up "
             "to about 500k faces, 4096 up to 2M, 8192 up to 8M, 16384 beyond.",
             2048, 64, 16384, &FilterValues::texture_size),
      intRow("gutter", "--gutter", "PX", "Gutter (texels)",
             "Texels kept free between any two charts at the texture size, so that filtering "
             "and mipmaps do not bleed one chart into another.",
             2, 0, 64, &FilterValues::gutter),
      intRow("chartstretch", "--chart-stretch", "P", "Chart stretch limit (%)",
             "A chart whose L2 stretch, flattened, is more than P% above isometric is split in "
             "two; lower values give more, smaller charts with less stretch.",
             3, 0, 100, &FilterValues::chart_stretch),
      intRow("stretchiterations", "--stretch-iterations", "K", "Stretch iterations",
             "Most refinement steps per stage for each chart, as in the patch filter; 0 gives "
             "each chart the paper's linear map.",
             sdp::kDefaultStretchIterations, 0, 100, &FilterValues::stretch_iterations),
      intRow("refinementwork", "--time-budget", "F", "Refinement work budget",
             "Each chart's refinement may do F times its linear map's work, and the atlas "
             "shares one floor for all its charts; 0: no limit. Counted, not timed: the same "
             "atlas on every run.",
             static_cast<int>(sdp::atlas::kDefaultAtlasRefineWorkFactor), 0, 1000,
             &FilterValues::time_budget),
      boolRow("selectedonly", "", "Selected faces only",
              "Make the atlas of the selected faces only; other faces keep their texture "
              "coordinates.",
              &FilterValues::selected_only),
      stringRow("texturename", "Texture file name",
                "Name of the checkerboard image written next to the mesh file and attached as "
                "its texture.",
                "straightest_atlas.png", &FilterValues::texture_name),
      intRow("checkers", "--checkers", "N", "Checkerboard squares",
             "Squares per side of the checkerboard.", 64, 1, 1024, &FilterValues::checkers),
  };
  return list;
}

FilterValues atlasDefaultValues() {
  return withDefaults(atlasParameters(), defaultValues());
}

sdp::atlas::AtlasOptions toAtlasOptions(const FilterValues& values) {
  for (const ParameterDescription& p : atlasParameters()) {
    if (p.int_field) checkValue(p, values.*p.int_field, p.inMeshLab() ? p.name : p.cli_flag);
  }
  if (values.texture_name.empty()) throw ParameterizationError("the texture file name is empty");
  sdp::atlas::AtlasOptions options;
  options.chart = sdp::atlas::atlasChartDefaults();
  options.chart.stretch_iterations = values.stretch_iterations;
  options.chart.refine_work_factor = values.time_budget;
  if (values.time_budget == 0) options.chart.refine_min_work = 0;
  options.texture_size = values.texture_size;
  options.gutter = values.gutter;
  options.max_chart_stretch = 1.0 + values.chart_stretch / 100.0;
  return options;
}

std::vector<std::string> atlasReportLines(const sdp::atlas::AtlasReport& r) {
  std::vector<std::string> lines;
  lines.push_back("Straightest distances atlas: " + std::to_string(r.vertices) + " vertices, " +
                  std::to_string(r.faces) + " faces, " + std::to_string(r.components) + " pieces");
  std::string summary;
  for (const sdp::atlas::AtlasSummaryField& field : sdp::atlas::atlasSummaryFields())
    summary += (summary.empty() ? "" : ", ") + std::string(field.key) + " " +
               formatted(field.log_format, field.number(r));
  lines.push_back(summary);
  if (r.non_manifold_edges + r.non_manifold_vertices + r.zero_area_faces > 0)
    lines.push_back("split: " + std::to_string(r.non_manifold_edges) + " non-manifold edges, " +
                    std::to_string(r.non_manifold_vertices) + " non-manifold vertices; " +
                    std::to_string(r.zero_area_faces) + " zero-area faces charted alone");
  // Faces wound against their neighbours have their own warning (the count and the fix).
  for (const std::string& note : r.notes) lines.push_back(note);
  for (const std::string& warning : r.warnings) lines.push_back("warning: " + warning);
  return lines;
}

}  // namespace sdp::filter
