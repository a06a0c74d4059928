#include "checked_descent.h"

#include <chrono>
#include <new>
#include <utility>

#include "core/common/work.h"

namespace sdp {

CheckedDescent::CheckedDescent(const Patch& patch, const LocalUVs& start, StretchMetrics& metrics,
                               const RefineBudget& budget, const Progress& progress, Stage stage)
    : patch_(patch),
      metrics_(metrics),
      budget_(budget),
      progress_(progress),
      stage_(stage),
      border_(boundaryEdges(patch)),
      current_(start),
      best_(start) {}

bool CheckedDescent::beginStep(int step, int steps) {
  progress_.report(stage_, step, steps);
  if (stepped_) {
    budget_.step_work = step_work_;
    budget_.step_seconds =
        std::chrono::duration<double>(RefineBudget::Clock::now() - step_start_).count();
    if (expected_work_ > 0 && step_work_ > 0) {
      budget_.step_seconds *= expected_work_ / step_work_;
      budget_.step_work = expected_work_;
    }
    expected_work_ = 0;
  }
  if (budget_.expired()) return false;
  stepped_ = true;
  step_work_ = 0;
  step_start_ = RefineBudget::Clock::now();
  return true;
}

void CheckedDescent::expectNextStepWork(double work) {
  expected_work_ = work;
}

void CheckedDescent::addWork(double work) {
  step_work_ += work;
  budget_.charge(work);
}

bool CheckedDescent::keepsClearance() {
  // Decided on the first step's start (after any rescaling by the method): a start already
  // closer than the clearance (a tiny border edge) keeps the plain simplicity test, so the
  // refinement never does less than before.
  if (keeps_clearance_ < 0)
    keeps_clearance_ = edgesAreSimple(border_, current_, borderClearance(border_, current_));
  return keeps_clearance_ > 0;
}

CheckedDescent::Outcome CheckedDescent::tryStep(
    const LocalUVs& direction, double length, int max_halvings,
    const std::function<bool(LocalUVs& candidate, double length)>& admit) {
  const int n = patch_.real_vertex_count;
  Outcome outcome;
  candidate_ = current_;  // the entries no step moves (hole fills) as in current()
  const double faces = patch_.real_face_count;
  for (int halvings = 0; halvings <= max_halvings; ++halvings, length *= 0.5) {
    for (int v = 0; v < n; ++v) candidate_[v] = current_[v] + length * direction[v];
    addWork(n * WorkCosts::kVectorEntry);
    if (admit && !admit(candidate_, length)) continue;
    addWork(faces * WorkCosts::kFlipCheckFace);
    if (hasFlippedFace(patch_, candidate_)) continue;
    // The sweep sorts the border edges, then tests the few whose x ranges overlap.
    addWork(20.0 * border_.size() * WorkCosts::kNonzero);
    if (!edgesAreSimple(border_, candidate_,
                        keepsClearance() ? borderClearance(border_, candidate_) : 0))
      continue;
    if (l2_of_) {
      outcome.taken = true;
      outcome.halvings = halvings;
      current_.swap(candidate_);
      const double l2 = l2_of_();
      outcome.gained = budget_.gained(best_l2_, l2);
      if (l2 < best_l2_) {
        best_l2_ = l2;
        best_ = current_;
        best_moved_ = true;
      }
      break;
    }
    addWork(faces * WorkCosts::kMetricsFace);
    StretchMetrics measured = stretchMetrics(patch_, candidate_);
    if (measured.flipped_faces > 0) continue;  // the same rule; kept as the last word
    outcome.taken = true;
    outcome.halvings = halvings;
    current_.swap(candidate_);
    outcome.gained = budget_.gained(metrics_.l2, measured.l2);
    if (measured.l2 < metrics_.l2) {
      metrics_ = std::move(measured);
      best_ = current_;
    }
    break;
  }
  return outcome;
}

void CheckedDescent::measureL2By(std::function<double()> l2_of, double start_l2,
                                 const LocalUVs& start) {
  l2_of_ = std::move(l2_of);
  best_l2_ = start_l2;
  start_ = &start;
}

LocalUVs CheckedDescent::takeBest() {
  // best_moved_ is only set with measureL2By; l2_of_ itself is not called here (the caller's
  // locals it reads may be gone, in the caller's out-of-memory handler).
  if (!best_moved_) return std::move(best_);
  addWork(patch_.real_face_count * WorkCosts::kMetricsFace);
  StretchMetrics measured;
  try {
    measured = stretchMetrics(patch_, best_);
  } catch (const std::bad_alloc&) {  // called from the methods' own out-of-memory handlers
    fell_back_ = true;
    return *start_;
  }
  // The method's measure and the metrics' differ in rounding (and on faces too small for a
  // frame): the start stays when the metrics do not rank the best map lower.
  if (measured.flipped_faces > 0 || !(measured.l2 < metrics_.l2)) {
    fell_back_ = true;
    return *start_;
  }
  metrics_ = std::move(measured);
  return std::move(best_);
}

}  // namespace sdp
