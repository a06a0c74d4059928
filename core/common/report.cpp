#include "report.h"

#include "json.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace sdp {
namespace {

using json::jsonInt;
using json::jsonList;
using json::jsonNumber;
using json::jsonNumbers;
using json::jsonObject;
using json::jsonString;

// `fallback_counts`'s meaning, from kFallbackKinds.
const char* fallbackCountsMeaning() {
  static const std::string text = [] {
    std::string t;
    for (const FallbackKind& kind : kFallbackKinds)
      t += (t.empty() ? "`" : ", `") + std::string(kind.key) + "` (" + kind.meaning + ")";
    return t;
  }();
  return text.c_str();
}

ReportField summary(const char* key, const char* meaning, const char* log_label,
                    const char* log_format, bool integer, double (*number)(const Report&)) {
  ReportField f{key, meaning};
  f.summary = true;
  f.integer = integer;
  f.log_label = log_label;
  f.log_format = log_format;
  f.number = number;
  return f;
}
ReportField integer(const char* key, const char* meaning, double (*number)(const Report&)) {
  ReportField f{key, meaning};
  f.integer = true;
  f.number = number;
  return f;
}
ReportField real(const char* key, const char* meaning, double (*number)(const Report&)) {
  ReportField f{key, meaning};
  f.number = number;
  return f;
}
ReportField other(const char* key, const char* meaning, std::string (*json)(const Report&)) {
  ReportField f{key, meaning};
  f.json = json;
  return f;
}

}  // namespace

std::string ReportField::jsonValue(const Report& r) const {
  if (json) return json(r);
  return integer ? jsonInt(static_cast<int>(number(r))) : jsonNumber(number(r));
}

namespace {

using R = const Report&;

// The summary rows: what every front end shows.
std::vector<ReportField> summaryFields() {
  return {
      summary("l2_stretch",
              "Sander et al. L2 texture stretch of the map as stored, area-weighted, normalized so "
              "1.0 is "
              "isometric",
              "L2 stretch", "%.4f", false, [](R r) { return r.l2_stretch; }),
      summary("linf_stretch", "the worst face's largest stretch (same normalization)",
              "Linf stretch", "%.4f", false, [](R r) { return r.linf_stretch; }),
      summary(
          "flipped_faces",
          "faces with non-positive UV area as stored: always 0 (a run that cannot reach 0 fails)",
          "flipped faces", "%.0f", true, [](R r) { return double(r.flipped_faces); }),
      summary("fallbacks",
              "per-neighbour, per-ring and per-walk fallbacks plus whole-boundary ones, summed "
              "(`fallback_counts` breaks it down)",
              "fallbacks", "%.0f", true, [](R r) { return double(r.fallbacks.total()); }),
      summary("source_vertex",
              "S of the measured boundary (a vertex index of the input mesh), -1 for circle and "
              "square",
              "source vertex", "%.0f", true, [](R r) { return double(r.source_vertex); }),
      summary("seconds",
              "wall time of the parameterization (topology, weights, boundary, solve, "
              "refinement, metrics), no file I/O",
              "seconds", "%.3f", false, [](R r) { return r.seconds; }),
  };
}

// The patch, the choices and the refinement.
std::vector<ReportField> runFields() {
  return {
      integer("vertices",
              "vertices of the patch (unreferenced ones are left out and counted below)",
              [](R r) { return double(r.vertices); }),
      integer("faces", "faces of the patch", [](R r) { return double(r.faces); }),
      other("weights", "the weights asked for (CLI name)",
            [](R r) { return jsonString(r.weights); }),
      other("boundary", "the boundary asked for (CLI name)",
            [](R r) { return jsonString(r.boundary); }),
      other("boundary_used", "the boundary actually used (differs after a safety fallback)",
            [](R r) { return jsonString(r.boundary_used); }),
      integer("stretch_iterations", "refinement steps run",
              [](R r) { return double(r.stretch_iterations_run); }),
      integer("best_iteration", "the step whose map was kept (0 = the linear map)",
              [](R r) { return double(r.best_iteration); }),
      real("l2_stretch_linear", "L2 of the linear map before refinement",
           [](R r) { return r.l2_stretch_linear; }),
      real("l2_stretch_fixed_boundary",
           "L2 after the reweighting on the fixed boundary, before the boundary was let go",
           [](R r) { return r.l2_stretch_fixed_boundary; }),
      integer("free_boundary_steps",
              "free-boundary steps taken, as-rigid-as-possible and Newton together (0: the "
              "boundary stayed)",
              [](R r) { return double(r.free_boundary_steps); }),
      other("refinement_stop",
            "why refinement ended: `iterations`, `converged`, `work budget`, `time limit` (the "
            "command line's `--time-limit`), or `not run`",
            [](R r) { return jsonString(r.refinement_stop); }),
      real("refinement_work",
           "work the refinement did, as a multiple of the linear map's (counted from sizes and "
           "iterations, not timed: the same on every run)",
           [](R r) { return r.refinement_work; }),
  };
}

// The counts, the storage, the stages and the messages.
std::vector<ReportField> detailFields() {
  return {
      other("fallback_counts", fallbackCountsMeaning(),
            [](R r) {
              std::vector<std::pair<std::string, std::string>> counts;
              for (const FallbackKind& kind : kFallbackKinds)
                counts.emplace_back(kind.key, jsonInt(r.fallbacks[kind.id]));
              return jsonObject(counts);
            }),
      integer("unreferenced_vertices", "input vertices no face uses (left out of the map)",
              [](R r) { return double(r.unreferenced_vertices); }),
      integer("holes_filled",
              "inner boundary loops filled virtually for the solve (removed from the result)",
              [](R r) { return double(r.holes_filled); }),
      integer("ears_unfolded",
              "measured boundary: ear apexes (boundary vertices of one face) placed across their "
              "chord with the ear's own shape instead of on the convex polygon",
              [](R r) { return double(r.ears_unfolded); }),
      other("storage",
            "`precision` the UVs are stored in (`double`, `float`, `float, 6 decimals`), "
            "`degenerate_faces` that rounding would have collapsed, `moved_vertices` the repair "
            "moved",
            [](R r) {
              return jsonObject({{"precision", jsonString(r.storage)},
                                 {"degenerate_faces", jsonInt(r.storage_degenerate_faces)},
                                 {"moved_vertices", jsonInt(r.storage_moved_vertices)}});
            }),
      other("stage_seconds", "seconds per stage, in run order",
            [](R r) { return jsonNumbers(r.stage_seconds); }),
      other("stage_work",
            "work per stage in units of about a nanosecond of one core here, counted from sizes "
            "and iterations (what the refinement budget counts; the same on every run)",
            [](R r) { return jsonNumbers(r.stage_work); }),
      other("warnings", "one line per fallback or notice (the CLI also prints them to stderr)",
            [](R r) { return jsonList(r.warnings, jsonString); }),
      other(
          "notes",
          "what was done that needs no action (a storage repair); in MeshLab's log as plain lines",
          [](R r) { return jsonList(r.notes, jsonString); }),
  };
}

}  // namespace

const std::vector<ReportField>& reportFields() {
  static const std::vector<ReportField> fields = [] {
    std::vector<ReportField> all = summaryFields();
    for (auto part : {runFields, detailFields}) {
      const std::vector<ReportField> rows = part();
      all.insert(all.end(), rows.begin(), rows.end());
    }
    return all;
  }();
  return fields;
}

std::string Report::toJson() const {
  const std::vector<ReportField>& fields = reportFields();
  std::ostringstream o;
  o << "{\n";
  for (size_t i = 0; i < fields.size(); ++i) {
    o << "  " << jsonString(fields[i].key) << ": " << fields[i].jsonValue(*this)
      << (i + 1 < fields.size() ? ",\n" : "\n");
  }
  o << "}\n";
  return o.str();
}

}  // namespace sdp
