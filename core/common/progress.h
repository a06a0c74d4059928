// The run's stages in one table: in run order, each with the key the report times and counts it
// under (stage_seconds, stage_work), the label the front ends' progress bars show and its share
// of the bar; and the one way a cancel is signalled (ParameterizationError "cancelled by the
// user").
#pragma once

#include <iterator>
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

struct StageRow {
  Stage id;
  const char* key;    // report key: stage_seconds / stage_work
  const char* label;  // what the front ends show
  int from, to;       // percent of the whole run
};

// In enum order. The weights and boundary overlap; the solve and metrics may run again after a
// fallback, and refinement takes about as long as the rest when it runs.
inline constexpr StageRow kStages[] = {
    {Stage::Topology, "topology", "topology", 0, 10},
    {Stage::Weights, "weights", "weights", 10, 40},
    {Stage::Boundary, "boundary", "boundary", 40, 40},
    {Stage::Solve, "solve", "solve", 40, 80},
    {Stage::Metrics, "metrics", "metrics", 80, 85},
    {Stage::Refine, "refine", "refine", 85, 95},
    {Stage::FreeBoundary, "free_boundary", "free boundary", 95, 97},
    {Stage::Newton, "newton", "free boundary", 97, 98},
    {Stage::Storage, "storage", "storage", 98, 100},
    {Stage::Done, "done", "done", 100, 100},
};
constexpr const StageRow& stageRow(Stage stage) {
  return kStages[static_cast<int>(stage)];
}
constexpr bool stagesInOrder() {
  for (int i = 0; i < static_cast<int>(std::size(kStages)); ++i)
    if (static_cast<int>(kStages[i].id) != i) return false;
  return true;
}
static_assert(stagesInOrder() && std::size(kStages) == static_cast<size_t>(Stage::Done) + 1);

class Progress {
 public:
  Progress() = default;
  explicit Progress(ProgressCallback callback) : callback_(std::move(callback)) {}

  // Reports `stage` after `step` of its `steps` (its start by default); throws when the
  // callback says stop.
  void report(Stage stage, int step = 0, int steps = 1) const {
    if (!callback_) return;
    const StageRow& row = stageRow(stage);
    const int percent = row.from + (row.to - row.from) * step / steps;
    if (!callback_(row.label, percent)) throw ParameterizationError("cancelled by the user");
  }
  // The end of the run: reported, never cancelled.
  void done() const {
    if (callback_) callback_(stageRow(Stage::Done).label, 100);
  }

 private:
  ProgressCallback callback_;
};

}  // namespace sdp
