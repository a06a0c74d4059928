// What the user gets back besides the UVs: docs/method.md §5 metrics and §6 report keys.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace sdp {

// The pipeline's fallbacks, one row per kind: its key in the report's `fallback_counts`, what it
// means, the words of MeshLab's log line and, for the kinds counted per vertex, the warning after
// the count (a whole-boundary fallback writes its own reason where it happens).
enum class Fallback { StraightestToLtd, DegenerateRing, DistanceWalk, WholeBoundary };
struct FallbackKind {
  Fallback id;
  const char* key;
  const char* meaning;
  const char* log_label;
  const char* warning;
};
inline constexpr std::array<FallbackKind, 4> kFallbackKinds = {{
    {Fallback::StraightestToLtd, "straightest_to_ltd",
     "neighbours whose cutting plane crossed no far-side edge, given the LTD direction",
     "straightest->ltd",
     " neighbours used the LTD direction (their cutting plane crossed no far-side edge)"},
    {Fallback::DegenerateRing, "degenerate_rings",
     "vertices with a zero-area face or zero-length edge at them, given uniform weights",
     "degenerate rings", " vertices with a degenerate 1-ring used uniform weights"},
    {Fallback::DistanceWalk, "walk_fallbacks",
     "boundary distances taken from edge paths because the plane walk missed its vertex or "
     "wandered more than 1.5x the edge-path length",
     "walks", " boundary distances used the edge-graph distance (plane walk failed or wandered)"},
    {Fallback::WholeBoundary, "boundary_fallbacks",
     "whole-boundary fallbacks, e.g. measured to circle, or uniform weights after a fold",
     "boundary", nullptr},
}};

struct FallbackRecord {
  std::array<int, kFallbackKinds.size()> counts{};
  void add(Fallback kind, int count = 1) { counts[static_cast<size_t>(kind)] += count; }
  int operator[](Fallback kind) const { return counts[static_cast<size_t>(kind)]; }
  int total() const {
    int sum = 0;
    for (int c : counts) sum += c;
    return sum;
  }
};

// Per-stage amounts (seconds or work) in the order stages were first met.
using StageAmounts = std::vector<std::pair<std::string, double>>;

// Adds `amount` to the entry `key`, or appends it.
inline void addToStage(StageAmounts& stages, const std::string& key, double amount) {
  for (auto& entry : stages)
    if (entry.first == key) {
      entry.second += amount;
      return;
    }
  stages.emplace_back(key, amount);
}

struct Report {
  int vertices = 0;  // vertices referenced by the patch
  int faces = 0;
  std::string weights;        // scheme asked for (CLI name)
  std::string boundary;       // boundary asked for (CLI name)
  std::string boundary_used;  // boundary actually used (differs after a safety fallback)
  int source_vertex = -1;     // input index of S (measured boundary), else -1
  double l2_stretch = 0;      // Sander L2, 1.0 = isometric
  double linf_stretch = 0;    // Sander L-infinity (worst face)
  int flipped_faces = 0;      // faces with non-positive signed UV area in the returned map
  int stretch_iterations_run = 0;
  int best_iteration = 0;                // iteration whose map was kept (0 = linear solve)
  double l2_stretch_linear = 0;          // L2 of the linear map before refinement
  double l2_stretch_fixed_boundary = 0;  // L2 after the reweighting, before the free boundary
  int free_boundary_steps = 0;           // free-boundary steps taken (0: the boundary stayed)
  // Why refinement ended (refine_budget.h): "iterations", "converged", "work budget" or "time
  // limit" (running out wins when any loop did); "not run" for the linear map.
  std::string refinement_stop = "not run";
  // Work (work.h) the refinement spent, as a multiple of the linear map's.
  double refinement_work = 0;
  // Every fallback, counted by kind where it happens (kFallbackKinds).
  FallbackRecord fallbacks;
  int ears_unfolded = 0;  // measured boundary: ear apexes placed with their own shape (boundary.h)
  int unreferenced_vertices = 0;
  int holes_filled = 0;  // inner boundary loops filled virtually for the solve
  // The UVs as stored (Options::storage.precision): l2/linf/flips above describe them. Faces that
  // rounding would have flipped or collapsed, and the vertices moved to keep them one-to-one.
  std::string storage = "double";
  int storage_degenerate_faces = 0;
  int storage_moved_vertices = 0;
  double seconds = 0;  // wall time of the parameterization (no file I/O)
  std::vector<std::pair<std::string, double>> stage_seconds;  // in run order
  // Work (work.h) per stage, in run order: what the budget counts instead of seconds.
  std::vector<std::pair<std::string, double>> stage_work;
  std::vector<std::string> warnings;  // one line each, for logs
  std::vector<std::string> notes;     // what was done that needs no action (e.g. a storage repair)

  // JSON object with a key per reportFields() row, in its order.
  std::string toJson() const;
};

// One row of the report's table: the JSON key and what it means. The `summary` rows are the
// docs/method.md §6 values every front end shows: the pymeshlab dict, the log's summary line and
// the first keys of the JSON report.
struct ReportField {
  const char* key;      // JSON key, and the pymeshlab dict key of a summary row
  const char* meaning;  // for docs/usage.md
  bool summary = false;
  bool integer = false;                          // summary rows: an int (else a double)
  const char* log_label = nullptr;               // summary rows: the words before the value
  const char* log_format = nullptr;              // summary rows: printf format of the value
  double (*number)(const Report&) = nullptr;     // numeric rows
  std::string (*json)(const Report&) = nullptr;  // other rows: the JSON text of the value
  std::string jsonValue(const Report& r) const;  // either kind
};
const std::vector<ReportField>& reportFields();

}  // namespace sdp
