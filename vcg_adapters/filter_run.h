// What both MeshLab shims (2020.09, 2025.07) do between reading the parameters and touching the
// mesh: pick the source vertex, run the core, translate indices back, word the report. Plain
// C++ on the vcg mesh type; the shims add MeshLab's parameter lists, logging and textures.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "filter_straightest_param/core/parameterize.h"
#include "filter_straightest_param/filter_description.h"
#include "vcg_adapters/patch_adapter.h"

namespace sdp::vcg_adapter {

struct FilterRun {
  PatchInput input;
  sdp::Result result;
  int source_mesh_vertex = -1;     // mesh index of the source S actually used, -1 when none
  std::vector<std::string> notes;  // remarks for the log (e.g. the selected vertex that was used)
};

// Called with a percentage (0..100) and the stage name.
using ProgressSink = std::function<void(int percent, const char* stage)>;

// Reads the mesh, runs sdp::parameterize and leaves the mesh untouched. Throws
// sdp::ParameterizationError with the user-facing reason.
template <class MeshType>
FilterRun runParameterization(const MeshType& mesh, const sdp::filter::FilterValues& values,
                              const ProgressSink& progress = {}) {
  sdp::Options options = sdp::filter::toOptions(values);
  setMeshLabStorage(options);
  FilterRun run;
  run.input = extractPatch(mesh, values.selected_only);

  // sourcevertex is a mesh vertex index; a single selected vertex wins over it (docs/method.md §6).
  int mesh_source = values.source_vertex;
  const int selected = singleSelectedVertex(mesh);
  if (selected >= 0) {
    if (run.input.coreVertexOf(selected) >= 0) {
      mesh_source = selected;
      run.notes.push_back("source vertex " + std::to_string(selected) +
                          " taken from the selection");
    } else {
      run.notes.push_back("the selected vertex " + std::to_string(selected) +
                          " is not part of the patch; ignored");
    }
  }
  options.source_vertex = -1;
  if (mesh_source >= 0) {
    options.source_vertex = run.input.coreVertexOf(mesh_source);
    if (options.source_vertex < 0) {
      throw sdp::ParameterizationError("source vertex " + std::to_string(mesh_source) +
                                       " is not a vertex of the patch");
    }
  }
  if (progress) {
    // MeshLab's callbacks cannot cancel reliably (meshlabserver's always says "go on"), so the
    // run is never cancelled from here.
    options.progress = [progress](const char* stage, int percent) {
      progress(percent, stage);
      return true;
    };
  }

  run.result = sdp::parameterize(run.input.positions, run.input.triangles, options);
  run.source_mesh_vertex = run.input.meshVertexOf(run.result.report.source_vertex);
  return run;
}

inline std::string formatReportValue(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

// docs/method.md §6 report values (the pymeshlab dict). Stretch and flips describe the UVs as the
// mesh stores them (the core measured them so, see setMeshLabStorage()).
struct ReportValues {
  double l2_stretch = 0;
  double linf_stretch = 0;
  int flipped_faces = 0;
  int fallbacks = 0;
  int source_vertex = -1;  // mesh index
  double seconds = 0;
};

inline ReportValues reportValues(const FilterRun& run, const sdp::UVMeasures& stored) {
  ReportValues values;
  values.l2_stretch = stored.l2_stretch;
  values.linf_stretch = stored.linf_stretch;
  values.flipped_faces = stored.flipped_faces;
  values.fallbacks = run.result.report.fallbacks;
  values.source_vertex = run.source_mesh_vertex;
  values.seconds = run.result.report.seconds;
  return values;
}

// The log lines: what ran, then the docs/method.md §6 report values, then remarks and the core's
// warnings.
inline std::vector<std::string> reportLines(const FilterRun& run, const sdp::UVMeasures& stored) {
  const sdp::Report& r = run.result.report;
  const ReportValues values = reportValues(run, stored);
  std::vector<std::string> lines;
  std::string what = "Straightest distances: " + std::to_string(r.vertices) + " vertices, " +
                     std::to_string(r.faces) + " faces, weights " + r.weights + ", boundary " +
                     r.boundary;
  if (!r.boundary_used.empty() && r.boundary_used != r.boundary) {
    what += " (used " + r.boundary_used + ")";
  }
  lines.push_back(what);
  lines.push_back("L2 stretch " + formatReportValue("%.4f", values.l2_stretch) + ", Linf stretch " +
                  formatReportValue("%.4f", values.linf_stretch) + ", flipped faces " +
                  std::to_string(values.flipped_faces) + ", fallbacks " +
                  std::to_string(values.fallbacks) + ", source vertex " +
                  std::to_string(values.source_vertex) + ", " +
                  formatReportValue("%.3f", values.seconds) + " s");
  if (r.fallbacks > 0) {
    lines.push_back("fallbacks: straightest->ltd " + std::to_string(r.straightest_to_ltd) +
                    ", degenerate rings " + std::to_string(r.degenerate_rings) + ", walks " +
                    std::to_string(r.walk_fallbacks) + ", boundary " +
                    std::to_string(r.boundary_fallbacks));
  }
  if (r.stretch_iterations_run > 0) {
    lines.push_back("stretch refinement: " + std::to_string(r.stretch_iterations_run) +
                    " iterations, kept iteration " + std::to_string(r.best_iteration) +
                    ", linear L2 " + formatReportValue("%.4f", r.l2_stretch_linear));
    if (r.free_boundary_steps > 0)
      lines.push_back("free boundary: " + std::to_string(r.free_boundary_steps) +
                      " steps, L2 on the fixed boundary " +
                      formatReportValue("%.4f", r.l2_stretch_fixed_boundary));
  }
  for (const std::string& note : run.notes) lines.push_back(note);
  for (const std::string& note : r.notes) lines.push_back(note);
  for (const std::string& warning : r.warnings) lines.push_back("warning: " + warning);
  return lines;
}

}  // namespace sdp::vcg_adapter
