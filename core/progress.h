// The run's progress bar in one place: the stages in run order, each with its share of the bar,
// and the one way a cancel is signalled (ParameterizationError "cancelled by the user").
#pragma once

#include <utility>

#include "error.h"
#include "options.h"

namespace sdp {

enum class Stage {
  Topology,
  Weights,
  Boundary,  // a fallback boundary, made after the weights
  Solve,
  Metrics,
  Refine,
  FreeBoundary,
  Newton,
  Storage,
  Done
};

class Progress {
 public:
  Progress() = default;
  explicit Progress(ProgressCallback callback) : callback_(std::move(callback)) {}

  // Reports `stage` after `step` of its `steps` (its start by default); throws when the
  // callback says stop.
  void report(Stage stage, int step = 0, int steps = 1) const {
    if (!callback_) return;
    const Span span = spanOf(stage);
    const int percent = span.from + (span.to - span.from) * step / steps;
    if (!callback_(span.name, percent)) throw ParameterizationError("cancelled by the user");
  }
  // The end of the run: reported, never cancelled.
  void done() const {
    if (callback_) callback_(spanOf(Stage::Done).name, 100);
  }

 private:
  struct Span {
    const char* name;  // what the front ends show
    int from, to;      // percent of the whole run
  };
  static Span spanOf(Stage stage) {
    // In enum order. The weights and boundary overlap; the solve and metrics may run again
    // after a fallback, and refinement takes about as long as the rest when it runs.
    static const Span spans[] = {
        {"topology", 0, 10},       {"weights", 10, 40},       {"boundary", 40, 40},
        {"solve", 40, 80},         {"metrics", 80, 85},       {"refine", 85, 95},
        {"free boundary", 95, 97}, {"free boundary", 97, 98}, {"storage", 98, 100},
        {"done", 100, 100},
    };
    return spans[static_cast<int>(stage)];
  }

  ProgressCallback callback_;
};

}  // namespace sdp
