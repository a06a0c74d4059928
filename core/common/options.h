// What the user chooses: docs/method.md §2 (weights), §3 (boundary), §4 (refinement), §6 (names).
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>

namespace sdp {

enum class WeightScheme { Straightest, Ltd, Floater, MeanValue, Uniform };
enum class BoundaryShape { Measured, Circle, Square };
// How the source vertex S of the measured boundary is chosen when the user gives none.
enum class SourceRule { FarthestFromBoundary, NearestBoundaryCentroid };

// How the front end stores the UVs; the map is one-to-one as stored (storage.h).
enum class UVStorage {
  Double,               // full precision (the CLI's OBJ)
  Float,                // single precision (PLY)
  FloatAndSixDecimals,  // MeshLab: float in memory, "%f" (6 decimals) in its OBJ files
};

// One table per choice the user makes, in enum order (checked below): the value, its command
// line and report name, and the label every front end shows (MeshLab's dialog, .mlx and
// pymeshlab values; docs/method.md §6). Names, labels, counts and parsing all come from these
// rows: adding a choice is one row here and its case where the choice is used; adding a weight
// scheme is its row (with its function) and the function (weights.cpp).
template <class Enum>
struct EnumRow {
  Enum id;
  const char* name;
  const char* label;
};

struct Ring;  // straightest.h
// A weight scheme: the non-negative weights of one interior vertex for its ring neighbours
// (w: ring.size() entries, zero on entry), normalized to sum 1 afterwards (weights.h); false
// when the ring is degenerate for the scheme (the vertex then gets uniform weights, counted).
// `to_ltd` counts neighbours that fell back to the LTD direction.
using RingWeightsFunction = bool (*)(const Ring& ring, double* w, int& to_ltd);
namespace weight_schemes {  // weights.cpp
bool straightest(const Ring& ring, double* w, int& to_ltd);
bool ltd(const Ring& ring, double* w, int& to_ltd);
bool floater(const Ring& ring, double* w, int& to_ltd);
bool meanValue(const Ring& ring, double* w, int& to_ltd);
bool uniform(const Ring& ring, double* w, int& to_ltd);
}  // namespace weight_schemes

struct WeightSchemeRow {
  WeightScheme id;
  const char* name;
  const char* label;
  RingWeightsFunction weights;
  bool uses_angles;       // needs the ring's angles (prepareRing) first
  double work_per_entry;  // in WorkCosts::kWeightEntry: plane walks 1, closed formulas 0.25
};

inline constexpr std::array<WeightSchemeRow, 5> kWeightSchemes = {{
    {WeightScheme::Straightest, "straightest", "Straightest distances (cutting planes)",
     weight_schemes::straightest, true, 1.0},
    {WeightScheme::Ltd, "ltd", "LTD straightest geodesics", weight_schemes::ltd, true, 1.0},
    {WeightScheme::Floater, "floater", "Floater shape-preserving", weight_schemes::floater, true,
     0.25},
    {WeightScheme::MeanValue, "mean_value", "Mean value", weight_schemes::meanValue, true, 0.25},
    {WeightScheme::Uniform, "uniform", "Uniform", weight_schemes::uniform, false, 0.25},
}};
inline constexpr std::array<EnumRow<BoundaryShape>, 3> kBoundaryShapes = {{
    {BoundaryShape::Measured, "measured", "Measured (straightest distances)"},
    {BoundaryShape::Circle, "circle", "Circle"},
    {BoundaryShape::Square, "square", "Square"},
}};
inline constexpr std::array<EnumRow<SourceRule>, 2> kSourceRules = {{
    {SourceRule::FarthestFromBoundary, "farthest", "Farthest from the boundary"},
    {SourceRule::NearestBoundaryCentroid, "centroid", "Nearest the boundary's centroid"},
}};

template <class Row, size_t N>
constexpr bool inEnumOrder(const std::array<Row, N>& table) {
  for (size_t i = 0; i < N; ++i)
    if (static_cast<size_t>(table[i].id) != i) return false;
  return true;
}
static_assert(inEnumOrder(kWeightSchemes) && inEnumOrder(kBoundaryShapes) &&
              inEnumOrder(kSourceRules));

constexpr int kWeightSchemeCount = static_cast<int>(kWeightSchemes.size());
constexpr int kBoundaryShapeCount = static_cast<int>(kBoundaryShapes.size());

// The row's name of `id`, and the value whose name is `name`.
template <class Row, size_t N, class Enum>
const char* nameIn(const std::array<Row, N>& table, Enum id) {
  return table[static_cast<size_t>(id)].name;
}
template <class Row, size_t N>
std::optional<decltype(Row::id)> parseIn(const std::array<Row, N>& table, const std::string& name) {
  for (const Row& row : table)
    if (name == row.name) return row.id;
  return std::nullopt;
}

inline const char* weightSchemeName(WeightScheme w) {
  return nameIn(kWeightSchemes, w);
}
inline const char* boundaryShapeName(BoundaryShape b) {
  return nameIn(kBoundaryShapes, b);
}
inline const char* sourceRuleName(SourceRule r) {
  return nameIn(kSourceRules, r);
}
inline std::optional<WeightScheme> parseWeightScheme(const std::string& name) {
  return parseIn(kWeightSchemes, name);
}
inline std::optional<BoundaryShape> parseBoundaryShape(const std::string& name) {
  return parseIn(kBoundaryShapes, name);
}
inline std::optional<SourceRule> parseSourceRule(const std::string& name) {
  return parseIn(kSourceRules, name);
}
const char* uvStorageName(UVStorage storage);

// How a front end keeps a layout (storage.h's store step): the frame and the precision.
struct StoragePolicy {
  // Scale and move the whole layout uniformly (aspect kept) so the texture coordinates its
  // faces use span [0,1] on the longer side, centred; else keep the layout's own frame (the
  // core's natural scale, 3D units).
  bool fit_unit_square = false;
  // Rounded to what the storage holds, repaired where rounding would degenerate a face.
  UVStorage precision = UVStorage::Double;
};

// Called with a stage name and a percentage (0..100) of the whole run; returning false cancels
// the run (the core then throws ParameterizationError("cancelled by the user")).
using ProgressCallback = std::function<bool(const char* stage, int percent)>;

// The product's defaults for every front end (dialog, pymeshlab, CLI): refined, with a work
// budget of twice the linear map's work (work.h: counted, not timed, so the same map on every
// run; at most about 3x the linear map's cost on large patches), and at least kMinRefineWork,
// so small and medium patches are refined to convergence.
constexpr int kDefaultStretchIterations = 10;
constexpr double kDefaultRefineWorkFactor = 2.0;

struct Options {
  WeightScheme weights = WeightScheme::Straightest;
  BoundaryShape boundary = BoundaryShape::Measured;
  int source_vertex = -1;  // -1: automatic (source_rule); else an index into the input vertices
  SourceRule source_rule = SourceRule::FarthestFromBoundary;
  int outer_boundary_vertex = -1;  // with holes: a vertex on the outer loop; -1: longest loop
  int stretch_iterations = 0;      // 0: the paper's linear method; else the most steps per loop
  // eta of the Yoshizawa-Belyaev-Seidel reweighting: 0.5 gave the lowest stretch of
  // {0.5, 1, 2} on the shared meshes (K = 10 and 30, sdp_bench --stretch-exponent).
  double stretch_exponent = 0.5;
  // The K reweighting steps on the fixed boundary that refinement starts with; false goes from
  // the linear map straight to the free-boundary steps (the atlas's charts of large meshes:
  // AtlasOptions::reweight_below_faces).
  bool reweight = true;
  // Refinement beyond the paper: with the measured boundary, after the K reweighting steps on
  // the fixed boundary, K as-rigid-as-possible steps that move the boundary too
  // (free_boundary.h), each checked to keep the map one-to-one. Circle and square stay as asked.
  bool free_boundary = true;
  // When refinement stops before stretch_iterations (refine_budget.h): a step lowering L2 by
  // less than this relative amount ends its loop; refinement ends once it has done
  // max(refine_min_work, refine_work_factor x the linear map's work) (work.h). 0: no work limit.
  // Either way the same options give the same map on every run. time_limit_seconds > 0 adds a
  // wall-clock limit, which makes the map depend on the machine's speed and load.
  double refine_min_gain = 1e-3;
  double refine_work_factor = 0;
  double refine_min_work = 0;
  double time_limit_seconds = 0;
  // How the front end keeps the UVs: parameterize()'s store step (storage.h).
  StoragePolicy storage;
  ProgressCallback progress;
};

// Options with the product's refinement defaults (kDefault* above), as every front end starts.
Options productDefaults();

}  // namespace sdp
