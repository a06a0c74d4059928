#include "parameterize.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <new>
#include <optional>
#include <string>

#include "core/common/metrics.h"
#include "core/common/progress.h"
#include "core/common/storage.h"
#include "core/common/work.h"
#include "core/paper/boundary.h"
#include "core/paper/patch_topology.h"
#include "core/paper/solve.h"
#include "core/paper/weights.h"
#include "core/refine/free_boundary.h"
#include "core/refine/reweight.h"
#include "core/refine/stretch_newton.h"

namespace sdp {
namespace {

using Clock = std::chrono::steady_clock;

// Accumulates wall time per stage (a stage may run again after a fallback) and reports
// progress at each stage's start; a cancelled run stops at the next stage boundary.
class StageClock {
 public:
  StageClock(Report& report, const Progress& progress) : report_(report), progress_(progress) {}
  void begin(Stage stage) {
    progress_.report(stage);
    stage_ = stage;
    start_ = Clock::now();
  }
  void end() { add(stage_, std::chrono::duration<double>(Clock::now() - start_).count()); }
  void add(Stage stage, double seconds) { addTo(report_.stage_seconds, stage, seconds); }
  // Work (work.h) done in `stage`, added to the report's stage_work.
  void addWork(Stage stage, double work) { addTo(report_.stage_work, stage, work); }

 private:
  static void addTo(StageAmounts& stages, Stage stage, double amount) {
    addToStage(stages, stageRow(stage).key, amount);
  }

  Report& report_;
  const Progress& progress_;
  Stage stage_ = Stage::Topology;
  Clock::time_point start_;
};

constexpr double kFewRefinementSteps = 6;
constexpr double kFastStretchExponent = 1.0;
// The reweighting's solves when the grid's Newton steps follow within a work budget: its map
// is only their start (they move every vertex), so the solver's 1e-8 buys nothing there. At
// 1e-4 the re-solve takes 4 iterations instead of 6-7 and the saved work goes to Newton steps
// (face s2: L2 1.2501 -> 1.2455; 1e-3 folded on face s3 and needed the tight re-solve).
constexpr double kNewtonStartTolerance = 1e-4;
// The share of a limited refinement budget reweighting may use before the grid's Newton steps
// (one step at face s2 and s3; docs/measurements.md).
constexpr double kReweightShareBeforeGrid = 0.2;

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

}  // namespace

namespace {
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
Result flattenDiskChecked(const Positions& V, const Triangles& F, const Options& options);
void storeChecked(const Positions& V, const Triangles& F, const StoragePolicy& policy,
                  const Progress& progress, Result& result);

// One error type for every failure, so front ends print one line and never abort.
[[noreturn]] void outOfMemory(const char* what, const Positions& V, const Triangles& F) {
  throw ParameterizationError(std::string("not enough memory to ") + what + " a mesh of " +
                              std::to_string(V.rows()) + " vertices and " +
                              std::to_string(F.rows()) + " faces");
}
}  // namespace

Result flattenDisk(const Positions& V, const Triangles& F, const Options& options) {
  try {
    return flattenDiskChecked(V, F, options);
  } catch (const std::bad_alloc&) {
    outOfMemory("parameterize", V, F);
  }
}

Result parameterize(const Positions& V, const Triangles& F, const Options& options) {
  Result result = flattenDisk(V, F, options);
  const StoragePolicy& policy = options.storage;
  const Progress progress(options.progress);
  try {
    storeChecked(V, F, policy, progress, result);
  } catch (const std::bad_alloc&) {
    outOfMemory("store", V, F);
  }
  progress.done();
  return result;
}

namespace {

// The disk pipeline (docs/method.md), one run of it: each stage is a member function, called in
// this order by flattenDiskChecked():
//   topology            the patch, its holes, the user's source vertex
//   weightsAndBoundary  the interior weights (§2) and, alongside, the boundary (§3) under the
//                       boundary policy, which owns its fallback rules
//   solveOneToOne       the linear solve (§2), which owns tightening and the circle / uniform
//                       fallbacks: it returns a one-to-one map or refuses
//   refine              reweighting, then with the measured boundary ARAP and Newton steps, all
//                       under one work budget (§4, work.h)
//   countFallbacks      the report's counts and warnings
//   finish              the layout at natural scale, measured
// parameterize() then runs the store step (storeChecked, §5): the front end's frame and
// precision, repaired and certified, measured as stored.
class Pipeline {
 public:
  Pipeline(const Positions& V, const Options& options)
      : V_(V), options_(options), progress_(options.progress), clock_(report(), progress_) {
    if (options.stretch_iterations < 0)
      throw ParameterizationError("stretch iterations must be 0 or more");
    report().weights = weightSchemeName(options.weights);
    report().boundary = boundaryShapeName(options.boundary);
  }

  void topology(const Triangles& F) {
    clock_.begin(Stage::Topology);
    PatchOptions patch_options;
    patch_options.outer_vertex = options_.outer_boundary_vertex;
    patch_ = buildPatch(V_, F, patch_options);
    report().vertices = patch_.real_vertex_count;
    report().faces = patch_.real_face_count;
    report().holes_filled = patch_.holes_filled;
    report().unreferenced_vertices = static_cast<int>(V_.rows()) - patch_.real_vertex_count;
    linearWork(Stage::Topology,
               WorkCosts::kTopologyFace * (patch_.faceCount() + patch_.vertexCount()));
    shape_ = options_.boundary;
    source_ = userSource(patch_, static_cast<int>(V_.rows()), options_.source_vertex,
                         shape_ == BoundaryShape::Measured);
    clock_.end();
  }

  // The boundary (source choice, walks) runs on this thread while the other cores start on the
  // weights, then joins them: the two do not depend on each other. Their stage times overlap.
  void weightsAndBoundary() {
    clock_.begin(Stage::Weights);
    WeightCounts counts;
    weights_ = computeWeights(patch_, options_.weights, counts, [this] {
      const auto start = Clock::now();
      boundaryPolicy();
      clock_.add(Stage::Boundary, std::chrono::duration<double>(Clock::now() - start).count());
    });
    clock_.end();
    report().fallbacks.add(Fallback::StraightestToLtd, counts.straightest_to_ltd);
    report().fallbacks.add(Fallback::DegenerateRing, counts.degenerate_rings);
    // The boundary runs alongside the weights on another core: only the weights count.
    linearWork(Stage::Weights, weightsWork());
  }

  // Never returns a folded map: first the circle (strictly convex in exact arithmetic), then
  // uniform weights (Tutte, the best-conditioned system), else refuses with the reason.
  void solveOneToOne() {
    solver_.emplace(patch_);
    solveAndMeasure();
    if (metrics_.flipped_faces > 0 && shape_ != BoundaryShape::Circle) {
      fallBackToCircle("the " + std::string(boundaryShapeName(shape_)) + " boundary gave " +
                       std::to_string(metrics_.flipped_faces) + " flipped or degenerate faces");
      clock_.begin(Stage::Boundary);
      boundary_ = circleBoundary(patch_);
      clock_.end();
      solveAndMeasure();
    }
    if (metrics_.flipped_faces > 0 && options_.weights != WeightScheme::Uniform) {
      report().warnings.push_back(
          std::to_string(metrics_.flipped_faces) + " faces folded with " + report().weights +
          " weights (near-degenerate triangles); used uniform weights instead");
      report().fallbacks.add(Fallback::WholeBoundary);
      WeightCounts ignored;
      weights_ = computeWeights(patch_, WeightScheme::Uniform, ignored);
      linearWork(Stage::Weights, weightsWork());
      solveAndMeasure();
    }
    if (metrics_.flipped_faces > 0)
      throw ParameterizationError(
          "no one-to-one map: " + std::to_string(metrics_.flipped_faces) +
          " faces stay flipped or degenerate even with a circle boundary and uniform weights (the "
          "mesh has near-degenerate triangles)");
    report().l2_stretch_linear = metrics_.l2;
  }

  void refine() {
    if (options_.stretch_iterations <= 0) return;
    // One work budget for the three loops (reweighting, ARAP, Newton), counted on one meter;
    // each loop has its own budget object, which records why it stopped and what its last step
    // cost.
    refine_start_ = Clock::now();
    if (options_.refine_work_factor > 0)
      budget_work_ = std::max(options_.refine_min_work, options_.refine_work_factor * linear_work_);
    RefineBudget reweighting = newBudget();
    if (options_.reweight) {
      // Where the grid's Newton steps run, they gain more per unit of work than reweighting
      // after its first step or two: reweighting gets a share of a limited budget.
      const bool shared = gridStepsRun() && std::isfinite(budget_work_);
      if (shared) reweighting.work_limit = kReweightShareBeforeGrid * budget_work_;
      reweight(reweighting);
      clock_.addWork(Stage::Refine, refine_meter_.spent);
      // Its share spent, reweighting hands over: the later stages say why refinement stopped.
      if (!(shared && reweighting.stop == RefineStop::WorkBudget)) noteStop(reweighting);
    } else {
      // The free-boundary steps size their first step by a reweighting step's work.
      reweighting.step_work = solve_work_ + metricsWork();
    }
    report().l2_stretch_fixed_boundary = metrics_.l2;
    // Only the measured boundary is let go: it stands for the patch's own outline, which this
    // refines; a circle or square is a shape the user asked for (and it stays after a fallback
    // from measured to circle, where letting go helps most).
    if (options_.free_boundary && options_.boundary == BoundaryShape::Measured)
      freeBoundary(reweighting);
    report().refinement_stop = refineStopName(stop_);
    report().refinement_work = linear_work_ > 0 ? refine_meter_.spent / linear_work_ : 0;
  }

  // The per-vertex fallbacks' warnings, one per kind that happened, in the rows' order (the
  // whole-boundary ones wrote their reasons as they happened).
  void countFallbacks() {
    Report& r = report();
    r.boundary_used = boundaryShapeName(shape_);
    r.source_vertex = shape_ == BoundaryShape::Measured ? patch_.input_vertex[source_] : -1;
    r.ears_unfolded = shape_ == BoundaryShape::Measured ? measured_counts_.ears_unfolded : 0;
    for (const FallbackKind& kind : kFallbackKinds)
      if (kind.warning && r.fallbacks[kind.id] > 0)
        r.warnings.push_back(std::to_string(r.fallbacks[kind.id]) + kind.warning);
  }

  // The map at its natural scale (3D units), in double, as a layout in the input's numbering
  // (one texture coordinate per vertex), measured: flattenDisk()'s result.
  Result finish(const Triangles& F) {
    UVs uv = UVs::Zero(V_.rows(), 2);
    for (int v = 0; v < patch_.real_vertex_count; ++v)
      uv.row(patch_.input_vertex[v]) = patch_.unit * uv_[v].transpose();
    result_.layout = Layout::perVertex(std::move(uv), F);
    Report& r = report();
    r.l2_stretch = metrics_.l2;
    r.linf_stretch = metrics_.linf;
    r.flipped_faces = metrics_.flipped_faces;
    result_.face_stretch = std::move(metrics_.face_l2);
    r.seconds = std::chrono::duration<double>(Clock::now() - run_start_).count();
    return std::move(result_);
  }

 private:
  Report& report() { return result_.report; }

  void fallBackToCircle(const std::string& why) {
    report().warnings.push_back(why + "; used the circle boundary instead");
    report().fallbacks.add(Fallback::WholeBoundary);
    shape_ = BoundaryShape::Circle;
  }

  // The boundary policy: the shape asked for, unless it cannot serve, then the circle (with the
  // reason as a warning).
  void boundaryPolicy() {
    if (shape_ == BoundaryShape::Measured && source_ < 0)
      source_ = chooseSourceVertex(patch_, options_.source_rule);
    if (shape_ == BoundaryShape::Measured) {
      if (source_ < 0) {
        fallBackToCircle("the patch has no interior vertex to measure the boundary from");
      } else {
        boundary_ = measuredBoundary(patch_, source_, measured_counts_);
        report().fallbacks.add(Fallback::DistanceWalk,
                               measured_counts_.walk_failures + measured_counts_.walk_detours);
        if (boundary_.empty()) {
          fallBackToCircle("the measured boundary could not be made convex");
        } else if (const double ears = earStretch(patch_, boundary_),
                   circle_ears = earStretch(patch_, circleBoundary(patch_));
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
    } else if (shape_ == BoundaryShape::Square) {
      boundary_ = squareBoundary(patch_);
      if (boundary_.empty())
        fallBackToCircle("a square boundary needs at least 4 boundary vertices");
    }
    if (shape_ == BoundaryShape::Circle) boundary_ = circleBoundary(patch_);
  }

  // Solves and measures; a map with flipped faces from the (loose) iterative solve is solved
  // again tightly first: the fold may be the solver's, not the weights' or the boundary's.
  void solveAndMeasure() {
    do {
      clock_.begin(Stage::Solve);
      uv_ = solver_->solve(weights_, boundary_);
      clock_.end();
      clock_.begin(Stage::Metrics);
      metrics_ = stretchMetrics(patch_, uv_);
      clock_.end();
      solve_work_ += solver_->lastStats().work;
      linearWork(Stage::Solve, solver_->lastStats().work);
      linearWork(Stage::Metrics, metricsWork());
    } while (metrics_.flipped_faces > 0 && solver_->tighten());
  }

  RefineBudget newBudget() {
    RefineBudget budget;
    budget.min_gain = options_.refine_min_gain;
    budget.meter = &refine_meter_;
    budget.work_limit = budget_work_;
    if (options_.time_limit_seconds > 0)
      budget.deadline =
          refine_start_ + std::chrono::duration_cast<Clock::duration>(
                              std::chrono::duration<double>(options_.time_limit_seconds));
    return budget;
  }

  // The work of the weights over every ring entry (straightest and LTD walk planes; the
  // others are closed formulas).
  double weightsWork() const {
    return static_cast<double>(patch_.ring_vertex.size()) * WorkCosts::kWeightEntry *
           kWeightSchemes[static_cast<size_t>(options_.weights)].work_per_entry;
  }
  double metricsWork() const { return WorkCosts::kMetricsFace * patch_.real_face_count; }
  void linearWork(Stage stage, double work) {
    linear_work_ += work;
    clock_.addWork(stage, work);
  }

  // Whether the Newton stage starts with the coarse grid's steps (stretch_newton.h).
  bool gridStepsRun() const {
    return options_.free_boundary && options_.boundary == BoundaryShape::Measured &&
           stretchNewtonIsMatrixFree(patch_.real_vertex_count) &&
           StretchNewtonSettings().grid_max_steps > 0;  // the settings refine() passes
  }

  static bool outOfBudget(RefineStop stop) {
    return stop == RefineStop::WorkBudget || stop == RefineStop::TimeLimit;
  }
  // Why refinement ended: running out of budget wins when any loop did.
  void noteStop(const RefineBudget& budget) {
    if (outOfBudget(budget.stop) || !outOfBudget(stop_))
      stop_ = budget.stop == RefineStop::NotRun ? RefineStop::Iterations : budget.stop;
  }

  // Yoshizawa-Belyaev-Seidel reweighting on the fixed boundary, each step a linear solve.
  void reweight(const RefineBudget& budget) {
    // eta 0.5 reaches the lowest stretch in 5-10 steps, eta 1 gets most of the way in 2-3
    // (face.off, fixed boundary: L2 1.41 after 2 steps against 1.78). When the budget affords
    // fewer than 6 steps (each costs about the linear solve and its measure), the faster one
    // is used.
    double eta = options_.stretch_exponent;
    const double step_work = solve_work_ + metricsWork();
    if (std::isfinite(budget_work_) && budget_work_ < kFewRefinementSteps * step_work)
      eta = std::max(eta, kFastStretchExponent);

    if (gridStepsRun() && std::isfinite(budget_work_)) solver_->loosen(kNewtonStartTolerance);
    clock_.begin(Stage::Refine);
    std::vector<double> refined = weights_;
    StretchMetrics current = metrics_;
    const int steps = options_.stretch_iterations;
    for (int it = 1; it <= steps; ++it) {
      progress_.report(Stage::Refine, it, steps);
      if (it > 1 && budget.expired()) break;
      const auto iteration_start = Clock::now();
      reweightByStretch(patch_, current.vertex_l2, eta, refined);
      double work = 2.0 * patch_.ring_vertex.size() * WorkCosts::kNonzero;
      LocalUVs candidate;
      do {
        candidate = solver_->solve(refined, boundary_);
        current = stretchMetrics(patch_, candidate);
        work += solver_->lastStats().work + metricsWork();
      } while (current.flipped_faces > 0 && solver_->tighten());
      report().stretch_iterations_run = it;
      budget.charge(work);
      budget.step_work = work;
      budget.step_seconds = std::chrono::duration<double>(Clock::now() - iteration_start).count();
      if (current.flipped_faces > 0) break;  // numerically folded: keep the best so far
      const bool gained = budget.gained(metrics_.l2, current.l2);
      if (current.l2 < metrics_.l2) {
        metrics_ = current;
        uv_.swap(candidate);
        report().best_iteration = it;
      }
      if (!gained) break;
    }
    clock_.end();
  }

  // ARAP steps, then Newton steps on the L2 stretch itself: they go on where ARAP's optimum
  // folds.
  void freeBoundary(const RefineBudget& reweighting) {
    progress_.report(Stage::FreeBoundary);
    clock_.begin(Stage::FreeBoundary);
    FreeBoundaryCounts counts;
    const RefineBudget arap = newBudget();
    // The first ARAP step with its setup costs about three reweighting solves (2.5x measured
    // at 1.65M vertices): not started when that would overrun the budget.
    arap.step_work = 3 * reweighting.step_work;
    arap.step_seconds = 3 * reweighting.step_seconds;
    double spent = refine_meter_.spent;
    // The grid's Newton steps make the large moves ARAP was there for, towards the stretch's
    // own optimum rather than ARAP's: ARAP first cost 2.7 s and ended higher on face s2
    // (docs/measurements.md).
    const int arap_steps = gridStepsRun() ? 0 : options_.stretch_iterations;
    uv_ = relaxWithFreeBoundary(patch_, uv_, arap_steps, metrics_, counts, progress_, arap);
    noteStop(arap);
    clock_.addWork(Stage::FreeBoundary, refine_meter_.spent - spent);
    clock_.end();
    clock_.begin(Stage::Newton);
    spent = refine_meter_.spent;
    StretchNewtonCounts newton;
    const RefineBudget newton_budget = newBudget();
    // Without the sparse factor a fine Newton step costs several grid steps: neither is
    // started when it would overrun.
    StretchNewtonSettings settings;
    if (stretchNewtonIsMatrixFree(patch_.real_vertex_count)) {
      settings.first_fine_step_work = firstFineNewtonStepWork(patch_.real_face_count);
      newton_budget.step_work = gridStepsRun() ? gridNewtonStepWork(patch_.real_face_count)
                                               : settings.first_fine_step_work;
      newton_budget.step_seconds =
          reweighting.step_seconds * newton_budget.step_work / std::max(reweighting.step_work, 1.0);
    }
    uv_ = minimizeStretchWithFreeBoundary(patch_, uv_, options_.stretch_iterations, metrics_,
                                          newton, progress_, newton_budget, settings);
    noteStop(newton_budget);
    clock_.addWork(Stage::Newton, refine_meter_.spent - spent);
    report().free_boundary_steps = counts.steps_taken + newton.steps_taken;
    clock_.end();
  }

  const Clock::time_point run_start_ = Clock::now();
  const Positions& V_;
  const Options& options_;
  Result result_;
  Progress progress_;
  StageClock clock_;
  Patch patch_;
  BoundaryShape shape_ = BoundaryShape::Measured;
  int source_ = -1;
  Polygon boundary_;
  MeasuredCounts measured_counts_;
  std::vector<double> weights_;
  std::optional<InteriorSolver> solver_;
  LocalUVs uv_;
  StretchMetrics metrics_;
  Clock::time_point refine_start_;
  double linear_work_ = 0;  // work.h: everything before refinement
  double solve_work_ = 0;   // the linear solves' work, to predict a reweighting step
  double budget_work_ = std::numeric_limits<double>::infinity();
  WorkMeter refine_meter_;
  RefineStop stop_ = RefineStop::Iterations;
};

Result flattenDiskChecked(const Positions& V, const Triangles& F, const Options& options) {
  Pipeline run(V, options);
  run.topology(F);
  run.weightsAndBoundary();
  run.solveOneToOne();
  run.refine();
  run.countFallbacks();
  return run.finish(F);
}

// The store step on a flattened result (storage.h), timed and reported as the "storage" stage:
// the report then describes exactly the stored values.
void storeChecked(const Positions& V, const Triangles& F, const StoragePolicy& policy,
                  const Progress& progress, Result& result) {
  const auto start = Clock::now();
  progress.report(Stage::Storage);
  const StorageCounts storage = store(result.layout, policy);
  StretchMetrics stored = layoutStretch(V, F, result.layout);
  Report& r = result.report;
  r.storage = uvStorageName(policy.precision);
  r.storage_degenerate_faces = storage.degenerate_faces;
  r.storage_moved_vertices = storage.moved_vertices;
  // Repaired, so not a warning: the stored map is one-to-one.
  if (storage.degenerate_faces > 0)
    r.notes.push_back("stored one-to-one: " + std::to_string(storage.degenerate_faces) +
                      " faces would have collapsed when rounded to " + r.storage +
                      " texture coordinates; " + std::to_string(storage.moved_vertices) +
                      " vertices moved");
  r.l2_stretch = stored.l2;
  r.linf_stretch = stored.linf;
  r.flipped_faces = stored.flipped_faces;
  if (r.flipped_faces > 0)
    throw ParameterizationError("internal error: the stored map has flipped faces");
  result.face_stretch = std::move(stored.face_l2);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  r.stage_seconds.emplace_back(stageRow(Stage::Storage).key, seconds);
  r.seconds += seconds;
}

}  // namespace

}  // namespace sdp
