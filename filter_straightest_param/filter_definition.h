// The filter's one definition, shared by every front end: the MeshLab shims (their dialog, .mlx
// scripts and pymeshlab), the CLI, and docs/usage.md's tables. Plain C++ on top of the core (no Qt,
// MeshLab or vcglib): each front end turns the tables below into its own parameter classes,
// flags or lines, so none can drift from another.
#pragma once

#include <string>
#include <vector>

#include "core/atlas/atlas.h"
#include "core/common/options.h"
#include "core/common/report.h"

namespace sdp::filter {

// docs/method.md §6 names.
extern const char* const kFilterName;  // "Parametrization: Straightest Distances"
extern const char* const
    kPythonFilterName;     // "compute_texcoord_parametrization_straightest_distances"
std::string filterHelp();  // the filter's description shown in MeshLab (HTML)

// Every value a run can be given, whichever front end set it. Start from defaultValues().
struct FilterValues {
  int weights;             // index into the `weights` choices
  int boundary;            // index into the `boundary` choices
  int source_vertex;       // -1: automatic; else a vertex index in the front end's numbering
  int source_rule;         // index into the `--source-rule` choices
  int stretch_iterations;  // 0: the paper's linear map
  int time_budget;         // refinement work as a multiple of the linear map's; 0: no limit
  int time_limit;          // CLI: wall-clock seconds for the refinement; 0: none
  bool fixed_boundary;     // refinement keeps the measured boundary in place
  int outer_vertex;        // patches with holes: a vertex of the outer loop; -1: the longest
  bool selected_only;      // MeshLab: only the selected faces
  std::string texture_name;
  int checkers;
  int texture_size;
  bool natural_scale;  // CLI: UVs at the solver's scale instead of fitted into [0,1]
  // The atlas filter only.
  int gutter;         // texels kept free between charts
  int chart_stretch;  // a chart stretched more than 1 + this / 100 (L2) is split
};

enum class ParameterType { Enum, Int, Bool, String };

struct Choice {
  std::string cli_name;  // CLI value and report name, e.g. "straightest"
  std::string label;     // MeshLab's enum label, docs/method.md §6
};

// One row of the parameter table. A row with a `name` is a MeshLab parameter (dialog, .mlx,
// pymeshlab keyword); a row with a `cli_flag` is a CLI option; most rows are both.
struct ParameterDescription {
  std::string name;       // .mlx / pymeshlab name, e.g. "weights"; empty: CLI only
  std::string cli_flag;   // e.g. "--weights"; empty: MeshLab only
  std::string cli_value;  // the value's placeholder in --help, e.g. "W"; empty for a switch
  std::string label;      // MeshLab dialog label
  std::string help;       // one text for the tooltip, --help and docs/usage.md
  ParameterType type = ParameterType::Int;
  std::vector<Choice> choices;  // Enum only, in order: the value is the index
  int default_int = 0;          // Enum (index), Int, Bool (0/1)
  int min = 0, max = 0;         // Int: the accepted range, the same in every front end
  std::string default_string;   // String only
  // Where the value lives in FilterValues (the one matching `type`).
  int FilterValues::*int_field = nullptr;  // Enum, Int
  bool FilterValues::*bool_field = nullptr;
  std::string FilterValues::*string_field = nullptr;

  bool inMeshLab() const { return !name.empty(); }
  bool inCli() const { return !cli_flag.empty(); }
};

// In MeshLab's dialog order for the MeshLab rows: weights, boundary, sourcevertex,
// stretchiterations, selectedonly, texturename, checkers, texturesize. No MeshLab parameter may
// be added lightly: meshlabserver 2020.09 aborts (an assertion) on a script that lacks one of the
// filter's parameters, which every script saved before the addition would.
const std::vector<ParameterDescription>& parameters();

// Every field at its row's default.
FilterValues defaultValues();

// Throws ParameterizationError("<who> must be between <min> and <max>, got <value>") for an Int
// row, "unknown <who> choice <value>" for an Enum row; `who` is how the front end names it.
void checkValue(const ParameterDescription& p, int value, const std::string& who);

// Checks every value (the MeshLab name in the reason) and maps them to core options with the
// product's defaults (sdp::productDefaults). The storage and frame stay the front end's choice.
sdp::Options toOptions(const FilterValues& values);

// The report as log lines: the summary fields (sdp::reportFields) in one line after what ran,
// then the breakdown, `notes` (the front end's own remarks), the core's notes and warnings.
std::vector<std::string> reportLines(const sdp::Report& report,
                                     const std::vector<std::string>& notes = {});

// The one-line reason for the exception being handled (call it inside a catch block): its
// what(), "not enough memory" for std::bad_alloc, "unknown error" for anything else. Every front
// end words its failures so.
std::string currentFailureReason();

// docs/usage.md's tables in Markdown, generated from the tables above (tests/filter's
// readme_tables checks that docs/usage.md holds them): "parameters", "report", "atlas-parameters"
// and "atlas-report".
std::string markdownTable(const std::string& which);

// The atlas filter (core/atlas/atlas.h): its own names and parameter table, so the patch
// filter's parameters (and every saved script of it) stay as they are. Its rows fill the same
// FilterValues.
extern const char* const kAtlasFilterName;        // "Parametrization: Straightest Distances Atlas"
extern const char* const kAtlasPythonFilterName;  // "..._straightest_distances_atlas"
std::string atlasHelp();
// In MeshLab's dialog order: texturesize, gutter, chartstretch, stretchiterations,
// refinementwork, selectedonly, texturename, checkers.
const std::vector<ParameterDescription>& atlasParameters();
FilterValues atlasDefaultValues();
// Checks the atlas rows' values and maps them to the core's atlas options (storage left to the
// front end).
sdp::atlas::AtlasOptions toAtlasOptions(const FilterValues& values);
// The atlas report as log lines: what ran, the summary, what was split, notes and warnings.
std::vector<std::string> atlasReportLines(const sdp::atlas::AtlasReport& report);

}  // namespace sdp::filter
