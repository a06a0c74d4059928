// When refinement stops (docs/method.md §4): after `stretch_iterations` steps of a loop, at the
// first step that lowers the L2 stretch by less than a relative `min_gain` (measured progress),
// or when the refinement has used its work budget (a multiple of the linear map's own work,
// work.h, so large patches cost a bounded factor more than the paper's method). Work is counted,
// not timed: the same mesh and options stop at the same step on every run. Only an explicit
// wall-clock limit (the command line's --time-limit) reads a clock, and then the result may
// depend on the machine's load, as its user asked.
#pragma once

#include <chrono>
#include <limits>

#include "core/common/work.h"

namespace sdp {

enum class RefineStop { NotRun, Iterations, Converged, WorkBudget, TimeLimit };
const char* refineStopName(RefineStop stop);

struct RefineBudget {
  using Clock = std::chrono::steady_clock;
  // Work all refinement loops of a run may spend together, counted on `meter` (shared by them);
  // no meter: no work limit.
  double work_limit = std::numeric_limits<double>::infinity();
  WorkMeter* meter = nullptr;
  Clock::time_point deadline = Clock::time_point::max();  // wall-clock limit, when asked for
  double min_gain = 0;  // relative L2 decrease a step must reach for the loop to go on; 0: none
  mutable RefineStop stop = RefineStop::NotRun;

  // The next step's expected work and seconds (the last step's, recorded by the loop): a step
  // that would end past the budget is not started.
  mutable double step_work = 0;
  mutable double step_seconds = 0;

  bool expired() const {
    if (meter && meter->spent + step_work > work_limit) {
      stop = RefineStop::WorkBudget;
      return true;
    }
    if (deadline == Clock::time_point::max()) return false;
    const auto step =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(step_seconds));
    if (Clock::now() + step < deadline) return false;
    stop = RefineStop::TimeLimit;
    return true;
  }
  // Adds work done by a loop.
  void charge(double work) const {
    if (meter) meter->spent += work;
  }
  // True when `after` is worth another step after `before`; else records convergence.
  bool gained(double before, double after) const {
    if (!(min_gain > 0) || after < before * (1 - min_gain)) return true;
    stop = RefineStop::Converged;
    return false;
  }
};

}  // namespace sdp
