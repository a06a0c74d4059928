// What the user chooses: docs/method.md §2 (weights), §3 (boundary), §4 (refinement), §6 (names).
#pragma once

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

constexpr int kWeightSchemeCount = 5;
constexpr int kBoundaryShapeCount = 3;

// CLI / report names ("straightest", "ltd", ...), in docs/method.md §6 order.
const char* weightSchemeName(WeightScheme w);
const char* boundaryShapeName(BoundaryShape b);
const char* sourceRuleName(SourceRule r);
const char* uvStorageName(UVStorage storage);
std::optional<WeightScheme> parseWeightScheme(const std::string& name);
std::optional<BoundaryShape> parseBoundaryShape(const std::string& name);
std::optional<SourceRule> parseSourceRule(const std::string& name);

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
  // The frame and precision of the returned UVs: fitted (aspect kept) so the faces span [0,1] on
  // the longer side, or the core's natural scale (3D units); rounded to what the storage holds,
  // and repaired where rounding would degenerate a face.
  bool fit_unit_square = false;
  UVStorage storage = UVStorage::Double;
  ProgressCallback progress;
};

// Options with the product's refinement defaults (kDefault* above), as every front end starts.
Options productDefaults();

}  // namespace sdp
