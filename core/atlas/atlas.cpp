#include "atlas.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <limits>
#include <memory>
#include <new>
#include <numeric>
#include <optional>
#include <sstream>
#include <thread>
#include <unordered_map>
#include <unordered_set>

#include "charts.h"
#include "convex_cut.h"
#include "core/common/connectivity.h"
#include "core/common/error.h"
#include "core/common/geometry.h"
#include "core/common/json.h"
#include "core/common/metrics.h"
#include "core/common/parallel.h"
#include "core/common/report.h"
#include "core/common/storage.h"
#include "core/common/work.h"
#include "core/parameterize.h"
#include "measure.h"
#include "pack.h"
#include "planar_chart.h"

namespace sdp::atlas {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// When a stage began, in wall time and in the process's CPU time: the report gives both, so a
// stage that leaves a core idle shows (its CPU seconds near its wall seconds on two cores).
struct StageStart {
  Clock::time_point wall = Clock::now();
  std::clock_t cpu = std::clock();
};

// A chart once flattened: its faces, and per face corner a row of its own texture coordinates
// (natural scale, counter-clockwise as the faces run).
struct Chart {
  std::vector<int> faces;
  std::vector<Eigen::Vector2d> uv;
  std::vector<std::array<int, 3>> corner_row;  // per face of `faces`
  ChartReport report;
  double linear_work = 0, refine_work = 0;
  std::vector<std::pair<std::string, double>> stage_work;  // the patch pipeline's, per stage
};

// Work keys of the refinement stages (progress.h), the rest being the linear map's.
bool isRefineStage(const std::string& key) {
  return key == "refine" || key == "free_boundary" || key == "newton";
}

// One face alone, laid out with its own edge lengths; a zero-area face gets a right triangle
// with legs `leg`, so it still covers a positive area.
Chart singleFaceChart(const Positions& V, const Triangles& F, int f, bool zero_area, double leg) {
  Chart chart;
  chart.faces = {f};
  chart.corner_row = {{0, 1, 2}};
  const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
  if (zero_area) {
    chart.uv = {{0, 0}, {leg, 0}, {0, leg}};
  } else {
    const double ab = (b - a).norm();
    const Eigen::Vector3d e = (b - a) / ab;
    const double x = (c - a).dot(e), y = ((c - a) - x * e).norm();
    chart.uv = {{0, 0}, {ab, 0}, {x, y}};
  }
  chart.report.faces = 1;
  chart.report.area = faceArea3d(V, F, f);
  chart.report.l2_stretch = chart.report.linf_stretch = 1;
  chart.report.boundary_used = zero_area ? "zero area" : "one face";
  return chart;
}

// The 3D area of the faces of the list.
double facesArea(const Positions& V, const Triangles& F, const std::vector<int>& faces) {
  double area = 0;
  for (int f : faces) area += faceArea3d(V, F, f);
  return area;
}

// Flattens a disk-shaped face set: projected when flat, unrolled when developable
// (planar_chart.h), else by the patch pipeline; false when that refused.
bool flattenChart(const Positions& V, const Triangles& F, const std::vector<int>& faces,
                  const Options& options, Chart& chart, std::string& why) {
  std::vector<int> local;
  std::vector<int> input_vertex;
  Triangles sub(faces.size(), 3);
  {
    std::vector<std::pair<int, int>> corners;  // (input vertex, corner)
    corners.reserve(3 * faces.size());
    for (size_t i = 0; i < faces.size(); ++i)
      for (int k = 0; k < 3; ++k) corners.emplace_back(F(faces[i], k), static_cast<int>(3 * i + k));
    std::sort(corners.begin(), corners.end());
    for (size_t i = 0; i < corners.size(); ++i) {
      if (i == 0 || corners[i].first != corners[i - 1].first)
        input_vertex.push_back(corners[i].first);
      sub(corners[i].second / 3, corners[i].second % 3) = static_cast<int>(input_vertex.size()) - 1;
    }
  }
  Positions subV(input_vertex.size(), 3);
  for (size_t v = 0; v < input_vertex.size(); ++v) subV.row(v) = V.row(input_vertex[v]);
  chart.faces = faces;
  chart.corner_row.resize(faces.size());
  for (size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) chart.corner_row[i][k] = sub(i, k);
  chart.report.faces = static_cast<int>(faces.size());
  chart.report.area = facesArea(V, F, faces);
  std::optional<std::vector<Eigen::Vector2d>> exact = projectIfPlanar(subV, sub);
  const char* exact_name = "planar projection";
  if (!exact) {
    exact = unrollIfDevelopable(subV, sub);
    exact_name = "developable unrolled";
  }
  if (exact) {
    chart.uv = std::move(*exact);
    Layout layout;
    layout.uv.resize(chart.uv.size(), 2);
    for (size_t v = 0; v < chart.uv.size(); ++v) layout.uv.row(v) = chart.uv[v].transpose();
    layout.face_uv = sub;
    const StretchMetrics stretch = layoutStretch(subV, sub, layout);
    chart.report.l2_stretch = stretch.l2;
    chart.report.linf_stretch = stretch.linf;
    chart.report.boundary_used = exact_name;
    chart.linear_work = WorkCosts::kMetricsFace * static_cast<double>(faces.size());
    return true;
  }
  try {
    Result r = flattenDisk(subV, sub, options);
    chart.uv.resize(input_vertex.size());
    for (size_t v = 0; v < input_vertex.size(); ++v) chart.uv[v] = r.layout.uv.row(v).transpose();
    chart.report.l2_stretch = r.report.l2_stretch;
    chart.report.linf_stretch = r.report.linf_stretch;
    chart.report.boundary_used = r.report.boundary_used;
    chart.report.fallbacks = r.report.fallbacks.total();
    for (const auto& [key, work] : r.report.stage_work)
      (isRefineStage(key) ? chart.refine_work : chart.linear_work) += work;
    chart.stage_work = r.report.stage_work;
    return true;
  } catch (const ParameterizationError& e) {
    why = e.what();
    return false;
  }
}

// The part of a flattened chart on the faces of `faces` (a subset of its own), keeping its
// texture coordinates: a restriction of a one-to-one map is one-to-one. Its stretch is measured
// anew by layoutStretch, with the part's own normalization. `index_in_parent` holds, per input
// face of the parent, its index in parent.faces; `row_of` is -1 per parent row on entry and on
// return.
Chart restrictedChart(const Positions& V, const Triangles& F, const Chart& parent,
                      const std::vector<int>& faces, const std::vector<int>& index_in_parent,
                      std::vector<int>& row_of) {
  Chart chart;
  chart.faces = faces;
  chart.corner_row.resize(faces.size());
  std::vector<int> parent_row;  // per row of the part, its parent's row
  Triangles part_faces(faces.size(), 3);
  Layout layout;
  layout.face_uv.resize(faces.size(), 3);
  for (size_t i = 0; i < faces.size(); ++i) {
    const auto& rows = parent.corner_row[index_in_parent[faces[i]]];
    for (int k = 0; k < 3; ++k) {
      int& row = row_of[rows[k]];
      if (row < 0) {
        row = static_cast<int>(chart.uv.size());
        chart.uv.push_back(parent.uv[rows[k]]);
        parent_row.push_back(rows[k]);
      }
      chart.corner_row[i][k] = row;
      layout.face_uv(i, k) = row;
    }
    part_faces.row(i) = F.row(faces[i]);
  }
  for (int row : parent_row) row_of[row] = -1;
  layout.uv.resize(chart.uv.size(), 2);
  for (size_t v = 0; v < chart.uv.size(); ++v) layout.uv.row(v) = chart.uv[v].transpose();
  const StretchMetrics stretch = layoutStretch(V, part_faces, layout);
  const bool measured = std::isfinite(stretch.l2) && std::isfinite(stretch.linf);
  chart.report.faces = static_cast<int>(faces.size());
  chart.report.area = facesArea(V, F, faces);
  // Nothing to measure (no area): never kept.
  chart.report.l2_stretch = measured ? stretch.l2 : std::numeric_limits<double>::infinity();
  chart.report.linf_stretch = measured ? stretch.linf : std::numeric_limits<double>::infinity();
  // The map is the parent's (whose fallbacks the report counted once); its border is partly a
  // cut through it.
  const std::string kPartOf = "part of ";
  chart.report.boundary_used = parent.report.boundary_used.rfind(kPartOf, 0) == 0
                                   ? parent.report.boundary_used
                                   : kPartOf + parent.report.boundary_used;
  return chart;
}

void checkInput(const Positions& V, const Triangles& F, const AtlasOptions& options) {
  if (F.rows() == 0) throw ParameterizationError("the mesh has no faces");
  if (options.texture_size < 64 || options.texture_size > 16384)
    throw ParameterizationError("texture size must be between 64 and 16384, got " +
                                std::to_string(options.texture_size));
  if (options.gutter < 0 || options.gutter > 64)
    throw ParameterizationError("gutter must be between 0 and 64 texels, got " +
                                std::to_string(options.gutter));
  if (!(options.max_chart_stretch >= 1.0))
    throw ParameterizationError("the chart stretch limit must be at least 1");
  // The first face with a bad corner, searched on every core (a second at 13M faces on one),
  // then its reason.
  const int faces = static_cast<int>(F.rows());
  auto badCorner = [&](int f, int k) {
    const int v = F(f, k);
    return v < 0 || v >= V.rows() || !V.row(v).allFinite();
  };
  const int slots = faceSumSlots(faces);
  std::vector<int> first_bad(slots, faces);
  parallelForSlots(faces, slots, [&](int begin, int end, int slot) {
    for (int f = begin; f < end; ++f)
      if (badCorner(f, 0) || badCorner(f, 1) || badCorner(f, 2)) {
        first_bad[slot] = f;
        return;
      }
  });
  const int f = *std::min_element(first_bad.begin(), first_bad.end());
  if (f == faces) return;
  for (int k = 0; k < 3; ++k) {
    const int v = F(f, k);
    if (v < 0 || v >= V.rows())
      throw ParameterizationError("face " + std::to_string(f) + " has vertex index " +
                                  std::to_string(v) + " out of range (the mesh has " +
                                  std::to_string(V.rows()) + " vertices)");
    if (!V.row(v).allFinite())
      throw ParameterizationError("vertex " + std::to_string(v) +
                                  " has a coordinate that is not finite");
  }
}

// The pieces of the chartable faces joined across the graph's edges, in order of first face.
std::vector<std::vector<int>> components(const FaceGraph& g) {
  std::vector<std::vector<int>> pieces;
  std::vector<char> seen(g.faceCount(), 0);
  for (int start = 0; start < g.faceCount(); ++start) {
    if (seen[start] || !g.chartable[start]) continue;
    std::vector<int> piece = {start};
    seen[start] = 1;
    for (size_t i = 0; i < piece.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int next = g.across[3 * piece[i] + k];
        if (next >= 0 && !seen[next]) seen[next] = 1, piece.push_back(next);
      }
    std::sort(piece.begin(), piece.end());
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

// Faces per part when a piece that is not a disk is first cut (pieces of fewer than twice this
// are halved): near the size of the charts that stay (armadillo: 86k faces, 51 charts), so that
// few large parts are flattened only to be split again. On the atlas bench, 60000 -> 10000 took
// the probe's time from 20.8 to 16.2 s with 604 charts instead of 618 (the 1.38M-face armadillo:
// 23 s, 204 charts); 5000 split the bumpy cube and the bunny more.
constexpr size_t kFacesPerFirstPart = 10000;
// On large meshes (kLargeMeshFaces) the first parts shrink in proportion, down to
// kFewestFacesPerFirstPart: the refinement floor (kAtlasMinRefineWork) is shared by area, so a
// part of a large mesh gets little of it, stops on the work budget above the chart limit and is
// split level by level. On the scans bench's cheburashka x64 (828k faces, 8192 texture) with
// and without noise, 10000 -> 1500 took the charts stage from 36.7 / 40.3 s to 16.7 / 21.3 s,
// charts from 1397 / 1713 to 1143 / 1397, seam 99.6 -> 76.9 and efficiency 0.558 -> 0.653
// (docs/measurements.md). On the atlas bench's models (at most 86k faces) 1500 would add charts
// and seam (the bumpy cube 11 -> 28 charts), so they keep 10000.
constexpr size_t kFewestFacesPerFirstPart = 1500;

size_t facesPerFirstPart(size_t mesh_faces) {
  if (mesh_faces < static_cast<size_t>(kLargeMeshFaces)) return kFacesPerFirstPart;
  const double scaled =
      static_cast<double>(kFacesPerFirstPart) * kLargeMeshFaces / static_cast<double>(mesh_faces);
  return std::max(kFewestFacesPerFirstPart, static_cast<size_t>(scaled));
}

// Straight cuts of flattened charts (convex_cut.h), lengths in units of √(mesh area), areas in
// units of the mesh area; chosen with the atlas bench (docs/measurements.md): a chart longer
// than kLongestChart limits the scale of the whole atlas; a convex cut must remove kCutWorth of
// hull area per length of cut and kCutMinGain in all (lower values add charts and seam faster
// than efficiency), leaving kCutMinSide of the chart on either side.
constexpr double kLongestChart = 1.0;
// A chart of more than kFewestFacesToSplitForLinf faces whose worst face stretches more than
// kMostChartLinf (L∞, the chart's own normalization) is split like one above the L2 limit: on
// the atlas bench, median L∞ 2.45 -> 2.13 for 3 % more charts (3 gave 1.95 for 6 %).
constexpr double kMostChartLinf = 4.0;
constexpr size_t kFewestFacesToSplitForLinf = 50;
// A piece cut out of a flattened chart keeps its part of the chart's map when within the chart
// limits and its worst face stretches at most kMostKeptLinf; else it is flattened anew, which
// relaxes it: on the atlas bench, median L∞ 2.49 without this rule, 1.98 with it.
constexpr double kMostKeptLinf = 2.0;
constexpr double kCutWorth = 0.1;
// A convex cut's gain is also weighed against the seam it leaves along the faces' edges, at this
// weight: across a fan of slivers (a CAD part's flat face) the faces by the side of their
// centroid meet along a saw-tooth of long edges, many times the straight cut; on a regular mesh
// the edges zig-zag about 1.3 times the cut, and the straight cut's test stays the one that
// binds. On the CAD models tuned with, seam 457 -> 432 at the same median L-infinity (1.44);
// weight 1: 430 but 1.55 (docs/measurements.md).
constexpr double kCutSeamWeight = 0.5;
constexpr double kCutMinGain = 0.005;
constexpr double kCutMinSide = 0.05;
// A piece is first cut along its sharp edges (dihedral angle above 40 degrees) into feature
// patches of at least kFewestPatchFaces faces (cutIntoDisks).
const double kSharpEdgeCos = std::cos(40.0 * kPi / 180);
constexpr int kFewestPatchFaces = 20;
// A piece is mechanical, and grows by its faces' own normals, when its second feature patch
// holds this share of its area (AtlasBuilder::growByOwnNormalsOnMechanicalPieces).
constexpr double kMechanicalPatchShare = 1e-3;
// A feature patch that is still no disk (faces joined by fillets, which no sharp edge bounds) is
// cut into flat patches (flatPatches), each facing within kFlatPatchDegrees of its seed face:
// on the CAD models tuned with, 20 degrees gave the lowest median L-infinity (1.44; 15: 1.63,
// 25: 1.57, 35: 1.66) for 3% more seam than splitting such patches by size alone.
const double kFlatPatchCos = std::cos(20.0 * kPi / 180);
// A feature patch with holes is flattened whole when its holes could hold at most this share of
// its area (AtlasBuilder::holesAreSmall).
constexpr double kMostHoleAreaShare = 0.25;
// Merging charts back (AtlasBuilder::mergeCharts) flattens at most kMergedFacesPerFace faces per
// face of the mesh, at least kMergedFacesFloor (all passes, at most kMostMergePasses, up to about
// 50k faces); above 200k faces each face adds one, not two: a pass costs about as much as the
// charts' flattening, the longest stage of a large scan.
constexpr double kMergedFacesPerFace = 2.0, kMergedFacesFloor = 400000;
constexpr double kMergedFacesPerLargeFace = 1.0, kMergedFacesForLargeMeshes = 200000;
constexpr int kMostMergePasses = 8;
// A merged chart's bounding rectangle may exceed the two parts' together by this share: the
// pieces of an unrolled wall (a drilled hole's, cut into flat patches) add up to exactly their
// rectangles, and rounding refused such merges at random. On the CAD models tuned with, 5e-3 gave
// 458 of seam (477 refusing any excess; 1e-3: 462) at the same median L-infinity; 1e-2 raised
// it from 1.56 to 1.62 (docs/measurements.md).
constexpr double kMergedBoxTolerance = 5e-3;
// A pair is not flattened for merging when its two maps, joined along their shared vertices as
// they are (no bending), would take more than this many times the two rectangles apart. On the
// 32 CAD and 10 shared closed models, of 4793 merge tries the accepted ones came to at most
// 1.49 times (a bolt's thread; the rest at most 1.16), and the 348 tries above 1.75 were all
// refused after flattening; on the scans bench's armadillo x16 and fertility x64 the merges kept
// came to at most 1.019 times, and 19-39% of the faces flattened for refused pairs were in pairs
// above 1.05. 1.05 on large meshes first (2 more charts of 4104 on armadillo x64), then on all:
// on the CAD models charts +0.9% and seam +0.6% for merging 14-15% faster, on the shared closed
// models +6 of 456 charts and seam 138.6 -> 138.8 for 24% less time (docs/measurements.md).
constexpr double kMostJoinedBoxRatio = 1.05;

// The progress bar, in percent where each stage starts (kAtlasStages): the connectivity, the
// first cut (counted in faces), the charts' rounds (by faces flattened, then charts decided),
// merging (by faces flattened of its budget), the packing tries (by charts placed, weighed by
// their size; packAndStore), storage and measures. Shares near the stages' time on the scans
// bench's 5.47M- and 13.6M-face scans with noise (`stage_seconds`: cut 13 and 18 %, charts 42
// and 32 %, merging 14 and 17 %, packing 20 and 23 %), so that at about 5M faces the run's
// percentage moves every two seconds or less (bench/scans.py's progress column).
// The connectivity analysis moves the bar a percent per step (makeAtlas), the face graph one
// more (the analysis's last step and the face graph waited 3.6 s for one at 5.47M faces).
constexpr int kConnectivityPercent = 3, kCutPercent = 5, kFlattenPercent = 19, kMergePercent = 54,
              kPackPercent = 69, kStorePercent = 91, kMeasurePercent = 96;
static_assert(kAtlasStages[1].from == kCutPercent && kAtlasStages[2].from == kFlattenPercent &&
              kAtlasStages[3].from == kMergePercent && kAtlasStages[4].from == kPackPercent &&
              kAtlasStages[5].from == kStorePercent && kAtlasStages[6].from == kMeasurePercent);

// The run's progress as the front ends get it, on the calling thread (their callbacks are not
// thread-safe), never backwards: chart.progress gets the run's percentage when it moves, or a
// second after the last call (a front end that redraws in its callback stays responsive);
// stage_progress gets the stage's own percentage when it or the stage moves.
class ProgressBar {
 public:
  explicit ProgressBar(const AtlasOptions& options)
      : run_(options.chart.progress), stage_(options.stage_progress) {}

  // `percent` of the run, fractions included; false when the user cancelled. `call`: the run's
  // callback is called even when nothing moved.
  bool report(double percent, bool call = false) {
    percent = std::max(std::clamp(percent, 0.0, 100.0), percent_);
    percent_ = percent;
    const int whole = static_cast<int>(percent);
    bool go_on = true;
    if (run_ && (call || whole > whole_ || secondsSince(last_call_) >= 1.0)) {
      last_call_ = Clock::now();
      go_on = run_("atlas", whole);
    }
    whole_ = std::max(whole, whole_);
    if (stage_) {
      int stage = 0;
      while (stage + 1 < static_cast<int>(std::size(kAtlasStages)) &&
             kAtlasStages[stage + 1].from <= percent)
        ++stage;
      const double from = kAtlasStages[stage].from;
      const double to = stage + 1 < static_cast<int>(std::size(kAtlasStages))
                            ? kAtlasStages[stage + 1].from
                            : 100.0;
      const int own = std::clamp(static_cast<int>(100 * (percent - from) / (to - from)), 0, 100);
      if (stage != stage_index_ || own > stage_percent_) {
        stage_index_ = stage;
        stage_percent_ = own;
        stage_(kAtlasStages[stage].name, own, whole);
      }
    }
    return go_on;
  }
  int percent() const { return whole_; }        // the run's, the last reported (-1 before any)
  double fraction() const { return percent_; }  // the same with its fraction

 private:
  const ProgressCallback& run_;
  const StageProgressCallback& stage_;
  double percent_ = 0;
  int whole_ = -1;
  int stage_index_ = -1, stage_percent_ = -1;
  Clock::time_point last_call_ = Clock::now();
};

class AtlasBuilder {
 public:
  // `start`: when the run began (the connectivity of `F`, checked, is its first stage).
  AtlasBuilder(const Positions& V, const Triangles& F, const AtlasOptions& options,
               StageStart start, ProgressBar& bar)
      : V_(V), F_(F), options_(options), start_(start), bar_(bar) {}

  // `geometry`: faceGraphGeometry(V, F) when already built (alongside the connectivity), else
  // empty. Both are taken, and freed once used: at 13M faces the graph is over a gigabyte, and
  // packing and storage, where a run's memory peaks, need neither.
  AtlasResult run(Connectivity connectivity, FaceGraph geometry = {}) {
    report(kConnectivityPercent);
    auto stage = start_;
    int graph_step = 0;  // the face graph's passes: seconds apart at millions of faces
    FaceGraph graph = geometry.F ? std::move(geometry) : faceGraphGeometry(V_, F_, [&] {
      report(kConnectivityPercent + 0.2 * ++graph_step);
    });
    joinFacesAcrossEdges(graph, connectivity);
    edges_all_joined_ =
        connectivity.non_manifold_edges == 0 && connectivity.inconsistent_edges == 0;
    AtlasReport& r = result_.report;
    r.vertices = connectivity.vertices;
    r.faces = connectivity.faces;
    r.non_manifold_edges = connectivity.non_manifold_edges;
    r.non_manifold_vertices = connectivity.non_manifold_vertices;
    r.inconsistent_edges = connectivity.inconsistent_edges;
    connectivity = Connectivity();
    total_area_ = 0;
    int chartable_faces = 0;
    for (int f = 0; f < graph.faceCount(); ++f)
      total_area_ += graph.area[f], chartable_faces += graph.chartable[f] ? 1 : 0;
    if (chartable_faces == 0)
      throw ParameterizationError("every face has zero area (no surface to flatten)");
    report(kConnectivityPercent + 1);
    endStage("connectivity", stage);

    stage = StageStart();
    addZeroAreaCharts(graph, graph.faceCount() - chartable_faces);
    std::vector<std::vector<int>> pieces = components(graph);
    report(kConnectivityPercent + 1.6);
    r.components = static_cast<int>(pieces.size());
    checkRoomForCharts(r.zero_area_faces + r.components);
    growByOwnNormalsOnMechanicalPieces(graph, pieces);
    report(kCutPercent);
    endStage("cut", stage);
    makeCharts(graph, std::move(pieces));
    report(kMergePercent);  // every stage's bar starts, merging or not
    if (options_.merge_charts) mergeCharts(graph);
    scratch_.clear();  // about 12 bytes a face each: not kept through packing and storage
    graph = FaceGraph();

    packAndStore();
    r.seconds = secondsSince(start_.wall);
    report(100);
    return std::move(result_);
  }

 private:
  // A mechanical piece grows its parts by its faces' own normals, not the smoothed ones
  // (FaceGraph::growth_normal): its normals carry no noise, and on a coarse mesh a few rings of
  // faces reach across a gear's tooth. Mechanical: its second feature patch holds at least
  // kMechanicalPatchShare of its area (secondFeaturePatchShare). On the CAD models the second
  // patch holds 0.8-42 % of the part, on the atlas bench's organic models 0 or 0.5-31 % (cow,
  // cheburashka, the knight, the truck: creases), and on the scans bench's meshes, where noise
  // makes dihedral angles above the sharp edges' 40 degrees around patches of some tens of
  // faces, below 0.01 % (docs/measurements.md, *Growth by smoothed normals*).
  void growByOwnNormalsOnMechanicalPieces(FaceGraph& graph,
                                          const std::vector<std::vector<int>>& pieces) {
    // The bar's room from where run() left it to the cut, by faces flooded (a second at 5.47M
    // faces); the largest piece on the calling thread, which alone may move it.
    int largest = 0;
    for (size_t i = 0; i < pieces.size(); ++i)
      if (pieces[i].size() > pieces[largest].size()) largest = static_cast<int>(i);
    std::atomic<long long> flooded{0};
    const double from = bar_.fraction(), faces_in_all = static_cast<double>(F_.rows());
    const GrowthProgress progress = [&](int faces) {
      flooded += faces;
      reportWithin(from, kCutPercent, static_cast<double>(flooded.load()), faces_in_all);
    };
    forEachWithScratch(
        graph, static_cast<int>(pieces.size()),
        [&](int i, FaceScratch& scratch) {
          const std::vector<int>& faces = pieces[i];
          if (faces.size() < 2 ||
              secondFeaturePatchShare(graph, faces, kSharpEdgeCos, kFewestPatchFaces, scratch,
                                      &progress) < kMechanicalPatchShare)
            return;
          for (int f : faces) graph.growth_normal[f] = graph.normal[f].cast<float>();
        },
        largest);
  }

  // Refuses at the start, not after the charts' work, when `fewest_charts` charts cannot fit
  // the texture at any scale: every chart covers a texel at least, and the texels of two charts
  // are at least a gutter apart in both directions (pack.h), so the texture holds at most
  // ceil(size / gutter)^2 charts.
  void checkRoomForCharts(long long fewest_charts) const {
    const long long size = options_.texture_size, gutter = std::max(options_.gutter, 1);
    const long long most = ((size + gutter - 1) / gutter) * ((size + gutter - 1) / gutter);
    if (fewest_charts > most)
      throw ParameterizationError(
          "the mesh needs at least " + std::to_string(fewest_charts) +
          " charts (one per piece and per zero-area face), more than a " + std::to_string(size) +
          " texel texture with a " + std::to_string(options_.gutter) + " texel gutter can hold (" +
          std::to_string(most) + "): raise the texture size or lower the gutter");
  }

  // Reports `percent` of the run (ProgressBar), on the calling thread only; a cancel is noted
  // (for the workers) and thrown.
  void report(double percent) {
    if (std::this_thread::get_id() != caller_) return;
    if (!bar_.report(percent)) cancelled_ = true;
    if (cancelled_) throw ParameterizationError("cancelled by the user");
  }
  // `done` of `expected` of the part of the bar from `from` to `to`.
  void reportWithin(double from, double to, double done, double expected) {
    report(from + (to - from) * std::min(1.0, done / std::max(expected, 1.0)));
  }

  // A set of faces still to be charted, with the part of an earlier map it may keep.
  struct Piece {
    std::vector<int> faces;
    std::optional<Chart> map;  // from a flattened chart this piece was cut out of
  };

  // Whether a flattened chart's stretch is within the atlas's limits (else it is split).
  bool stretchAccepted(const Chart& chart) const {
    return chart.report.l2_stretch <= options_.max_chart_stretch &&
           !(chart.report.linf_stretch > kMostChartLinf &&
             chart.faces.size() > kFewestFacesToSplitForLinf);
  }

  // Charts: each piece that is not a disk is split; each disk is flattened, and split again when
  // its stretch is above the limit or the patch pipeline refused it; one face is a chart alone.
  // A disk cut out of a flattened chart keeps that chart's map when its own stretch is within
  // the limits: flattening it anew would cost the most of the atlas's time (docs/method.md §7).
  // Level by level, every step runs on all pieces of the level at once (sorting them into disks
  // and parts, flattening, deciding what each chart becomes), and the results are taken in piece
  // order, so the charts are the same on any number of cores.
  void makeCharts(const FaceGraph& graph, std::vector<std::vector<int>> pieces) {
    AtlasReport& r = result_.report;
    int charted_faces = 0;
    std::vector<Piece> pending;
    for (std::vector<int>& faces : pieces) pending.push_back({std::move(faces), {}});
    // The bar's room for the charts: two thirds for the first round (most of the work), then
    // half of what is left for each next; flattening fills nine tenths of a round's share.
    double round_from = kFlattenPercent;
    for (int round = 0; !pending.empty(); ++round) {
      const double round_to =
          round_from + (round == 0 ? 2.0 / 3 : 0.5) * (kMergePercent - round_from);
      StageStart stage;
      std::vector<Piece> disks = sortIntoDisks(graph, std::move(pending), charted_faces);
      pending.clear();
      endStage("cut", stage);
      stage = StageStart();
      // Largest first, so the long ones start early.
      std::stable_sort(disks.begin(), disks.end(), [](const Piece& a, const Piece& b) {
        return a.faces.size() > b.faces.size();
      });
      std::vector<Chart> flat(disks.size());
      std::vector<char> ok(disks.size(), 0);
      double round_faces = 0;
      for (const Piece& disk : disks) round_faces += static_cast<double>(disk.faces.size());
      std::atomic<int> done_faces{0};
      const double split_from = round_from + 0.9 * (round_to - round_from);
      parallelForDynamic(static_cast<int>(disks.size()), 1, [&](int begin, int end, int worker) {
        for (int i = begin; i < end; ++i) {
          if (cancelled_) return;
          const std::vector<int>& faces = disks[i].faces;
          if (disks[i].map) {
            flat[i] = std::move(*disks[i].map);  // no work: linear_work stays 0
            ok[i] = 1;
          } else {
            std::string why;
            ok[i] = flattenChart(V_, F_, faces, chartOptions(faces.size()), flat[i], why);
          }
          done_faces += static_cast<int>(faces.size());
          if (worker == 0) reportWithin(round_from, split_from, done_faces, round_faces);
        }
      });
      if (cancelled_) throw ParameterizationError("cancelled by the user");
      // Every flattening counts, also of charts split afterwards.
      for (const Chart& chart : flat) {
        countWork(chart);
        r.chart_fallbacks += chart.report.fallbacks;  // 0 for a kept map
      }
      endStage("flatten", stage);
      stage = StageStart();
      std::vector<Outcome> outcomes(disks.size());
      std::atomic<int> decided{0};
      forEachWithScratch(graph, static_cast<int>(disks.size()), [&](int i, FaceScratch& scratch) {
        outcomes[i] = outcome(graph, disks[i].faces, flat[i], ok[i], scratch);
        reportWithin(split_from, round_to, ++decided, disks.size());
      });
      for (size_t i = 0; i < disks.size(); ++i) {
        Outcome& o = outcomes[i];
        if (o.keep) {
          charted_faces += static_cast<int>(disks[i].faces.size());
          charts_.push_back(std::move(flat[i]));
        }
        if (o.split) ++r.charts_split;
        for (Piece& piece : o.pieces) pending.push_back(std::move(piece));
      }
      endStage("split", stage);
      report(round_to);
      round_from = round_to;
    }
  }

  // Charts that share a border are merged back when the merged chart is a disk that flattens
  // within the chart limits, its worst face no worse, its bounding rectangle no larger than the
  // two parts' together, and is not cut again for packing: the first cut and the halving by
  // stretch leave borders that no limit asked for (docs/method.md §7). Pairs by the length of
  // border they share, longest first; each pass tries disjoint pairs at once (in parallel) and
  // takes them in pair order, so the same on any number of cores. The faces flattened for merging
  // are counted against a budget in proportion to the mesh.
  void mergeCharts(const FaceGraph& graph) {
    AtlasReport& r = result_.report;
    const StageStart stage;
    MergeState state;
    state.chart_of.assign(F_.rows(), -1);
    const double faces = static_cast<double>(F_.rows());
    state.budget = std::max(
        kMergedFacesFloor, std::min(kMergedFacesPerFace * faces,
                                    kMergedFacesPerLargeFace * faces + kMergedFacesForLargeMeshes));
    for (int pass = 0; pass < kMostMergePasses; ++pass) {
      const double spent_before = state.spent;
      const std::vector<MergeTry> tries = mergeTries(graph, state);
      if (tries.empty()) break;
      std::vector<Chart> merged(tries.size());
      std::vector<char> accepted(tries.size(), 0);
      std::atomic<long long> tried_faces{0};
      forEachWithScratch(graph, static_cast<int>(tries.size()), [&](int i, FaceScratch& scratch) {
        accepted[i] = tryMerge(graph, tries[i], merged[i], scratch);
        tried_faces += static_cast<long long>(tries[i].faces.size());
        reportWithin(kMergePercent, kPackPercent,
                     spent_before + static_cast<double>(tried_faces.load()), state.budget);
      });
      int merges = 0;
      std::vector<char> gone(charts_.size(), 0);
      for (size_t i = 0; i < tries.size(); ++i) {
        countWork(merged[i]);
        if (!accepted[i]) {
          state.refused.insert(tries[i].hash);
          continue;
        }
        charts_[tries[i].a] = std::move(merged[i]);
        gone[tries[i].b] = 1;
        ++merges;
      }
      if (merges == 0) break;
      size_t kept = 0;
      for (size_t c = 0; c < charts_.size(); ++c)
        if (!gone[c]) {
          if (kept != c) charts_[kept] = std::move(charts_[c]);
          ++kept;
        }
      charts_.resize(kept);
      r.charts_merged += merges;
    }
    endStage("merge", stage);
  }

  struct MergeState {
    std::vector<int> chart_of;             // per face
    std::unordered_set<uint64_t> refused;  // hashes of face sets flattened and refused
    double budget = 0, spent = 0;          // faces flattened for merging
  };
  struct MergeTry {
    int a, b;  // charts, a < b
    std::vector<int> faces;
    uint64_t hash;  // of `faces` (a collision only skips a try: the same on every run)
  };

  // The pairs of charts to try merging in this pass: neighbours by the length of their shared
  // border, longest first, each chart in one pair at most, none refused before, within budget.
  std::vector<MergeTry> mergeTries(const FaceGraph& graph, MergeState& state) const {
    for (size_t c = 0; c < charts_.size(); ++c)
      for (int f : charts_[c].faces) state.chart_of[f] = static_cast<int>(c);
    struct Shared {
      int a, b;
      double length;
    };
    std::vector<Shared> edges;
    for (int f = 0; f < graph.faceCount(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int g = graph.across[3 * f + k], cf = state.chart_of[f];
        if (g < f || cf == state.chart_of[g]) continue;
        const double length = (V_.row(F_(f, k)) - V_.row(F_(f, (k + 1) % 3))).norm();
        edges.push_back({std::min(cf, state.chart_of[g]), std::max(cf, state.chart_of[g]), length});
      }
    std::sort(edges.begin(), edges.end(),
              [](const Shared& x, const Shared& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
    std::vector<Shared> pairs;
    for (const Shared& e : edges)
      if (!pairs.empty() && pairs.back().a == e.a && pairs.back().b == e.b)
        pairs.back().length += e.length;
      else
        pairs.push_back(e);
    for (Shared& p : pairs)
      p.length /= std::sqrt(std::min(charts_[p.a].report.area, charts_[p.b].report.area));
    std::stable_sort(pairs.begin(), pairs.end(),
                     [](const Shared& x, const Shared& y) { return x.length > y.length; });
    std::vector<char> taken(charts_.size(), 0);
    std::vector<MergeTry> tries;
    for (const Shared& p : pairs) {
      if (taken[p.a] || taken[p.b]) continue;
      MergeTry t{p.a, p.b, charts_[p.a].faces, 1469598103934665603ull};  // FNV-1a
      t.faces.insert(t.faces.end(), charts_[p.b].faces.begin(), charts_[p.b].faces.end());
      std::sort(t.faces.begin(), t.faces.end());
      for (int f : t.faces) t.hash = (t.hash ^ static_cast<uint64_t>(f)) * 1099511628211ull;
      if (state.refused.count(t.hash)) continue;
      if (state.spent + static_cast<double>(t.faces.size()) > state.budget) break;
      state.spent += static_cast<double>(t.faces.size());
      taken[p.a] = taken[p.b] = 1;
      tries.push_back(std::move(t));
    }
    return tries;
  }

  // The rectangle the two charts' maps would take side by side, each at the 3D scale, b turned
  // and moved onto a along their shared vertices (least squares, no mirror): what a merged
  // chart's map is near when neither part must bend to join the other. 0 when they share fewer
  // than two vertices.
  double joinedBoxArea(const Chart& a, const Chart& b) const {
    auto scaled = [](const Chart& chart) {
      const double uv_area = uvArea(chart.uv, chart.corner_row);
      return uv_area > 0 ? std::sqrt(chart.report.area / uv_area) : 0.0;
    };
    const double sa = scaled(a), sb = scaled(b);
    if (!(sa > 0) || !(sb > 0)) return 0;
    // Mesh vertex -> its UV in chart a (a disk: one UV per vertex).
    std::unordered_map<int, int> in_a;
    for (size_t i = 0; i < a.faces.size(); ++i)
      for (int k = 0; k < 3; ++k) in_a.emplace(F_(a.faces[i], k), a.corner_row[i][k]);
    std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> shared;  // (in b, in a)
    std::unordered_set<int> seen;
    for (size_t i = 0; i < b.faces.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int v = F_(b.faces[i], k);
        const auto it = in_a.find(v);
        if (it == in_a.end() || !seen.insert(v).second) continue;
        shared.emplace_back(b.uv[b.corner_row[i][k]] * sb, a.uv[it->second] * sa);
      }
    if (shared.size() < 2) return 0;
    Eigen::Vector2d cb = Eigen::Vector2d::Zero(), ca = Eigen::Vector2d::Zero();
    for (const auto& [pb, pa] : shared) cb += pb, ca += pa;
    cb /= static_cast<double>(shared.size()), ca /= static_cast<double>(shared.size());
    double dot = 0, crs = 0;
    for (const auto& [pb, pa] : shared) {
      const Eigen::Vector2d qb = pb - cb, qa = pa - ca;
      dot += qb.dot(qa), crs += qb.x() * qa.y() - qb.y() * qa.x();
    }
    const double angle = std::atan2(crs, dot);
    Eigen::Matrix2d turn;
    turn << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
    std::vector<Eigen::Vector2d> points;
    points.reserve(a.uv.size() + b.uv.size());
    for (const Eigen::Vector2d& p : a.uv) points.push_back(p * sa);
    for (const Eigen::Vector2d& p : b.uv) points.push_back(turn * (p * sb - cb) + ca);
    return smallestRectangleArea(points);
  }

  // Flattens the pair's faces into `merged`; true when the merged chart is to replace the two.
  bool tryMerge(const FaceGraph& graph, const MergeTry& t, Chart& merged,
                FaceScratch& scratch) const {
    if (!isDisk(graph, t.faces, scratch)) return false;
    // A pair whose maps, joined as they are, would take a far larger rectangle than the two
    // apart is refused without flattening: merged, it failed the rectangle or the stretch
    // limits every time (docs/measurements.md).
    const Chart &a = charts_[t.a], &b = charts_[t.b];
    const double parts = boxArea(a) + boxArea(b);
    if (joinedBoxArea(a, b) > kMostJoinedBoxRatio * parts) return false;
    std::string why;
    if (!flattenChart(V_, F_, t.faces, chartOptions(t.faces.size()), merged, why)) return false;
    if (!stretchAccepted(merged) ||
        merged.report.linf_stretch >
            std::max({a.report.linf_stretch, b.report.linf_stretch, kMostKeptLinf}) ||
        boxArea(merged) > parts * (1 + kMergedBoxTolerance))
      return false;
    // As outcome() judges a chart: cut again when the cut leaves two pieces or more.
    return straightCutPieces(graph, merged, scratch.region).size() < 2;
  }

  // The area of the chart's smallest bounding rectangle, at the 3D scale: what packing gives it.
  static double boxArea(const Chart& chart) {
    const double uv_area = uvArea(chart.uv, chart.corner_row);
    if (!(uv_area > 0)) return 0;
    return smallestRectangleArea(chart.uv) * chart.report.area / uv_area;
  }

  // The area of the smallest rectangle around the points (one side on their hull).
  static double smallestRectangleArea(const std::vector<Eigen::Vector2d>& points) {
    const Eigen::Matrix2d turn = smallestBoxRotation(points);
    Eigen::Vector2d low = turn * points.front(), high = low;
    for (const Eigen::Vector2d& p : points)
      low = low.cwiseMin(turn * p), high = high.cwiseMax(turn * p);
    return (high - low).prod();
  }

  // A chart of its own for each face a chart cannot hold (zero area, repeated corner), sized by
  // the mean edge of the others (measured only when there is such a face: a pass over every
  // edge was most of a second at 5.47M faces).
  void addZeroAreaCharts(const FaceGraph& graph, int unchartable_faces) {
    if (unchartable_faces == 0) return;
    double edge_sum = 0;
    int edge_count = 0;
    for (int f = 0; f < graph.faceCount(); ++f) {
      if (!graph.chartable[f]) continue;
      for (int k = 0; k < 3; ++k)
        edge_sum += (V_.row(F_(f, k)) - V_.row(F_(f, (k + 1) % 3))).norm(), ++edge_count;
    }
    const double mean_edge = edge_sum / edge_count;
    for (int f = 0; f < graph.faceCount(); ++f)
      if (!graph.chartable[f]) {
        ++result_.report.zero_area_faces;
        charts_.push_back(singleFaceChart(V_, F_, f, true, mean_edge));
      }
  }

  // Adds the time since `since` to the stage's wall and CPU seconds (summed over the rounds).
  void endStage(const std::string& key, const StageStart& since) {
    AtlasReport& r = result_.report;
    addToStage(r.stage_seconds, key, secondsSince(since.wall));
    addToStage(r.stage_cpu_seconds, key,
               static_cast<double>(std::clock() - since.cpu) / CLOCKS_PER_SEC);
  }

  // Adds a flattening's work to the atlas's (every flattening counts, also when not kept).
  void countWork(const Chart& chart) {
    linear_work_ += chart.linear_work;
    refine_work_ += chart.refine_work;
    for (const auto& [key, work] : chart.stage_work)
      addToStage(result_.report.stage_work, key, work);
  }

  // Calls body(i, scratch) for i in [0, n) on the workers, each with its own FaceScratch (made
  // when first needed; at most kMostScratchWorkers of them, as each is about 14 bytes a face);
  // i = `on_caller` (if in range) first, on the calling thread.
  template <class Body>
  void forEachWithScratch(const FaceGraph& graph, int n, Body&& body, int on_caller = -1) {
    // Kept for the whole run: a round late in the charts has few pieces, and making the scratch
    // anew for each cost 0.08 s a round at 13.6M faces.
    std::vector<std::unique_ptr<FaceScratch>>& scratch = scratch_;
    if (scratch.empty()) scratch.resize(kMostScratchWorkers);
    auto scratchOf = [&](int worker) -> FaceScratch& {
      if (!scratch[worker]) scratch[worker] = std::make_unique<FaceScratch>(graph);
      return *scratch[worker];
    };
    const bool caller_first = on_caller >= 0 && on_caller < n;
    parallelForAlongside(
        n, 1,
        [&] {
          if (caller_first) body(on_caller, scratchOf(0));  // the calling thread is worker 0
        },
        [&](int begin, int end, int worker) {
          FaceScratch& own = scratchOf(worker);
          for (int i = begin; i < end; ++i) {
            if (cancelled_) return;
            if (caller_first && i == on_caller) continue;
            body(i, own);
          }
        },
        kMostScratchWorkers);
    if (cancelled_) throw ParameterizationError("cancelled by the user");
  }

  // The pieces made ready for flattening, in order: a disk as it is (with its part of an earlier
  // map when that map is within the limits), and a piece that is not a disk cut into disks, as
  // it must be; a large one into parts of about facesPerFirstPart faces at once, not halved
  // level by level, so that its largest pieces are not flattened only to be split again. One
  // face alone becomes a chart here (added to `charted_faces`).
  std::vector<Piece> sortIntoDisks(const FaceGraph& graph, std::vector<Piece> pieces,
                                   int& charted_faces) {
    std::vector<char> disk(pieces.size(), 0);
    std::vector<std::vector<std::vector<int>>> cut(pieces.size());
    // Before the first flattening the bar follows the cut, in faces: the disk test (counted as
    // half the faces: it took a tenth of the cut of the 5.47M-face scan), the feature patches'
    // flood (once; 1.3 s there), the seeds and three growths over every face in the worst case. The
    // longest piece's cut takes the longest: it runs on the calling thread, which alone may call
    // the progress callback.
    std::atomic<long long> grown{0};
    double expected = 0;
    int largest = 0;
    for (size_t i = 0; i < pieces.size(); ++i) {
      expected += 5.5 * static_cast<double>(pieces[i].faces.size());
      if (pieces[i].faces.size() > pieces[largest].faces.size()) largest = static_cast<int>(i);
    }
    const bool first = bar_.percent() < kFlattenPercent;
    const GrowthProgress growth = [&](int faces) {
      grown += faces;
      if (first) reportWithin(kCutPercent, kFlattenPercent, grown, expected);
    };
    forEachWithScratch(
        graph, static_cast<int>(pieces.size()),
        [&](int i, FaceScratch& scratch) {
          const std::vector<int>& faces = pieces[i].faces;
          if (faces.size() == 1) return;
          disk[i] = isDisk(graph, faces, scratch);
          if (disk[i]) return;
          growth(static_cast<int>(faces.size() / 2));
          cut[i] = cutIntoDisks(graph, faces, scratch, growth);
        },
        largest);
    std::vector<Piece> ready;
    for (size_t i = 0; i < pieces.size(); ++i) {
      if (pieces[i].faces.size() == 1) {
        charts_.push_back(singleFaceChart(V_, F_, pieces[i].faces[0], false, 0));
        ++charted_faces;
      } else if (disk[i]) {
        Piece& piece = pieces[i];
        if (piece.map &&
            !(stretchAccepted(*piece.map) && piece.map->report.linf_stretch <= kMostKeptLinf))
          piece.map.reset();
        ready.push_back(std::move(piece));
      } else {
        for (std::vector<int>& part : cut[i]) ready.push_back({std::move(part), {}});
      }
    }
    return ready;
  }

  // A piece that is not a disk (the caller tested it) in disks: in its feature patches (bounded
  // by sharp edges), each patch that is neither a disk nor one with small holes then split into
  // parts of about facesPerFirstPart faces.
  std::vector<std::vector<int>> cutIntoDisks(const FaceGraph& graph, const std::vector<int>& faces,
                                             FaceScratch& scratch, const GrowthProgress& growth) {
    auto split = [&](const std::vector<int>& part) {
      const int parts =
          std::max<int>(2, static_cast<int>(part.size() / facesPerFirstPart(F_.rows())));
      return splitFaces(graph, part, parts, scratch, &growth);
    };
    // One patch (no sharp edges) is the piece itself, which is no disk but may be one with
    // holes.
    std::vector<std::vector<int>> patches =
        featurePatches(graph, faces, kSharpEdgeCos, kFewestPatchFaces, scratch, &growth);
    // A patch with holes (a flat face around drilled holes) is flattened whole, its holes
    // filled for the solve as the patch filter fills them, and split only when it fails the
    // limits: cut into disks it would take a seam from every hole. Not above the first cut's
    // part size: a scan with holes punched is a sphere with small holes, and is cut into parts
    // at once as before, not flattened whole first.
    const size_t part_size = facesPerFirstPart(F_.rows());
    auto flattenable = [&](const std::vector<int>& patch) {
      // Above the part size only a disk is flattened whole, and most such patches (a scan's
      // whole piece) are not: isDisk says so without building their mesh. The piece itself,
      // as its one patch, was just tested.
      if (patch.size() > part_size)
        return patch.size() < faces.size() && isDisk(graph, patch, scratch);
      const int holes = patch.size() == 1 ? 0 : regionHoles(graph, patch, scratch);
      return holes == 0 || (holes > 0 && holesAreSmall(graph, patch, scratch));
    };
    // Only in a piece that has sharp edges (a mechanical part), and up to the part size: an
    // organic piece, or a large noisy one, is split by size as before.
    const bool mechanical = patches.size() >= 2;
    std::vector<std::vector<int>> disks;
    for (std::vector<int>& patch : patches) {
      if (flattenable(patch)) {
        disks.push_back(std::move(patch));
        continue;
      }
      if (mechanical && patch.size() <= part_size) {
        std::vector<std::vector<int>> flats =
            flatPatches(graph, patch, kFlatPatchCos, kFewestPatchFaces, scratch);
        if (flats.size() >= 2) {
          for (std::vector<int>& flat : flats) {
            if (flattenable(flat)) {
              disks.push_back(std::move(flat));
              continue;
            }
            for (std::vector<int>& part : split(flat)) disks.push_back(std::move(part));
          }
          continue;
        }
      }
      for (std::vector<int>& part : split(patch)) disks.push_back(std::move(part));
    }
    return disks;
  }

  // True when the holes of a disk with holes could hold at most kMostHoleAreaShare of its area:
  // each hole's perimeter P bounds its area by P^2 / 4 pi (a circle's), the longest loop being
  // the outer one. A ring (a plate's side wall, a hole's wall) fails: flattened whole it would
  // leave its middle empty in the texture.
  bool holesAreSmall(const FaceGraph& graph, const std::vector<int>& faces,
                     FaceScratch& scratch) const {
    std::vector<int>& region = scratch.region;
    for (int f : faces) region[f] = 0;
    std::vector<std::pair<int, int>> border;  // (from vertex, half-edge), as the faces run
    double area = 0;
    for (int f : faces) {
      area += graph.area[f];
      for (int k = 0; k < 3; ++k) {
        const int across = graph.across[3 * f + k];
        if (across < 0 || region[across] != 0) border.emplace_back(F_(f, k), 3 * f + k);
      }
    }
    for (int f : faces) region[f] = kOutside;
    std::sort(border.begin(), border.end());
    std::vector<char> walked(border.size(), 0);
    std::vector<double> perimeters;
    for (size_t start = 0; start < border.size(); ++start) {
      if (walked[start]) continue;
      double perimeter = 0;
      for (size_t at = start; !walked[at];) {
        walked[at] = 1;
        const int h = border[at].second, f = h / 3, k = h % 3;
        const int to = F_(f, (k + 1) % 3);
        perimeter += (V_.row(F_(f, k)) - V_.row(to)).norm();
        const auto next = std::lower_bound(border.begin(), border.end(), std::make_pair(to, -1));
        if (next == border.end() || next->first != to) break;
        at = static_cast<size_t>(next - border.begin());
      }
      perimeters.push_back(perimeter);
    }
    std::sort(perimeters.begin(), perimeters.end());
    double holes_area = 0;
    for (size_t i = 0; i + 1 < perimeters.size(); ++i)
      holes_area += perimeters[i] * perimeters[i] / (4 * kPi);
    return holes_area <= kMostHoleAreaShare * area;
  }

  // regionIsDisk, ruled out first by the Euler characteristic where that is exact: linear in the
  // faces, where regionIsDisk builds their mesh (seconds for a scan's whole piece).
  bool isDisk(const FaceGraph& graph, const std::vector<int>& faces, FaceScratch& scratch) const {
    if (edges_all_joined_ && regionEulerCharacteristic(graph, faces, scratch) != 1) return false;
    return regionIsDisk(graph, faces, scratch);
  }

  // What a flattened disk becomes: a chart (keep), or pieces to chart again (split), each with
  // its part of the chart's map when it was flattened.
  struct Outcome {
    bool keep = false;
    bool split = false;
    std::vector<Piece> pieces;
  };
  Outcome outcome(const FaceGraph& graph, const std::vector<int>& faces, const Chart& chart,
                  bool flattened, FaceScratch& scratch) const {
    Outcome o;
    if (flattened && stretchAccepted(chart)) {
      std::vector<std::vector<int>> parts = straightCutPieces(graph, chart, scratch.region);
      if (parts.size() >= 2) {
        o.split = true;
        o.pieces = cutOut(chart, std::move(parts), scratch.region);
      } else {
        o.keep = true;
      }
      return o;
    }
    std::vector<std::vector<int>> parts = splitFaces(graph, faces, 2, scratch);
    if (parts.size() < 2) {
      // Cannot be split further: keep the flattened chart, or its faces one by one.
      if (flattened)
        o.keep = true;
      else
        for (int f : faces) o.pieces.push_back({{f}, {}});
      return o;
    }
    o.split = true;
    if (flattened) {
      o.pieces = cutOut(chart, std::move(parts), scratch.region);
    } else {
      for (std::vector<int>& part : parts) o.pieces.push_back({std::move(part), {}});
    }
    return o;
  }

  // The pieces of a flattened chart, each with its part of the chart's map (one face alone
  // becomes a chart of its own anyway). `index_in_chart` is per-face scratch, kOutside on entry
  // and on return.
  std::vector<Piece> cutOut(const Chart& chart, std::vector<std::vector<int>> parts,
                            std::vector<int>& index_in_chart) const {
    for (size_t i = 0; i < chart.faces.size(); ++i)
      index_in_chart[chart.faces[i]] = static_cast<int>(i);
    std::vector<int> row_of(chart.uv.size(), -1);
    std::vector<Piece> pieces;
    for (std::vector<int>& part : parts) {
      std::optional<Chart> map;
      if (part.size() > 1) map = restrictedChart(V_, F_, chart, part, index_in_chart, row_of);
      pieces.push_back({std::move(part), std::move(map)});
    }
    for (int f : chart.faces) index_in_chart[f] = kOutside;
    return pieces;
  }

  // A flattened chart's pieces when it should be cut along a straight line, else nothing: a
  // chart longer than kLongestChart is halved across its length; one whose best convex cut
  // (convex_cut.h) removes enough hull area for the seam it adds is cut there.
  std::vector<std::vector<int>> straightCutPieces(const FaceGraph& graph, const Chart& chart,
                                                  std::vector<int>& scratch) const {
    if (chart.faces.size() < 8) return {};
    const double uv_area = uvArea(chart.uv, chart.corner_row);
    if (!(uv_area > 0) || !(chart.report.area > 0)) return {};
    const double to_3d = std::sqrt(chart.report.area / uv_area);  // plane lengths to 3D lengths
    const double mesh_length = std::sqrt(total_area_);
    double extent = 0;
    std::optional<ConvexCut> cut = middleCut(chart.uv, extent);
    const bool long_chart = extent * to_3d > kLongestChart * mesh_length;
    if (!long_chart) {
      cut = bestConvexCut(chart.uv, chart.corner_row, kCutMinSide);
      if (!cut || cut->hull_gain * to_3d < kCutWorth * cut->length * mesh_length ||
          cut->hull_gain * to_3d * to_3d < kCutMinGain * total_area_)
        return {};
    }
    // Faces by the side of their centroid, then each side's connected pieces.
    std::vector<double> along(chart.faces.size());
    for (size_t i = 0; i < chart.faces.size(); ++i) {
      const auto& t = chart.corner_row[i];
      along[i] = cut->normal.dot((chart.uv[t[0]] + chart.uv[t[1]] + chart.uv[t[2]]) / 3);
    }
    if (long_chart) {
      // Faces as long as the chart (a CAD face's slivers) can all lie on one side of its
      // middle: then the cut goes through their middle instead, which still shortens it.
      const auto [low, high] = std::minmax_element(along.begin(), along.end());
      if (*low >= cut->offset || *high < cut->offset) {
        std::vector<double> sorted = along;
        std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
        cut->offset = sorted[sorted.size() / 2];
      }
    }
    for (size_t i = 0; i < chart.faces.size(); ++i)
      scratch[chart.faces[i]] = along[i] < cut->offset ? 0 : 1;
    if (!long_chart && cut->hull_gain * to_3d * to_3d < kCutWorth * kCutSeamWeight *
                                                            cutSeam(graph, chart.faces, scratch) *
                                                            mesh_length) {
      for (int f : chart.faces) scratch[f] = kOutside;
      return {};
    }
    std::vector<std::vector<int>> pieces;
    for (int start : chart.faces) {
      const int side = scratch[start];
      if (side < 0) continue;
      std::vector<int> piece = {start};
      scratch[start] = kUnassigned;
      for (size_t j = 0; j < piece.size(); ++j)
        for (int k = 0; k < 3; ++k) {
          const int next = graph.across[3 * piece[j] + k];
          if (next >= 0 && scratch[next] == side)
            scratch[next] = kUnassigned, piece.push_back(next);
        }
      std::sort(piece.begin(), piece.end());
      pieces.push_back(std::move(piece));
    }
    for (int f : chart.faces) scratch[f] = kOutside;
    return pieces;
  }

  // The 3D length of the edges between faces on side 0 and side 1 of `side` (per face): the seam
  // a cut leaves.
  double cutSeam(const FaceGraph& graph, const std::vector<int>& faces,
                 const std::vector<int>& side) const {
    double length = 0;
    for (int f : faces)
      for (int k = 0; k < 3; ++k) {
        const int g = graph.across[3 * f + k];
        if (g >= 0 && side[f] == 0 && side[g] == 1)
          length += (V_.row(F_(f, k)) - V_.row(F_(f, (k + 1) % 3))).norm();
      }
    return length;
  }

  // The patch pipeline's options for a chart of `faces` faces: one work floor for the whole
  // atlas, shared by area (faces), not one per chart.
  Options chartOptions(size_t faces) const {
    Options o = options_.chart;
    o.storage = StoragePolicy{};  // the atlas stores all charts at once, packed
    o.progress = [this](const char*, int) { return !cancelled_.load(); };
    if (result_.report.faces >= options_.reweight_below_faces) o.reweight = false;
    if (o.refine_min_work > 0)
      o.refine_min_work *= static_cast<double>(faces) / std::max(result_.report.faces, 1);
    return o;
  }

  void packAndStore() {
    report(kPackPercent);
    AtlasReport& r = result_.report;
    // Each chart at the scale that minimizes the whole atlas's L2 (s^2 proportional to its L2
    // times its 3D over UV area): the atlas's L2 is then the area-weighted mean of the charts'.
    std::vector<ChartShape> shapes(charts_.size());
    for (size_t c = 0; c < charts_.size(); ++c) {
      const Chart& chart = charts_[c];
      const double uv_area = uvArea(chart.uv, chart.corner_row);
      double scale = 1;
      if (chart.report.area > 0 && uv_area > 0)
        scale = std::sqrt(chart.report.l2_stretch * chart.report.area / uv_area);
      shapes[c].uv.resize(chart.uv.size());
      for (size_t v = 0; v < chart.uv.size(); ++v) shapes[c].uv[v] = chart.uv[v] * scale;
      shapes[c].triangles = chart.corner_row;
    }
    PackOptions pack;
    pack.texture_size = options_.texture_size;
    pack.gutter = options_.gutter;
    // The scale search's tries get shares of the bar's room for packing: at a million faces
    // and more it takes two or three (pack.cpp), each about as long as the others; later tries
    // halve what is left.
    // A later try places the same charts in the same order as the one before, at another
    // scale: its share moves as that try's clock did (the bar only; the packing counts no time).
    auto timeline = std::make_shared<PackTimeline>();
    pack.progress = [this, timeline](double done, int attempt) {
      double from = 0, to = 0.45;  // of the room
      for (int a = 0; a < attempt; ++a) from = to, to = a == 0 ? 0.8 : to + 0.5 * (1 - to);
      const double part = from + (to - from) * timeline->timeDone(done, attempt);
      report(kPackPercent + (kStorePercent - kPackPercent) * part);
    };
    for (int attempt = 0;; ++attempt) {
      StageStart stage;
      const Packing packing = packCharts(shapes, pack);
      report(kStorePercent - 1);  // the layout of millions of faces takes seconds
      Layout layout = packedLayout(shapes, packing);
      endStage("pack", stage);
      report(kStorePercent);
      stage = StageStart();
      StoragePolicy policy;
      policy.precision = options_.storage;
      int store_step = 0;
      const StorageCounts counts =
          store(layout, policy, [&] { report(kStorePercent + ++store_step); });
      report(kStorePercent + 3);
      // The pixel check ends below the measures' start (it once ran past it, and the stage bar
      // named it the measures).
      const PixelMeasures pixels = measurePixels(
          layout, layout.chart, options_.texture_size, options_.gutter, [this](double done) {
            report(kStorePercent + 3 + (kMeasurePercent - kStorePercent - 3.01) * done);
          });
      endStage("store", stage);
      if (pixels.overlapping_pixels == 0 && pixels.gutter_violations == 0) {
        r.texels_per_unit = packing.texels_per_unit;
        r.storage = uvStorageName(options_.storage);
        r.storage_degenerate_faces = counts.degenerate_faces;
        r.storage_moved_vertices = counts.moved_vertices;
        finish(std::move(layout));
        return;
      }
      if (attempt == 2)
        throw ParameterizationError(
            "internal error: the packed charts overlap or break the gutter once stored (" +
            std::to_string(pixels.overlapping_pixels) + " pixels covered twice, " +
            std::to_string(pixels.gutter_violations) + " in a gutter)");
      pack.shrink *= 0.97;
    }
  }

  // The progress of packing tries: `done` as the packer counts it, turned into the share of the
  // try's time the last try had taken at that point, when there was one.
  struct PackTimeline {
    int attempt = -1;
    Clock::time_point start;
    std::vector<std::pair<double, double>> current, previous;  // (done, seconds into the try)
    double timeDone(double done, int try_number) {
      if (try_number != attempt) {
        previous = std::move(current);
        current.clear();
        attempt = try_number;
        start = Clock::now();
      }
      current.emplace_back(done, secondsSince(start));
      if (previous.size() < 2 || !(previous.back().second > 0)) return done;
      const auto at =
          std::lower_bound(previous.begin(), previous.end(), std::make_pair(done, -1.0));
      return std::min(
          1.0, (at == previous.end() ? previous.back() : *at).second / previous.back().second);
    }
  };

  Layout packedLayout(const std::vector<ChartShape>& shapes, const Packing& packing) const {
    Layout layout;
    int rows = 0;
    for (const Chart& chart : charts_) rows += static_cast<int>(chart.uv.size());
    layout.uv.resize(rows, 2);
    layout.face_uv.resize(F_.rows(), 3);
    layout.chart.assign(F_.rows(), -1);
    int offset = 0;
    for (size_t c = 0; c < charts_.size(); ++c) {
      const Chart& chart = charts_[c];
      for (size_t v = 0; v < chart.uv.size(); ++v)
        layout.uv.row(offset + v) =
            packing.apply(static_cast<int>(c), shapes[c].uv[v], options_.texture_size).transpose();
      for (size_t i = 0; i < chart.faces.size(); ++i) {
        const int f = chart.faces[i];
        for (int k = 0; k < 3; ++k) layout.face_uv(f, k) = offset + chart.corner_row[i][k];
        layout.chart[f] = static_cast<int>(c);
      }
      offset += static_cast<int>(chart.uv.size());
    }
    return layout;
  }

  void finish(Layout layout) {
    AtlasReport& r = result_.report;
    report(kMeasurePercent);
    const StageStart stage;
    // The stretch (by the atlas's own charts) on another core while this thread measures the
    // rest and reports its steps: each is a pass over every face, a second or two at 5M faces,
    // and the measures alone kept one core (store() certified the pixels).
    StretchMetrics stretch;
    AtlasMeasures measures;
    int measure_step = 0;  // three steps, seconds apart at 13M faces
    parallelForAlongside(
        1, 1,
        [&] {
          measures = measureLayout(V_, F_, layout,
                                   [&] { report(kMeasurePercent + std::min(++measure_step, 3)); });
        },
        [&](int, int, int) { stretch = layoutStretch(V_, F_, layout); });
    if (stretch.flipped_faces > 0)
      throw ParameterizationError("internal error: the stored atlas has flipped faces");
    r.charts = static_cast<int>(charts_.size());
    r.seam = measures.seam;
    r.packing_efficiency = measures.efficiency;
    r.l2_stretch = stretch.l2;
    r.linf_stretch = stretch.linf;
    r.flipped_faces = stretch.flipped_faces;
    r.overlapping_charts = 0;  // store() certified that no two charts' borders cross
    r.texture_size = options_.texture_size;
    r.gutter = options_.gutter;
    for (const Chart& chart : charts_) r.chart_table.push_back(chart.report);
    r.refinement_work = linear_work_ > 0 ? refine_work_ / linear_work_ : 0;
    if (measures.charts != r.charts)
      r.notes.push_back(std::to_string(r.charts) + " charts are " +
                        std::to_string(measures.charts) +
                        " pieces by their stored texture coordinates");
    result_.face_stretch = stretch.face_l2;
    result_.layout = std::move(layout);
    endStage("measure", stage);
  }

  const Positions& V_;
  const Triangles& F_;
  const AtlasOptions& options_;
  const StageStart start_;
  const std::thread::id caller_ = std::this_thread::get_id();
  ProgressBar& bar_;
  AtlasResult result_;
  std::vector<Chart> charts_;
  static constexpr int kMostScratchWorkers = 4;
  std::vector<std::unique_ptr<FaceScratch>> scratch_;  // per worker (forEachWithScratch)
  double total_area_ = 0;
  // Every edge two faces share is one the face graph joins (regionEulerCharacteristic is exact).
  bool edges_all_joined_ = false;
  double linear_work_ = 0, refine_work_ = 0;  // of every flattening, work.h
  std::atomic<bool> cancelled_{false};
};

// Faces wound against their neighbours (a mesh whose faces were written in random order of
// corners) are turned over to agree with their piece before charting, so charts cross those
// edges as the surface runs instead of cutting each one; the stored corners are then given back
// in the face's own order, so such a face's UV triangle runs clockwise: counted, not a fold.
AtlasResult atlasOfTurnedFaces(const Positions& V, const Triangles& F, const AtlasOptions& options,
                               const Connectivity& input, StageStart start,
                               const std::function<void()>& step, ProgressBar& bar) {
  const std::vector<char> turn = coherentOrientation(F, input);
  Triangles turned = F;
  int turned_faces = 0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (turn[f]) std::swap(turned(f, 1), turned(f, 2)), ++turned_faces;
  Connectivity connectivity = analyzeConnectivity(turned, static_cast<int>(V.rows()), step);
  AtlasResult result = AtlasBuilder(V, turned, options, start, bar).run(std::move(connectivity));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    if (turn[f]) std::swap(result.layout.face_uv(f, 1), result.layout.face_uv(f, 2));
  AtlasReport& r = result.report;
  r.inconsistent_edges = input.inconsistent_edges;
  r.faces_against_chart = turned_faces;
  r.warnings.insert(
      r.warnings.begin(),
      std::to_string(turned_faces) + " faces are wound against their neighbours (" +
          std::to_string(input.inconsistent_edges) +
          " inconsistent edges): charted as the surface runs, their texture triangles run "
          "clockwise; MeshLab's Re-Orient all faces coherently (pymeshlab "
          "meshing_re_orient_faces_coherently) fixes the winding");
  return result;
}

// Calls the bar at `percent` of the run; throws when the user cancelled.
void callBar(ProgressBar& bar, int percent) {
  if (!bar.report(percent, true)) throw ParameterizationError("cancelled by the user");
}

// The mesh in a spatial order: its faces sorted along a Morton curve of their centroids (ties
// by index, so the same order on any machine), its vertices in the order those faces first use
// them (unused ones last, as they were).
struct SpatialOrder {
  Positions V;
  Triangles F;
  std::vector<int> input_face;  // per ordered face, the input's
};
SpatialOrder spatialOrder(const Positions& V, const Triangles& F) {
  const int faces = static_cast<int>(F.rows());
  std::vector<Eigen::Vector3d> centroid(faces);
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int f = first; f < last; ++f)
      centroid[f] = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3;
  });
  Eigen::Vector3d low = centroid[0], high = low;
  for (const Eigen::Vector3d& c : centroid) low = low.cwiseMin(c), high = high.cwiseMax(c);
  const double side = std::max((high - low).maxCoeff(), std::numeric_limits<double>::min());
  // 21 bits per axis, interleaved into 63.
  auto spread = [](std::uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
  };
  std::vector<std::pair<std::uint64_t, int>> keyed(faces);
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int f = first; f < last; ++f) {
      std::uint64_t code = 0;
      for (int a = 0; a < 3; ++a) {
        const double t = std::clamp((centroid[f][a] - low[a]) / side, 0.0, 1.0);
        code |= spread(static_cast<std::uint64_t>(t * 2097151.0)) << a;
      }
      keyed[f] = {code, f};
    }
  });
  sortOnTwoCores(keyed);  // the keys are distinct
  SpatialOrder o;
  o.input_face.resize(faces);
  // Vertices numbered in order of first use along the ordered faces, then the unused ones in
  // input order. One core took a quarter of a second per 5M faces: here each slot of faces
  // lists its own first uses, and the lists joined in slot order number each vertex where the
  // whole order first uses it (the slots hold a mark per vertex: one per core, a few at most).
  const int slots = std::clamp(faces / 65536, 1, std::min(parallelWorkers(), 4));
  std::vector<std::vector<int>> first_uses(slots);
  parallelForSlots(faces, slots, [&](int begin, int end, int slot) {
    std::vector<char> seen(V.rows(), 0);
    std::vector<int>& uses = first_uses[slot];
    for (int i = begin; i < end; ++i) {
      const int f = keyed[i].second;
      o.input_face[i] = f;
      for (int k = 0; k < 3; ++k)
        if (!seen[F(f, k)]) seen[F(f, k)] = 1, uses.push_back(F(f, k));
    }
  });
  std::vector<int> new_vertex(V.rows(), -1);
  int vertices = 0;
  for (const std::vector<int>& uses : first_uses)
    for (int v : uses)
      if (new_vertex[v] < 0) new_vertex[v] = vertices++;
  first_uses.clear();
  for (int& v : new_vertex)
    if (v < 0) v = vertices++;
  o.F.resize(faces, 3);
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int i = first; i < last; ++i)
      for (int k = 0; k < 3; ++k) o.F(i, k) = new_vertex[F(o.input_face[i], k)];
  });
  o.V.resize(V.rows(), 3);
  parallelFor(static_cast<int>(V.rows()), 16384, [&](int first, int last, int) {
    for (int v = first; v < last; ++v) o.V.row(new_vertex[v]) = V.row(v);
  });
  return o;
}

// An atlas of the mesh in spatial order given back in the input's face order (the UV rows stay
// as they are: chart by chart).
AtlasResult inInputOrder(AtlasResult ordered, const std::vector<int>& input_face) {
  AtlasResult result = std::move(ordered);
  Layout& layout = result.layout;
  const Triangles face_uv = layout.face_uv;
  const std::vector<int> chart = layout.chart;
  const std::vector<double> stretch = result.face_stretch;
  for (size_t i = 0; i < input_face.size(); ++i) {
    const int f = input_face[i];
    layout.face_uv.row(f) = face_uv.row(i);
    if (!chart.empty()) layout.chart[f] = chart[i];
    if (!stretch.empty()) result.face_stretch[f] = stretch[i];
  }
  return result;
}

// makeAtlas on a mesh already checked, in the order it is given.
AtlasResult atlasInOrder(const Positions& V, const Triangles& F, const AtlasOptions& options,
                         StageStart start, ProgressBar& bar) {
  int steps = 0;
  const std::function<void()> step = [&] { callBar(bar, std::min(++steps, 3)); };
  // The face graph's geometry needs no connectivity: it is built on the other core while the
  // connectivity's passes (sorting and union-find, mostly on one core) run here, where the
  // progress bar is called. Same graph as built after it.
  Connectivity connectivity;
  FaceGraph geometry;
  parallelForAlongside(
      1, 1, [&] { connectivity = analyzeConnectivity(F, static_cast<int>(V.rows()), step); },
      [&](int, int, int) { geometry = faceGraphGeometry(V, F); });
  if (connectivity.inconsistent_edges > 0 && options.turn_inconsistent_faces) {
    geometry = FaceGraph();  // the turned faces' normals differ
    return atlasOfTurnedFaces(V, F, options, connectivity, start, step, bar);
  }
  return AtlasBuilder(V, F, options, start, bar).run(std::move(connectivity), std::move(geometry));
}

}  // namespace

AtlasResult makeAtlas(const Positions& V, const Triangles& F, const AtlasOptions& options) {
  try {
    const StageStart start;
    // The bar starts before the connectivity, which takes seconds at millions of faces, and
    // moves with each of its three steps (to 3 %, where the builder starts).
    ProgressBar bar(options);
    callBar(bar, 0);
    checkInput(V, F, options);
    callBar(bar, 0);  // a call, not a move: the input's check takes a second at 13M faces
    if (F.rows() < options.spatial_order_faces) return atlasInOrder(V, F, options, start, bar);
    SpatialOrder ordered = spatialOrder(V, F);
    callBar(bar, 0);
    return inInputOrder(atlasInOrder(ordered.V, ordered.F, options, start, bar),
                        ordered.input_face);
  } catch (const std::bad_alloc&) {
    throw ParameterizationError("not enough memory to make an atlas of a mesh of " +
                                std::to_string(V.rows()) + " vertices and " +
                                std::to_string(F.rows()) + " faces");
  }
}

const std::vector<AtlasSummaryField>& atlasSummaryFields() {
  using R = const AtlasReport&;
  static const std::vector<AtlasSummaryField> fields = {
      {"charts", "number of charts", true, "%.0f", [](R r) { return double(r.charts); }},
      {"seam", "3D length of the cut edges over the square root of the 3D area", false, "%.2f",
       [](R r) { return r.seam; }},
      {"packing_efficiency", "UV area over the unit square", false, "%.3f",
       [](R r) { return r.packing_efficiency; }},
      {"l2_stretch", "Sander L2 stretch over the whole atlas (1 = isometric)", false, "%.4f",
       [](R r) { return r.l2_stretch; }},
      {"linf_stretch", "Sander L-infinity stretch (worst face)", false, "%.3f",
       [](R r) { return r.linf_stretch; }},
      {"flipped_faces", "faces flipped or degenerate as stored (always 0)", true, "%.0f",
       [](R r) { return double(r.flipped_faces); }},
      {"overlapping_charts", "charts overlapping another as stored (always 0)", true, "%.0f",
       [](R r) { return double(r.overlapping_charts); }},
      {"faces_against_chart",
       "faces wound against their neighbours, turned over for charting: their texture triangles "
       "run clockwise, as the surface runs (not flipped_faces, which counts folds)",
       true, "%.0f", [](R r) { return double(r.faces_against_chart); }},
      {"seconds", "wall time of the atlas (no file I/O)", false, "%.2f",
       [](R r) { return r.seconds; }},
  };
  return fields;
}

namespace {

// The report's `chart_table`: one JSON object per chart.
std::string chartTableJson(const AtlasReport& r) {
  std::string table = "[";
  for (size_t c = 0; c < r.chart_table.size(); ++c) {
    const ChartReport& t = r.chart_table[c];
    table += std::string(c ? ",\n    " : "\n    ") +
             json::jsonObject({{"faces", json::jsonInt(t.faces)},
                               {"area", json::jsonNumber(t.area)},
                               {"l2_stretch", json::jsonNumber(t.l2_stretch)},
                               {"linf_stretch", json::jsonNumber(t.linf_stretch)},
                               {"boundary_used", json::jsonString(t.boundary_used)},
                               {"fallbacks", json::jsonInt(t.fallbacks)}});
  }
  return table + (r.chart_table.empty() ? "]" : "\n  ]");
}

}  // namespace

const std::vector<AtlasDetailField>& atlasDetailFields() {
  using namespace json;
  using R = const AtlasReport&;
  static const std::vector<AtlasDetailField> fields = {
      {"vertices", "vertices of the mesh", [](R r) { return jsonInt(r.vertices); }},
      {"faces", "faces of the mesh (polygons fan-triangulated)",
       [](R r) { return jsonInt(r.faces); }},
      {"components", "pieces joined across manifold, consistently oriented edges",
       [](R r) { return jsonInt(r.components); }},
      {"texels_per_unit", "the one texel density of every chart, texels per unit of 3D length",
       [](R r) { return jsonNumber(r.texels_per_unit); }},
      {"texture_size", "texture width and height the charts were packed for, texels",
       [](R r) { return jsonInt(r.texture_size); }},
      {"gutter", "texels kept free between charts at that size",
       [](R r) { return jsonInt(r.gutter); }},
      {"non_manifold_edges",
       "edges of more than two faces: chart borders (the mesh is not changed)",
       [](R r) { return jsonInt(r.non_manifold_edges); }},
      {"non_manifold_vertices", "vertices whose faces form more than one fan: split per fan",
       [](R r) { return jsonInt(r.non_manifold_vertices); }},
      {"inconsistent_edges",
       "edges whose two faces are wound against each other in the input (charts cross them once "
       "the faces are turned to agree, see faces_against_chart)",
       [](R r) { return jsonInt(r.inconsistent_edges); }},

      {"zero_area_faces",
       "faces of zero area or a repeated vertex: a chart each, a positive-area UV triangle, left "
       "out of the stretch",
       [](R r) { return jsonInt(r.zero_area_faces); }},
      {"chart_fallbacks", "the patch pipeline's fallbacks, summed over every chart flattening",
       [](R r) { return jsonInt(r.chart_fallbacks); }},
      {"charts_split",
       "charts split again: L2 stretch above `chartstretch` (or a worst face stretched over 4x), "
       "refused by the patch pipeline, or cut along a straight line for packing (long, or with "
       "arms and bays)",
       [](R r) { return jsonInt(r.charts_split); }},
      {"charts_merged",
       "pairs of neighbouring charts merged back into one: the merged chart is a disk within the "
       "chart limits, its worst face no worse, and is not cut again for packing",
       [](R r) { return jsonInt(r.charts_merged); }},
      {"refinement_work",
       "the refinement work of every chart flattening (split charts too) over their linear maps' "
       "work",
       [](R r) { return jsonNumber(r.refinement_work); }},
      {"storage", "precision the UVs are stored and certified in",
       [](R r) { return jsonString(r.storage); }},
      {"storage_degenerate_faces", "faces that rounding to that precision would have collapsed",
       [](R r) { return jsonInt(r.storage_degenerate_faces); }},
      {"storage_moved_vertices", "UVs the storage repair moved",
       [](R r) { return jsonInt(r.storage_moved_vertices); }},
      {"stage_seconds",
       "seconds per stage, in run order: `connectivity`, `cut` (pieces tested for disks and cut "
       "into disks), `flatten` (charts flattened by the patch pipeline), `split` (chart limits "
       "checked, charts split), `pack`, `store` (rounding to the storage, its repair and the "
       "pixel check), `measure`; each summed over the rounds",
       [](R r) { return jsonNumbers(r.stage_seconds); }},
      {"stage_cpu_seconds",
       "CPU seconds per stage, of the whole process (every thread), as `stage_seconds` splits "
       "the run: a stage that keeps every core of the machine busy has its wall seconds times "
       "the cores",
       [](R r) { return jsonNumbers(r.stage_cpu_seconds); }},
      {"stage_work",
       "the patch pipeline's work per stage (its report's `stage_work` keys), summed over every "
       "chart flattening: units of about a nanosecond of one core here, counted from sizes and "
       "iterations, the same on every run",
       [](R r) { return jsonNumbers(r.stage_work); }},
      {"warnings", "one line per fallback or notice",
       [](R r) { return jsonList(r.warnings, jsonString); }},
      {"notes", "what was done that needs no action",
       [](R r) { return jsonList(r.notes, jsonString); }},
      {"chart_table",
       "per chart: `faces`, 3D `area`, `l2_stretch`, `linf_stretch`, `boundary_used` (`part of "
       "...` when the chart kept its part of a larger chart's map), `fallbacks`",
       chartTableJson},
  };
  return fields;
}

std::string AtlasReport::toJson() const {
  using namespace json;
  std::vector<std::pair<std::string, std::string>> m;
  for (const AtlasSummaryField& field : atlasSummaryFields()) {
    const double value = field.number(*this);
    m.emplace_back(field.key, field.integer ? jsonInt(static_cast<int>(value)) : jsonNumber(value));
  }
  for (const AtlasDetailField& field : atlasDetailFields())
    m.emplace_back(field.key, field.json(*this));
  std::ostringstream o;
  o << "{\n";
  for (size_t i = 0; i < m.size(); ++i)
    o << "  " << jsonString(m[i].first) << ": " << m[i].second << (i + 1 < m.size() ? ",\n" : "\n");
  o << "}\n";
  return o.str();
}

}  // namespace sdp::atlas
