// When refinement stops (docs/method.md §4): after `stretch_iterations` steps of a loop, at the
// first step that lowers the L2 stretch by less than a relative `min_gain` (measured progress),
// or when the refinement has used its time (a multiple of the linear map's own time, so large
// patches cost a bounded factor more than the paper's method).
#pragma once

#include <chrono>

namespace sdp {

enum class RefineStop { NotRun, Iterations, Converged, TimeBudget };
const char* refineStopName(RefineStop stop);

struct RefineBudget {
  using Clock = std::chrono::steady_clock;
  Clock::time_point deadline = Clock::time_point::max();
  double min_gain = 0;  // relative L2 decrease a step must reach for the loop to go on; 0: none
  mutable RefineStop stop = RefineStop::NotRun;

  // Seconds the next step is expected to take (the last one's, measured by the loop): a step
  // that would end past the deadline is not started.
  mutable double step_seconds = 0;

  bool expired() const {
    const auto step =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(step_seconds));
    if (deadline == Clock::time_point::max() || Clock::now() + step < deadline) return false;
    stop = RefineStop::TimeBudget;
    return true;
  }
  // True when `after` is worth another step after `before`; else records convergence.
  bool gained(double before, double after) const {
    if (!(min_gain > 0) || after < before * (1 - min_gain)) return true;
    stop = RefineStop::Converged;
    return false;
  }
};

}  // namespace sdp
