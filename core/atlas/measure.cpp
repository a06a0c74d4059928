#include "measure.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <atomic>
#include <climits>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/common/connectivity.h"
#include "core/common/disjoint_sets.h"
#include "core/common/geometry.h"
#include "core/common/metrics.h"
#include "core/common/parallel.h"
#include "raster.h"

namespace sdp::atlas {
namespace {

// The mesh's edges as groups of half-edges h = 3 f + k (corner k to k + 1), sorted by end points.
struct EdgeGroups {
  std::vector<int> half_edges;  // grouped
  std::vector<int> begin;       // group g: half_edges[begin[g] .. begin[g + 1])
};
EdgeGroups edgeGroups(const Triangles& F) {
  int vertices = 0;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) vertices = std::max(vertices, F(f, k) + 1);
  const std::vector<HalfEdgeKey> keys = sortedHalfEdges(F, vertices);
  EdgeGroups groups;
  groups.half_edges.reserve(keys.size());
  forEachEdgeRun(keys, [&](size_t begin, size_t end) {
    groups.begin.push_back(static_cast<int>(begin));
    for (size_t i = begin; i < end; ++i) groups.half_edges.push_back(keys[i].half_edge);
  });
  groups.begin.push_back(static_cast<int>(keys.size()));
  return groups;
}

// The UV of the corner of face h / 3 at vertex v.
Eigen::RowVector2d cornerAt(const Triangles& F, const Layout& layout, int f, int v) {
  for (int k = 0; k < 3; ++k)
    if (F(f, k) == v) return layout.corner(f, k);
  return layout.corner(f, 0);
}

// Both sides of the edge (a, b) carry the same UVs in faces f and g.
bool sameSides(const Triangles& F, const Layout& layout, int f, int g, int a, int b) {
  return cornerAt(F, layout, f, a) == cornerAt(F, layout, g, a) &&
         cornerAt(F, layout, f, b) == cornerAt(F, layout, g, b);
}

// chartsByUVs over edge groups the caller already has.
std::vector<int> chartsOfGroups(const Triangles& F, const Layout& layout, const EdgeGroups& groups,
                                int* count) {
  const int faces = static_cast<int>(F.rows());
  DisjointSets sets(faces);
  for (size_t g = 0; g + 1 < groups.begin.size(); ++g)
    for (int i = groups.begin[g]; i < groups.begin[g + 1]; ++i)
      for (int j = i + 1; j < groups.begin[g + 1]; ++j) {
        const int hi = groups.half_edges[i], hj = groups.half_edges[j];
        const int a = F(hi / 3, hi % 3), b = F(hi / 3, (hi % 3 + 1) % 3);
        if (sameSides(F, layout, hi / 3, hj / 3, a, b)) sets.join(hi / 3, hj / 3);
      }
  std::vector<int> chart(faces), number(faces, -1);
  int charts = 0;
  for (int f = 0; f < faces; ++f) {
    const int root = sets.find(f);
    if (number[root] < 0) number[root] = charts++;
    chart[f] = number[root];
  }
  if (count) *count = charts;
  return chart;
}

// Bands of rows, each rastered by one thread, grown by `reach` rows on either side (faces
// reaching those rows are rastered by both bands); the counts are sums of integers, the same in
// any order.
constexpr int kBandRows = 64;

// The owner of pixels covered by triangles of two charts or more (as the gutter sees them).
constexpr int kShared = -1;

// A row's covered pixels x0..x1, all of one owner: a chart, or kShared.
struct OwnerRun {
  int x0, x1, owner;
};

// One band's buffers, reused from band to band: the triangles' spans per grown row, and the
// owner runs per row.
struct BandScratch {
  struct Span {
    int row, x0, x1, chart;
  };
  std::vector<Span> spans, by_row;
  std::vector<int> row_begin, fill;
  struct Event {
    int x, delta, chart;  // a span starts (+1) or ends (-1) at x
  };
  std::vector<Event> events;                   // one row's
  std::vector<std::pair<int, int>> active;     // (chart, spans covering)
  std::vector<OwnerRun> runs;                  // every grown row's, in row order
  std::vector<int> run_begin;                  // row r's: runs[run_begin[r] .. run_begin[r + 1])
  std::vector<int> window_at;                  // per window row, a run
  std::vector<std::pair<int, int>> intervals;  // a run's pixels near other owners
};

// The faces of each band of rows they may reach (grown by `reach`), and their corners in pixels.
struct FacesByBand {
  std::vector<std::array<Eigen::Vector2d, 3>> corners;
  std::vector<int> band_begin, band_face;
};

FacesByBand facesByBand(const Layout& layout, int size, int reach) {
  const int bands = (size + kBandRows - 1) / kBandRows;
  const int faces = layout.faceCount();
  FacesByBand out;
  auto& corners = out.corners;
  auto& band_begin = out.band_begin;
  corners.resize(faces);
  band_begin.assign(bands + 1, 0);
  std::vector<int> first_band(faces), last_band(faces);
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int f = first; f < last; ++f) {
      double low = std::numeric_limits<double>::infinity(), high = -low;
      for (int k = 0; k < 3; ++k) {
        corners[f][k] = (layout.corner(f, k) * size).transpose();
        low = std::min(low, corners[f][k].y()), high = std::max(high, corners[f][k].y());
      }
      // Rows whose centres the triangle may reach (none when not finite).
      const double row_low = std::ceil(low - 0.5), row_high = std::floor(high - 0.5);
      if (!(row_low <= row_high) || row_high < 0 || row_low > size - 1) {
        first_band[f] = 0, last_band[f] = -1;
        continue;
      }
      const int first_row = static_cast<int>(std::max(0.0, row_low));
      const int last_row = static_cast<int>(std::min<double>(size - 1, row_high));
      first_band[f] = std::max(0, first_row - reach) / kBandRows;
      last_band[f] = std::min(size - 1, last_row + reach) / kBandRows;
    }
  });
  for (int f = 0; f < faces; ++f)
    for (int b = first_band[f]; b <= last_band[f]; ++b) ++band_begin[b + 1];
  for (int b = 0; b < bands; ++b) band_begin[b + 1] += band_begin[b];
  out.band_face.resize(band_begin[bands]);
  {
    std::vector<int> fill(band_begin.begin(), band_begin.end() - 1);
    for (int f = 0; f < faces; ++f)
      for (int b = first_band[f]; b <= last_band[f]; ++b) out.band_face[fill[b]++] = f;
  }
  return out;
}

// Turns the band's spans (scratch.spans, rows relative to the grown band of `rows` rows) into
// owner runs per row (scratch.runs, scratch.run_begin); returns the pixels of rows
// [core_begin, core_end) covered twice or more.
long long ownerRuns(BandScratch& s, int rows, int core_begin, int core_end) {
  s.row_begin.assign(rows + 1, 0);
  for (const BandScratch::Span& span : s.spans) ++s.row_begin[span.row + 1];
  for (int r = 0; r < rows; ++r) s.row_begin[r + 1] += s.row_begin[r];
  s.by_row.resize(s.spans.size());
  s.fill.assign(s.row_begin.begin(), s.row_begin.end() - 1);
  for (const BandScratch::Span& span : s.spans) s.by_row[s.fill[span.row]++] = span;
  s.runs.clear();
  s.run_begin.assign(1, 0);
  long long overlapping = 0;
  for (int r = 0; r < rows; ++r) {
    // A sweep along the row over the places where spans start and end: between two of them
    // the covering spans, and so the owner, stay the same.
    s.events.clear();
    for (int i = s.row_begin[r]; i < s.row_begin[r + 1]; ++i) {
      const BandScratch::Span& span = s.by_row[i];
      s.events.push_back({span.x0, 1, span.chart});
      s.events.push_back({span.x1 + 1, -1, span.chart});
    }
    std::sort(s.events.begin(), s.events.end(),
              [](const BandScratch::Event& a, const BandScratch::Event& b) { return a.x < b.x; });
    s.active.clear();
    int covering = 0;
    const bool core = r >= core_begin && r < core_end;
    for (size_t e = 0; e < s.events.size();) {
      const int x = s.events[e].x;
      for (; e < s.events.size() && s.events[e].x == x; ++e) {
        const int chart = s.events[e].chart, delta = s.events[e].delta;
        covering += delta;
        auto it = std::find_if(s.active.begin(), s.active.end(),
                               [&](const std::pair<int, int>& a) { return a.first == chart; });
        if (it == s.active.end()) it = s.active.insert(s.active.end(), {chart, 0});
        if ((it->second += delta) == 0) s.active.erase(it);
      }
      if (covering == 0 || e == s.events.size()) continue;
      const int next = s.events[e].x;  // pixels x .. next - 1 are covered alike
      if (core && covering >= 2) overlapping += next - x;
      const int owner = s.active.size() == 1 ? s.active.front().first : kShared;
      if (static_cast<int>(s.runs.size()) > s.run_begin.back() && s.runs.back().owner == owner &&
          s.runs.back().x1 + 1 == x)
        s.runs.back().x1 = next - 1;
      else
        s.runs.push_back({x, next - 1, owner});
    }
    s.run_begin.push_back(static_cast<int>(s.runs.size()));
  }
  return overlapping;
}

// The covered pixels of rows [core_begin, core_end) (relative to the grown band of `rows` rows)
// whose gutter is broken: whose window of (2 reach + 1)^2 pixels holds a pixel of another owner
// or a shared one (itself included), from ownerRuns' runs.
long long gutterBreaks(BandScratch& s, int rows, int reach, int core_begin, int core_end) {
  long long broken = 0;
  for (int r = core_begin; r < core_end; ++r) {
    const int from = std::max(0, r - reach), window = std::min(rows - 1, r + reach) - from + 1;
    // Per window row, the first run that may still reach row r's runs to come: a row's runs
    // are sorted and disjoint, so their grown ends only increase.
    s.window_at.resize(window);
    for (int w = 0; w < window; ++w) s.window_at[w] = s.run_begin[from + w];
    for (int i = s.run_begin[r]; i < s.run_begin[r + 1]; ++i) {
      const OwnerRun run = s.runs[i];
      if (run.owner == kShared) {
        broken += run.x1 - run.x0 + 1;
        continue;
      }
      s.intervals.clear();
      for (int w = 0; w < window; ++w) {
        const int end = s.run_begin[from + w + 1];
        int& k = s.window_at[w];
        while (k < end && s.runs[k].x1 + reach < run.x0) ++k;
        for (int j = k; j < end && s.runs[j].x0 - reach <= run.x1; ++j)
          if (s.runs[j].owner != run.owner)
            s.intervals.emplace_back(std::max(run.x0, s.runs[j].x0 - reach),
                                     std::min(run.x1, s.runs[j].x1 + reach));
      }
      std::sort(s.intervals.begin(), s.intervals.end());
      int counted_to = INT_MIN;  // their union's pixels, each once
      for (const auto& [low, high] : s.intervals) {
        const int first = std::max(low, counted_to + 1);
        if (high >= first) broken += high - first + 1, counted_to = high;
      }
    }
  }
  return broken;
}

}  // namespace

std::vector<int> chartsByUVs(const Triangles& F, const Layout& layout, int* count) {
  return chartsOfGroups(F, layout, edgeGroups(F), count);
}

PixelMeasures measurePixels(const Layout& layout, const std::vector<int>& chart, int size,
                            int gutter, const std::function<void(double)>& progress) {
  PixelMeasures m;
  if (size <= 0) return m;
  const int reach = std::max(0, gutter - 1);
  const int bands = (size + kBandRows - 1) / kBandRows;
  const FacesByBand banded = facesByBand(layout, size, reach);
  const auto& corners = banded.corners;
  const auto& band_begin = banded.band_begin;
  const auto& band_face = banded.band_face;
  std::vector<long long> overlapping(bands, 0), violations(bands, 0);
  // In runs of pixels, not pixels: the cost follows the triangles' rows, not the texture's area
  // (a small part's check at 4096^2 filled and swept 16M pixels several times over).
  // Bands are handed out one at a time: the packed charts fill the texture unevenly, and in
  // halves one core waited for the other (CPU/wall 1.26 over storage at 13.6M faces).
  std::atomic<int> bands_done{0};
  std::vector<BandScratch> scratch(parallelWorkers());
  parallelForDynamic(bands, 1, [&](int begin, int end, int worker) {
    BandScratch& s = scratch[worker];
    for (int b = begin; b < end; ++b) {
      const int row_begin = b * kBandRows, row_end = std::min(size, row_begin + kBandRows);
      const int grown_begin = std::max(0, row_begin - reach);
      const int grown_end = std::min(size, row_end + reach);
      s.spans.clear();
      for (int i = band_begin[b]; i < band_begin[b + 1]; ++i) {
        const int f = band_face[i];
        const int c = chart.empty() ? 0 : chart[f];
        coveredSpansInRows(corners[f].data(), size, grown_begin, grown_end,
                           [&](int y, int x0, int x1) {
                             s.spans.push_back({y - grown_begin, x0, x1, c});
                           });
      }
      const int rows = grown_end - grown_begin;
      const int core_begin = row_begin - grown_begin, core_end = row_end - grown_begin;
      overlapping[b] = ownerRuns(s, rows, core_begin, core_end);
      // A gutter of one texel: neighbours may belong to any chart.
      if (reach > 0) violations[b] = gutterBreaks(s, rows, reach, core_begin, core_end);
      const int done = ++bands_done;
      if (worker == 0 && progress) progress(static_cast<double>(done) / bands);
    }
  });
  for (int b = 0; b < bands; ++b) {
    m.overlapping_pixels += overlapping[b];
    m.gutter_violations += violations[b];
  }
  return m;
}

AtlasMeasures measureLayout(const Positions& V, const Triangles& F, const Layout& layout,
                            const std::function<void()>& step) {
  AtlasMeasures m;
  const int faces = static_cast<int>(F.rows());
  const EdgeGroups groups = edgeGroups(F);
  if (step) step();
  // The charts' union-find here, the seam and the 3D area on another core: each a pass of a
  // second or more at 13M faces, none depending on the others.
  double area3d = 0, seam = 0;
  parallelForAlongside(
      1, 1, [&] { m.chart = chartsOfGroups(F, layout, groups, &m.charts); },
      [&](int, int, int) {
        for (int f = 0; f < faces; ++f) area3d += faceArea3d(V, F, f);
        for (size_t g = 0; g + 1 < groups.begin.size(); ++g) {
          const int first = groups.begin[g], last = groups.begin[g + 1];
          if (last - first < 2) continue;  // the mesh's own boundary
          const int h0 = groups.half_edges[first];
          const int a = F(h0 / 3, h0 % 3), b = F(h0 / 3, (h0 % 3 + 1) % 3);
          bool cut = false;
          for (int i = first + 1; i < last && !cut; ++i)
            cut = !sameSides(F, layout, h0 / 3, groups.half_edges[i] / 3, a, b);
          if (cut) seam += (V.row(a) - V.row(b)).norm();
        }
      });
  if (step) step();
  m.seam = area3d > 0 ? seam / std::sqrt(area3d) : 0;

  // Each face's UV area and whether it leaves the square on every core; summed in face order.
  std::vector<double> signed_area(faces);
  const int slots = faceSumSlots(faces);
  std::vector<int> outside(slots, 0);
  parallelForSlots(faces, slots, [&](int begin, int end, int slot) {
    for (int f = begin; f < end; ++f) {
      const Eigen::RowVector2d p = layout.corner(f, 0), q = layout.corner(f, 1),
                               r = layout.corner(f, 2);
      signed_area[f] = 0.5 * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
      bool out = false;
      for (int k = 0; k < 3; ++k) {
        const Eigen::RowVector2d c = layout.corner(f, k);
        out |= !(c.x() >= 0 && c.x() <= 1 && c.y() >= 0 && c.y() <= 1);
      }
      outside[slot] += out;
    }
  });
  if (step) step();
  std::vector<double> chart_area(m.charts, 0.0);
  double uv_area = 0;
  for (int f = 0; f < faces; ++f) {
    chart_area[m.chart[f]] += signed_area[f];
    uv_area += std::abs(signed_area[f]);
  }
  for (int count : outside) m.outside_faces += count;
  for (double a : chart_area) m.mirrored_charts += a < 0;
  m.efficiency = uv_area;
  return m;
}

AtlasMeasures measureAtlas(const Positions& V, const Triangles& F, const Layout& layout,
                           int texture_size, int gutter) {
  AtlasMeasures m = measureLayout(V, F, layout);
  // Orientation per chart, flips, stretch: one normalization over the atlas.
  Layout charted = layout;
  charted.chart = m.chart;
  const StretchMetrics stretch = layoutStretch(V, F, charted);
  m.l2 = stretch.l2;
  m.linf = stretch.linf;
  m.flipped_faces = stretch.flipped_faces;
  const PixelMeasures pixels = measurePixels(layout, m.chart, texture_size, gutter);
  m.overlapping_pixels = pixels.overlapping_pixels;
  m.gutter_violations = pixels.gutter_violations;
  return m;
}

}  // namespace sdp::atlas
