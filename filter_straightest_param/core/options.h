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

constexpr int kWeightSchemeCount = 5;
constexpr int kBoundaryShapeCount = 3;

// CLI / report names ("straightest", "ltd", ...), in docs/method.md §6 order.
const char* weightSchemeName(WeightScheme w);
const char* boundaryShapeName(BoundaryShape b);
const char* sourceRuleName(SourceRule r);
std::optional<WeightScheme> parseWeightScheme(const std::string& name);
std::optional<BoundaryShape> parseBoundaryShape(const std::string& name);
std::optional<SourceRule> parseSourceRule(const std::string& name);

// Called with a stage name and a percentage (0..100) of the whole run; returning false cancels
// the run (the core then throws ParameterizationError("cancelled")).
using ProgressCallback = std::function<bool(const char* stage, int percent)>;

struct Options {
  WeightScheme weights = WeightScheme::Straightest;
  BoundaryShape boundary = BoundaryShape::Measured;
  int source_vertex = -1;  // -1: automatic (source_rule); else an index into the input vertices
  SourceRule source_rule = SourceRule::FarthestFromBoundary;
  int outer_boundary_vertex = -1;  // with holes: a vertex on the outer loop; -1: longest loop
  int stretch_iterations = 0;      // 0: the paper's linear method
  // eta of the Yoshizawa-Belyaev-Seidel reweighting: 0.5 gave the lowest stretch of
  // {0.5, 1, 2} on the shared meshes (K = 10 and 30, sdp_bench --stretch-exponent).
  double stretch_exponent = 0.5;
  // Refinement beyond the paper: with the measured boundary, after the K reweighting steps on
  // the fixed boundary, K as-rigid-as-possible steps that move the boundary too
  // (free_boundary.h), each checked to keep the map one-to-one. Circle and square stay as asked.
  bool free_boundary = true;
  ProgressCallback progress;
};

}  // namespace sdp
