#include "parameterize.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <string>

#include "boundary.h"
#include "free_boundary.h"
#include "metrics.h"
#include "patch.h"
#include "solve.h"
#include "storage.h"
#include "stretch_newton.h"
#include "weights.h"

namespace sdp {
namespace {

using Clock = std::chrono::steady_clock;

// Accumulates wall time per stage (a stage may run again after a fallback) and reports
// progress; a cancelled run stops at the next stage boundary.
class StageClock {
 public:
  StageClock(Report& report, const ProgressCallback& progress)
      : report_(report), progress_(progress) {}
  void begin(const char* stage, int percent) {
    if (progress_ && !progress_(stage, percent))
      throw ParameterizationError("cancelled by the user");
    stage_ = stage;
    start_ = Clock::now();
  }
  void end() { add(stage_, std::chrono::duration<double>(Clock::now() - start_).count()); }
  void add(const std::string& stage, double seconds) {
    if (double* total = find(stage))
      *total += seconds;
    else
      report_.stage_seconds.emplace_back(stage, seconds);
  }
  // Seconds spent so far in `stage` (0 if it has not run).
  double seconds(const std::string& stage) {
    const double* total = find(stage);
    return total ? *total : 0;
  }

 private:
  double* find(const std::string& stage) {
    for (auto& entry : report_.stage_seconds)
      if (entry.first == stage) return &entry.second;
    return nullptr;
  }

  Report& report_;
  const ProgressCallback& progress_;
  std::string stage_;
  Clock::time_point start_;
};

constexpr double kFewRefinementSteps = 6;
constexpr double kFastStretchExponent = 1.0;

// Validates a user-given source vertex; returns its local index (or -1 when none was given).
int userSource(const Patch& patch, int input_vertices, int source, bool needs_interior) {
  if (source < 0) return -1;
  const std::string name = "source vertex " + std::to_string(source);
  if (source >= input_vertices)
    throw ParameterizationError(name + " is out of range (the mesh has " +
                                std::to_string(input_vertices) + " vertices)");
  const int local = patch.local_vertex[source];
  if (local < 0) throw ParameterizationError(name + " is not used by any face");
  if (needs_interior && patch.on_boundary[local])
    throw ParameterizationError(
        name + " is on the boundary; the measured boundary needs an interior vertex");
  return local;
}

// Yoshizawa-Belyaev-Seidel: damp the pull of neighbours that are stretched, a_ij / sigma_j^eta,
// then renormalize each row. Weights stay positive, so the map stays one-to-one.
void reweightByStretch(const Patch& patch, const std::vector<double>& vertex_l2, double eta,
                       std::vector<double>& weights) {
  for (int v = 0; v < patch.vertexCount(); ++v) {
    if (patch.on_boundary[v]) continue;
    double sum = 0;
    for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) {
      const double sigma = std::max(vertex_l2[patch.ring_vertex[k]], 1e-6);
      weights[k] /= std::pow(sigma, eta);
      sum += weights[k];
    }
    for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) weights[k] /= sum;
  }
}

}  // namespace

namespace {

// Scales and moves the UVs uniformly (aspect kept) so the real vertices span [0,1] on the
// longer side, centred: a texture then covers the patch once. Stretch measures do not change.
void fitUnitSquare(const Patch& patch, LocalUVs& uv) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d high = -low;
  for (int v = 0; v < patch.real_vertex_count; ++v) {
    low = low.cwiseMin(uv[v]);
    high = high.cwiseMax(uv[v]);
  }
  const double extent = (high - low).maxCoeff();
  if (!(extent > 0) || !std::isfinite(extent))
    throw ParameterizationError("the parameterization has no extent");
  const Eigen::Vector2d centre = 0.5 * (low + high);
  for (auto& p : uv) p = (p - centre) / extent + Eigen::Vector2d::Constant(0.5);
}

UVMeasures measureUVsChecked(const Positions& V, const Triangles& F, const UVs& uv);
}  // namespace

UVMeasures measureUVs(const Positions& V, const Triangles& F, const UVs& uv) {
  try {
    return measureUVsChecked(V, F, uv);
  } catch (const std::bad_alloc&) {
    throw ParameterizationError("not enough memory to measure a mesh of " +
                                std::to_string(V.rows()) + " vertices");
  }
}

namespace {
UVMeasures measureUVsChecked(const Positions& V, const Triangles& F, const UVs& uv) {
  if (uv.rows() != V.rows()) throw ParameterizationError("one UV per vertex is needed");
  const Patch patch = buildPatch(V, F);
  LocalUVs local(patch.vertexCount(), Eigen::Vector2d::Zero());
  for (int v = 0; v < patch.real_vertex_count; ++v)
    local[v] = uv.row(patch.input_vertex[v]).transpose();
  const StretchMetrics m = stretchMetrics(patch, local);
  return {m.l2, m.linf, m.flipped_faces, m.face_l2};
}
}  // namespace

namespace {
Result parameterizeChecked(const Positions& V, const Triangles& F, const Options& options);
}  // namespace

Result parameterize(const Positions& V, const Triangles& F, const Options& options) {
  // Every failure leaves as the one error type, so front ends print one line and never abort.
  try {
    return parameterizeChecked(V, F, options);
  } catch (const std::bad_alloc&) {
    throw ParameterizationError("not enough memory to parameterize a mesh of " +
                                std::to_string(V.rows()) + " vertices and " +
                                std::to_string(F.rows()) + " faces");
  }
}

namespace {

Result parameterizeChecked(const Positions& V, const Triangles& F, const Options& options) {
  const auto run_start = Clock::now();
  if (options.stretch_iterations < 0)
    throw ParameterizationError("stretch iterations must be 0 or more");
  Result result;
  Report& report = result.report;
  report.weights = weightSchemeName(options.weights);
  report.boundary = boundaryShapeName(options.boundary);
  StageClock clock(report, options.progress);

  clock.begin("topology", 0);
  PatchOptions patch_options;
  patch_options.outer_vertex = options.outer_boundary_vertex;
  const Patch patch = buildPatch(V, F, patch_options);
  report.vertices = patch.real_vertex_count;
  report.faces = patch.real_face_count;
  report.holes_filled = patch.holes_filled;
  report.unreferenced_vertices = static_cast<int>(V.rows()) - patch.real_vertex_count;
  BoundaryShape shape = options.boundary;
  int source = userSource(patch, static_cast<int>(V.rows()), options.source_vertex,
                          shape == BoundaryShape::Measured);
  clock.end();

  auto fallBackToCircle = [&](const std::string& why) {
    report.warnings.push_back(why + "; used the circle boundary instead");
    ++report.boundary_fallbacks;
    shape = BoundaryShape::Circle;
  };
  Polygon boundary;
  MeasuredCounts measured_counts;
  // The boundary (source choice, walks) runs on this thread while the other cores start on the
  // weights, then joins them: the two do not depend on each other. Their stage times overlap.
  auto measureBoundary = [&] {
    const auto start = Clock::now();
    if (shape == BoundaryShape::Measured && source < 0)
      source = chooseSourceVertex(patch, options.source_rule);
    if (shape == BoundaryShape::Measured) {
      if (source < 0) {
        fallBackToCircle("the patch has no interior vertex to measure the boundary from");
      } else {
        boundary = measuredBoundary(patch, source, measured_counts);
        if (boundary.empty()) {
          fallBackToCircle("the measured boundary could not be made convex");
        } else if (const double ears = earStretch(patch, boundary),
                   circle_ears = earStretch(patch, circleBoundary(patch));
                   ears > 4 * std::max(circle_ears, 1.0)) {
          // Faces with all corners on the boundary are shaped by the polygon alone; where the
          // convex hull straightened a stretch, they are crushed flat. Ears are unfolded
          // (boundary.h: beetle.off, camel_b.off hold); this catches fins, wider strips.
          char numbers[96];
          std::snprintf(numbers, sizeof numbers, "%.3g (circle: %.3g)", ears, circle_ears);
          fallBackToCircle(
              std::string("the measured polygon crushes the faces lying on the boundary, "
                          "their stretch ") +
              numbers);
        }
        // Walks that miss their boundary vertex (a strongly curved patch seen from S) fall
        // back one vertex at a time to the edge-graph distance, counted in walk_fallbacks: the
        // polygon holds even when most of them miss (camel_b: 435 of 486; refined from it, its
        // L2 is lower than from the circle, 1.0187 against 1.0203).
      }
    } else if (shape == BoundaryShape::Square) {
      boundary = squareBoundary(patch);
      if (boundary.empty())
        fallBackToCircle("a square boundary needs at least 4 boundary vertices");
    }
    if (shape == BoundaryShape::Circle) boundary = circleBoundary(patch);
    clock.add("boundary", std::chrono::duration<double>(Clock::now() - start).count());
  };
  clock.begin("weights", 10);
  WeightCounts weight_counts;
  std::vector<double> weights =
      computeWeights(patch, options.weights, weight_counts, measureBoundary);
  clock.end();

  InteriorSolver solver(patch);
  LocalUVs uv;
  StretchMetrics metrics;
  // Solves and measures; a map with flipped faces from the (loose) iterative solve is solved
  // again tightly first: the fold may be the solver's, not the weights' or the boundary's.
  auto solveAndMeasure = [&](const std::vector<double>& w, const Polygon& polygon) {
    do {
      clock.begin("solve", 40);
      uv = solver.solve(w, polygon);
      clock.end();
      clock.begin("metrics", 80);
      metrics = stretchMetrics(patch, uv);
      clock.end();
    } while (metrics.flipped_faces > 0 && solver.tighten());
  };
  solveAndMeasure(weights, boundary);

  // Never return a folded map: first the circle (strictly convex in exact arithmetic), then
  // uniform weights (Tutte, the best-conditioned system), else refuse with the reason.
  if (metrics.flipped_faces > 0 && shape != BoundaryShape::Circle) {
    fallBackToCircle("the " + std::string(boundaryShapeName(shape)) + " boundary gave " +
                     std::to_string(metrics.flipped_faces) + " flipped or degenerate faces");
    clock.begin("boundary", 40);
    boundary = circleBoundary(patch);
    clock.end();
    solveAndMeasure(weights, boundary);
  }
  if (metrics.flipped_faces > 0 && options.weights != WeightScheme::Uniform) {
    report.warnings.push_back(std::to_string(metrics.flipped_faces) + " faces folded with " +
                              report.weights +
                              " weights (near-degenerate triangles); used uniform weights instead");
    ++report.boundary_fallbacks;
    WeightCounts ignored;
    weights = computeWeights(patch, WeightScheme::Uniform, ignored);
    solveAndMeasure(weights, boundary);
  }
  if (metrics.flipped_faces > 0)
    throw ParameterizationError("no one-to-one map: " + std::to_string(metrics.flipped_faces) +
                                " faces stay flipped or degenerate even with a circle boundary and "
                                "uniform weights (the mesh has near-degenerate triangles)");
  report.l2_stretch_linear = metrics.l2;

  if (options.stretch_iterations > 0) {
    // One deadline for the three loops (reweighting, ARAP, Newton); each loop has its own
    // budget object, which records why it stopped and how long its last step took.
    const auto refine_start = Clock::now();
    double budget_seconds = std::numeric_limits<double>::infinity();
    if (options.refine_time_factor > 0) {
      const double linear = std::chrono::duration<double>(refine_start - run_start).count();
      budget_seconds = std::max(options.refine_min_seconds, options.refine_time_factor * linear);
    }
    auto newBudget = [&] {
      RefineBudget budget;
      budget.min_gain = options.refine_min_gain;
      if (std::isfinite(budget_seconds))
        budget.deadline = refine_start + std::chrono::duration_cast<Clock::duration>(
                                             std::chrono::duration<double>(budget_seconds));
      return budget;
    };
    RefineStop stop = RefineStop::Iterations;
    auto note = [&](const RefineBudget& budget) {
      if (budget.stop == RefineStop::TimeBudget || stop != RefineStop::TimeBudget)
        stop = budget.stop == RefineStop::NotRun ? RefineStop::Iterations : budget.stop;
    };

    // eta 0.5 reaches the lowest stretch in 5-10 steps, eta 1 gets most of the way in 2-3
    // (face.off, fixed boundary: L2 1.41 after 2 steps against 1.78). When the budget affords
    // fewer than 6 steps (each costs about the linear solve), the faster one is used.
    double eta = options.stretch_exponent;
    const double solve_seconds = clock.seconds("solve");
    if (std::isfinite(budget_seconds) && solve_seconds > 0 &&
        budget_seconds < kFewRefinementSteps * solve_seconds)
      eta = std::max(eta, kFastStretchExponent);

    clock.begin("refine", 85);
    const RefineBudget reweighting = newBudget();
    std::vector<double> refined = weights;
    StretchMetrics current = metrics;
    for (int it = 1; it <= options.stretch_iterations; ++it) {
      if (options.progress &&
          !options.progress("refine", 85 + 10 * it / options.stretch_iterations))
        throw ParameterizationError("cancelled by the user");
      if (it > 1 && reweighting.expired()) break;
      const auto iteration_start = Clock::now();
      reweightByStretch(patch, current.vertex_l2, eta, refined);
      LocalUVs candidate;
      do {
        candidate = solver.solve(refined, boundary);
        current = stretchMetrics(patch, candidate);
      } while (current.flipped_faces > 0 && solver.tighten());
      report.stretch_iterations_run = it;
      reweighting.step_seconds =
          std::chrono::duration<double>(Clock::now() - iteration_start).count();
      if (current.flipped_faces > 0) break;  // numerically folded: keep the best so far
      const bool gained = reweighting.gained(metrics.l2, current.l2);
      if (current.l2 < metrics.l2) {
        metrics = current;
        uv.swap(candidate);
        report.best_iteration = it;
      }
      if (!gained) break;
    }
    note(reweighting);
    clock.end();
    report.l2_stretch_fixed_boundary = metrics.l2;
    // Only the measured boundary is let go: it stands for the patch's own outline, which this
    // refines; a circle or square is a shape the user asked for (and it stays after a fallback
    // from measured to circle, where letting go helps most).
    if (options.free_boundary && options.boundary == BoundaryShape::Measured) {
      if (options.progress && !options.progress("free boundary", 95))
        throw ParameterizationError("cancelled by the user");
      clock.begin("free_boundary", 95);
      FreeBoundaryCounts counts;
      const RefineBudget arap = newBudget();
      // The first ARAP step with its setup costs about three reweighting solves (2.5x measured
      // at 1.65M vertices): not started when that would overrun the deadline.
      arap.step_seconds = 3 * reweighting.step_seconds;
      uv = relaxWithFreeBoundary(patch, uv, options.stretch_iterations, metrics, counts,
                                 options.progress, arap);
      note(arap);
      // Then Newton steps on the L2 stretch itself: they go on where ARAP's optimum folds.
      StretchNewtonCounts newton;
      const RefineBudget newton_budget = newBudget();
      uv = minimizeStretchWithFreeBoundary(patch, uv, options.stretch_iterations, metrics, newton,
                                           options.progress, newton_budget);
      note(newton_budget);
      report.free_boundary_steps = counts.steps_taken + newton.steps_taken;
      clock.end();
    }
    report.refinement_stop = refineStopName(stop);
  }

  report.boundary_used = boundaryShapeName(shape);
  report.source_vertex = shape == BoundaryShape::Measured ? patch.input_vertex[source] : -1;
  report.straightest_to_ltd = weight_counts.straightest_to_ltd;
  report.degenerate_rings = weight_counts.degenerate_rings;
  report.walk_fallbacks = measured_counts.walk_failures + measured_counts.walk_detours;
  report.ears_unfolded = shape == BoundaryShape::Measured ? measured_counts.ears_unfolded : 0;
  report.fallbacks = report.straightest_to_ltd + report.degenerate_rings + report.walk_fallbacks +
                     report.boundary_fallbacks;
  if (report.straightest_to_ltd > 0)
    report.warnings.push_back(std::to_string(report.straightest_to_ltd) +
                              " neighbours used the LTD direction (their cutting plane crossed no "
                              "far-side edge)");
  if (report.degenerate_rings > 0)
    report.warnings.push_back(std::to_string(report.degenerate_rings) +
                              " vertices with a degenerate 1-ring used uniform weights");
  if (report.walk_fallbacks > 0)
    report.warnings.push_back(std::to_string(report.walk_fallbacks) +
                              " boundary distances used the edge-graph distance (plane walk failed "
                              "or wandered)");

  // The map as the front end stores it: in its frame, rounded, repaired where rounding would
  // degenerate a face (storage.h); the report then describes exactly those UVs.
  clock.begin("storage", 98);
  for (auto& p : uv) p *= patch.unit;
  if (options.fit_unit_square) fitUnitSquare(patch, uv);
  const StorageCounts storage = roundForStorage(patch, uv, options.storage);
  if (options.fit_unit_square || options.storage != UVStorage::Double) {
    metrics = stretchMetrics(patch, uv);
    if (metrics.flipped_faces > 0)
      throw ParameterizationError("internal error: the stored map has flipped faces");
  }
  report.storage = uvStorageName(options.storage);
  report.storage_degenerate_faces = storage.degenerate_faces;
  report.storage_moved_vertices = storage.moved_vertices;
  // Repaired, so not a warning: the stored map is one-to-one.
  if (storage.degenerate_faces > 0)
    report.notes.push_back("stored one-to-one: " + std::to_string(storage.degenerate_faces) +
                           " faces would have collapsed when rounded to " + report.storage +
                           " texture coordinates; " + std::to_string(storage.moved_vertices) +
                           " vertices moved");
  clock.end();
  report.l2_stretch = metrics.l2;
  report.linf_stretch = metrics.linf;
  report.flipped_faces = metrics.flipped_faces;

  result.uv = UVs::Zero(V.rows(), 2);
  for (int v = 0; v < patch.real_vertex_count; ++v)
    result.uv.row(patch.input_vertex[v]) = uv[v].transpose();
  result.face_stretch = std::move(metrics.face_l2);
  report.seconds = std::chrono::duration<double>(Clock::now() - run_start).count();
  if (options.progress) options.progress("done", 100);
  return result;
}

}  // namespace

}  // namespace sdp
