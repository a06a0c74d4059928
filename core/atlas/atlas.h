// The atlas: any triangle mesh in (closed, any genus, many pieces, non-manifold, inconsistently
// oriented), one packed texture layout out (docs/method.md §7):
//   connectivity   half-edges, components, non-manifold elements (connectivity.h), reported;
//                  faces wound against their neighbours turned over to agree with them
//   charts         disk-shaped charts grown on the faces (charts.h), split until each flattens
//                  with low stretch
//   flatten        every chart by the patch pipeline (flattenDisk: straightest weights, measured
//                  boundary, refinement), in parallel, under one work budget for the whole atlas
//   pack           all charts at one texel density into [0,1]^2 with a gutter (pack.h)
//   store          rounded to the front end's storage, repaired, certified (storage.h), and the
//                  gutter checked on the stored values (measure.h)
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/common/layout.h"
#include "core/common/options.h"

namespace sdp::atlas {

// The charts' refinement work factor by default (Options::refine_work_factor), above the patch
// filter's: a chart left above the stretch limit is split and flattened again, so a budget that
// lets large charts converge costs less in all (the 1.38M-face armadillo: 3262 charts in 118 s
// at 2, 264 charts in 69 s at 6; docs/measurements.md).
constexpr double kDefaultAtlasRefineWorkFactor = 6.0;

// The refinement floor shared by all charts of an atlas (in proportion to their faces), kept at
// the value the atlas's charts were measured with when the patch filter's went down to
// kMinRefineWork (docs/measurements.md).
constexpr double kAtlasMinRefineWork = 2e9;

// The patch pipeline's defaults for the atlas's charts.
inline Options atlasChartDefaults() {
  Options o = productDefaults();
  o.refine_work_factor = kDefaultAtlasRefineWorkFactor;
  o.refine_min_work = kAtlasMinRefineWork;
  return o;
}

using StageProgressCallback =
    std::function<void(const char* stage, int stage_percent, int run_percent)>;

// From this many faces a mesh is large (a scan): the settings fitted on the scans bench apply
// (spatial order, charts refined without reweighting, smaller first parts, the merge bar of large
// meshes); below it, those fitted on the atlas and CAD benches, whose models are all smaller.
constexpr int kLargeMeshFaces = 200000;

// What the user chooses. `chart` carries the patch pipeline's choices for every chart (weights,
// boundary, refinement steps, progress callback); its fit_unit_square and storage are ignored.
struct AtlasOptions {
  Options chart = atlasChartDefaults();
  int texture_size = 2048;  // texels on a side
  int gutter = 2;           // texels kept free between charts
  // A chart whose L2 stretch, flattened, is above this is split in two (1 + this is what the
  // user asks: lower means more, smaller charts).
  double max_chart_stretch = 1.03;
  UVStorage storage = UVStorage::Double;
  // Faces wound against their neighbours are turned over for charting, so charts cross those
  // edges (their texture triangles then run clockwise, AtlasReport::faces_against_chart); false
  // cuts every such edge instead (kept for the bench's comparison; docs/method.md §7).
  bool turn_inconsistent_faces = true;
  // Neighbouring charts are merged back where the merged chart keeps the limits (fewer charts,
  // less seam); false keeps the charts as split (kept for the bench's comparison).
  bool merge_charts = true;
  // From this many faces the atlas is made on a copy of the mesh in a spatial order (faces along
  // a Morton curve of their centroids, vertices as the faces first use them) and given back in
  // the input's order: a scan's faces as written may lie far apart, and every stage that walks
  // across faces then waits on memory. Below it the mesh is charted as it is. Tests lower it.
  int spatial_order_faces = kLargeMeshFaces;
  // Meshes of at least this many faces refine their charts without the reweighting steps on the
  // fixed boundary (Options::reweight), straight from the linear map to the free-boundary steps:
  // on the scans bench's meshes that took fewer charts, less seam and less time at the same L2
  // (docs/measurements.md); below it the atlas bench's models keep the reweighting, which packs
  // them better. Tests lower it.
  int reweight_below_faces = kLargeMeshFaces;
  // A bar per stage, for front ends that redraw only when the bar's position moves (MeshLab):
  // the run's percentage moves every few seconds at millions of faces. Called on the calling
  // thread with the stage (kAtlasStages), its own percent done and the run's percent, whenever
  // either moves; chart.progress still gets the run's percentage and may cancel.
  StageProgressCallback stage_progress;
};

// The atlas's stages as stage_progress names them, in run order, each with the percent of the
// run where it starts.
struct AtlasStage {
  const char* name;
  int from;
};
inline constexpr AtlasStage kAtlasStages[] = {
    {"connectivity", 0}, {"cut", 5},    {"charts", 19},  {"merge", 54},
    {"pack", 69},        {"store", 91}, {"measure", 96},
};

struct ChartReport {
  int faces = 0;
  double area = 0;  // 3D
  double l2_stretch = 0, linf_stretch = 0;
  // The patch pipeline's boundary ("measured", "circle", ...), "part of measured" etc. when the
  // chart kept its part of a larger chart's map.
  std::string boundary_used;
  int fallbacks = 0;
};

struct AtlasReport {
  int vertices = 0, faces = 0;
  int components = 0;  // pieces joined across manifold, consistently oriented edges
  int charts = 0;
  double seam = 0;                // 3D length of cut edges / sqrt(3D area)
  double packing_efficiency = 0;  // UV area over the unit square
  double texels_per_unit = 0;     // one texel density for every chart
  int texture_size = 0, gutter = 0;
  double l2_stretch = 0, linf_stretch = 0;                // whole atlas, one normalization
  int flipped_faces = 0;                                  // 0: certified as stored
  int overlapping_charts = 0;                             // 0: certified as stored
  int non_manifold_edges = 0, non_manifold_vertices = 0;  // split inside the core
  int inconsistent_edges = 0;  // edges whose two faces are wound against each other, as input
  // Faces turned over to agree with their piece before charting: their texture triangles run
  // clockwise against their own winding, as the surface runs (0 for a consistently wound mesh).
  int faces_against_chart = 0;
  int zero_area_faces = 0;  // charted alone, left out of the stretch
  int chart_fallbacks = 0;  // the patch pipeline's fallbacks, over every chart flattening
  int charts_split = 0;     // charts refined into smaller ones for stretch, disk shape or packing
  int charts_merged = 0;    // pairs of charts merged back into one
  std::string storage = "double";
  int storage_degenerate_faces = 0, storage_moved_vertices = 0;
  double refinement_work = 0;  // over all charts, as a multiple of their linear maps' work
  double seconds = 0;
  // connectivity, cut (disk tests, cuts into disks), flatten, split (chart limits, splits),
  // pack, store (rounding, repair, pixel check), measure; seconds summed over the rounds.
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::vector<std::pair<std::string, double>> stage_cpu_seconds;  // the process's, per stage
  // The patch pipeline's counted work (work.h) per its stage, over every chart flattening.
  std::vector<std::pair<std::string, double>> stage_work;
  std::vector<std::string> warnings, notes;
  std::vector<ChartReport> chart_table;

  std::string toJson() const;
};

// The summary rows of the atlas report: the pymeshlab dict, the log's summary line and the first
// keys of the JSON report, in this order.
struct AtlasSummaryField {
  const char* key;
  const char* meaning;  // for docs/usage.md
  bool integer;
  const char* log_format;  // printf format of the value in the log line
  double (*number)(const AtlasReport&);
};
const std::vector<AtlasSummaryField>& atlasSummaryFields();

// The JSON report's other keys, after the summary's, in this order.
struct AtlasDetailField {
  const char* key;
  const char* meaning;  // for docs/usage.md
  std::string (*json)(const AtlasReport&);
};
const std::vector<AtlasDetailField>& atlasDetailFields();

struct AtlasResult {
  Layout layout;                     // per corner, seams split; layout.chart per face
  std::vector<double> face_stretch;  // per face, normalized L2 over the whole atlas
  AtlasReport report;
};

// Throws ParameterizationError with a one-line reason (no faces, a coordinate not finite, an
// index out of range, charts that do not fit the texture, cancelled by the user); a returned
// atlas is certified as stored: no flipped face, no chart overlapping another, every gutter kept.
AtlasResult makeAtlas(const Positions& V, const Triangles& F, const AtlasOptions& options = {});

}  // namespace sdp::atlas
