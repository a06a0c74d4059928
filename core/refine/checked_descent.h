// The skeleton both free-boundary refinements share (free_boundary.h's as-rigid-as-possible
// steps, stretch_newton.h's Newton steps), written once: each step asks for progress and the
// work budget, proposes a direction, and is then tried at decreasing lengths until the map stays
// one-to-one (no face flipped or collapsed, the boundary not crossing itself) and passes the
// method's own test; the map with the lowest L2 stretch is kept. Virtual hole-fill vertices
// (index >= real_vertex_count) never move.
#pragma once

#include <functional>
#include <vector>

#include "core/common/metrics.h"
#include "core/common/patch.h"
#include "core/common/progress.h"
#include "core/paper/solve.h"
#include "free_boundary.h"
#include "refine_budget.h"

namespace sdp {

class CheckedDescent {
 public:
  // `start` is one-to-one with its metrics in `metrics`, which follows the best map (with
  // measureL2By: set once, by takeBest()).
  CheckedDescent(const Patch& patch, const LocalUVs& start, StretchMetrics& metrics,
                 const RefineBudget& budget, const Progress& progress, Stage stage);

  // Before step `step` of `steps`: reports progress (throws when the user cancels) and returns
  // false when the budget has no room for another step. The previous step's work (and time)
  // is the budget's prediction for this one; the first step's prediction is the caller's.
  bool beginStep(int step, int steps);
  // Work (work.h) the method did for the current step (its direction); tryStep() counts its
  // own checks.
  void addWork(double work);
  // The next step is of another kind, expected to cost `work`: the budget's prediction for it
  // (work, and seconds in proportion) instead of the last step's.
  void expectNextStepWork(double work);

  struct Outcome {
    bool taken = false;   // a length passed every check; current() moved
    int halvings = 0;     // how often the length was halved before that
    bool gained = false;  // it lowered the best L2 by the budget's minimum gain
  };
  // Tries current() + length * direction for length, length / 2, ... (`max_halvings` halvings at
  // most). `admit` (may be empty) is the method's own test, run first; it may change the
  // candidate (e.g. rescale it). Only the first real_vertex_count entries of `direction` count.
  Outcome tryStep(const LocalUVs& direction, double length, int max_halvings,
                  const std::function<bool(LocalUVs& candidate, double length)>& admit = {});

  // The method measures each taken step's L2 itself (`l2_of`, called once the checks pass;
  // `start_l2` the start's by the same measure), and the full metrics are measured once, by
  // takeBest(), on the best map: each step then skips stretchMetrics' pass over the faces.
  // `start` (the constructor's, which must outlive this) is what takeBest() falls back to: no
  // copy of it is kept (at 1.65M vertices one would raise the run's peak memory).
  void measureL2By(std::function<double()> l2_of, double start_l2, const LocalUVs& start);
  const LocalUVs& current() const { return current_; }
  LocalUVs& current() { return current_; }  // for a method's own rescaling of the start
  // The map with the lowest L2 seen (its metrics in `metrics`); the start if none was lower.
  // With measureL2By, also the start when the metrics do not rank the best map lower or cannot
  // be measured (out of memory): fellBack() then says so. Its measure is charged to the budget
  // after the last step (60 units per face, under half a grid step), not predicted.
  LocalUVs takeBest();
  bool fellBack() const { return fell_back_; }

 private:
  const Patch& patch_;
  StretchMetrics& metrics_;
  const RefineBudget& budget_;
  const Progress& progress_;
  Stage stage_;
  std::vector<BorderEdge> border_;  // the same for every check
  int keeps_clearance_ = -1;        // -1 undecided; keepsClearance()
  bool keepsClearance();
  LocalUVs current_, candidate_, best_;
  std::function<double()> l2_of_;    // measureL2By's
  double best_l2_ = 0;               // by l2_of_
  bool best_moved_ = false;          // a step beat the start (by l2_of_)
  bool fell_back_ = false;           // takeBest() returned the start over a better-measured map
  const LocalUVs* start_ = nullptr;  // measureL2By's
  RefineBudget::Clock::time_point step_start_;
  bool stepped_ = false;      // a step has begun
  double step_work_ = 0;      // the current step's work so far
  double expected_work_ = 0;  // expectNextStepWork's, until the next step begins (0: none)
};

}  // namespace sdp
