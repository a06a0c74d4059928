#include "measure.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
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

// Owners are chart numbers (>= 0), kEmpty or kShared; kShared is the least, kEmpty the greatest
// as the window minimum sees it (it is skipped).
constexpr int kEmpty = std::numeric_limits<int>::max(), kShared = -1;

// Bands of rows, each rastered by one thread into buffers of its own, grown by `reach` rows on
// either side (faces reaching those rows are rastered by both bands), so the texture is never
// held whole; the counts are sums of integers, the same in any order.
constexpr int kBandRows = 64;

// One band's buffers: the owner of each pixel of its grown rows, their window minimum and
// maximum along rows, and one row's worth of the rest.
struct BandScratch {
  std::vector<int> owner, low, high, seen, least, greatest;
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
  for (int f = 0; f < faces; ++f) {
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
    for (int b = first_band[f]; b <= last_band[f]; ++b) ++band_begin[b + 1];
  }
  for (int b = 0; b < bands; ++b) band_begin[b + 1] += band_begin[b];
  out.band_face.resize(band_begin[bands]);
  {
    std::vector<int> fill(band_begin.begin(), band_begin.end() - 1);
    for (int f = 0; f < faces; ++f)
      for (int b = first_band[f]; b <= last_band[f]; ++b) out.band_face[fill[b]++] = f;
  }
  return out;
}

// The covered pixels of rows [row_begin, row_end) whose gutter is broken, from the owners of the
// rows [grown_begin, grown_end) around them (scratch.owner); the other buffers are scratch.
long long gutterBreaks(BandScratch& scratch, int size, int reach, int row_begin, int row_end,
                       int grown_begin, int grown_end) {
  const std::vector<int>& owner = scratch.owner;
  std::vector<int>&low = scratch.low, &high = scratch.high, &seen = scratch.seen;
  std::vector<int>&least = scratch.least, &greatest = scratch.greatest;
  // A covered pixel breaks the gutter when its window of (2 reach + 1)^2 pixels holds another
  // owner or a shared pixel: when the window's least and greatest owners (empty ones
  // skipped: the greatest reads them as kNone) differ. Both are taken along rows, then along
  // columns, without branches (the passes visit every pixel of the texture).
  constexpr int kNone = kShared - 1;
  const int grown_rows = grown_end - grown_begin;
  for (int y = 0; y < grown_rows; ++y) {
    const int* row = &owner[static_cast<size_t>(y) * size];
    int* row_low = &low[static_cast<size_t>(y) * size];
    int* row_high = &high[static_cast<size_t>(y) * size];
    for (int x = 0; x < size; ++x) seen[x] = row[x] == kEmpty ? kNone : row[x];
    std::copy(row, row + size, row_low);
    std::copy(seen.begin(), seen.end(), row_high);
    // Shift by shift, each loop plain enough to run in vector registers.
    for (int d = 1; d <= reach && d < size; ++d) {
      for (int x = 0; x < size - d; ++x) {
        row_low[x] = std::min(row_low[x], row[x + d]);
        row_high[x] = std::max(row_high[x], seen[x + d]);
      }
      for (int x = d; x < size; ++x) {
        row_low[x] = std::min(row_low[x], row[x - d]);
        row_high[x] = std::max(row_high[x], seen[x - d]);
      }
    }
  }
  long long broken = 0;
  for (int y = row_begin; y < row_end; ++y) {
    const int at = y - grown_begin;
    const int* row = &owner[static_cast<size_t>(at) * size];
    const int from = std::max(0, at - reach), to = std::min(grown_rows - 1, at + reach);
    std::copy(&low[static_cast<size_t>(from) * size], &low[static_cast<size_t>(from) * size] + size,
              least.begin());
    std::copy(&high[static_cast<size_t>(from) * size],
              &high[static_cast<size_t>(from) * size] + size, greatest.begin());
    for (int r = from + 1; r <= to; ++r) {
      const int* r_low = &low[static_cast<size_t>(r) * size];
      const int* r_high = &high[static_cast<size_t>(r) * size];
      for (int x = 0; x < size; ++x) {
        least[x] = std::min(least[x], r_low[x]);
        greatest[x] = std::max(greatest[x], r_high[x]);
      }
    }
    int row_broken = 0;
    for (int x = 0; x < size; ++x)
      row_broken += row[x] != kEmpty && (least[x] != greatest[x] || least[x] == kShared);
    broken += row_broken;
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
  parallelFor(bands, 1, [&](int begin, int end, int worker) {
    const size_t rows = kBandRows + 2 * reach;
    BandScratch s{std::vector<int>(rows * size), std::vector<int>(rows * size),
                  std::vector<int>(rows * size), std::vector<int>(size),
                  std::vector<int>(size),        std::vector<int>(size)};
    std::vector<int>& owner = s.owner;
    std::vector<unsigned char> covers(static_cast<size_t>(kBandRows) * size);
    for (int b = begin; b < end; ++b) {
      const int row_begin = b * kBandRows, row_end = std::min(size, row_begin + kBandRows);
      const int grown_begin = std::max(0, row_begin - reach);
      const int grown_end = std::min(size, row_end + reach);
      std::fill(owner.begin(), owner.end(), kEmpty);
      std::fill(covers.begin(), covers.end(), 0);
      for (int i = band_begin[b]; i < band_begin[b + 1]; ++i) {
        const int f = band_face[i];
        const int c = chart.empty() ? 0 : chart[f];
        // Per run of a row, in loops plain enough to run in vector registers.
        coveredSpansInRows(corners[f].data(), size, grown_begin, grown_end,
                           [&](int y, int x0, int x1) {
                             int* o = &owner[static_cast<size_t>(y - grown_begin) * size];
                             for (int x = x0; x <= x1; ++x)
                               o[x] = o[x] == kEmpty || o[x] == c ? c : kShared;
                             if (y < row_begin || y >= row_end) return;
                             unsigned char* n = &covers[static_cast<size_t>(y - row_begin) * size];
                             for (int x = x0; x <= x1; ++x) n[x] = n[x] < 255 ? n[x] + 1 : 255;
                           });
      }
      for (size_t at = 0; at < static_cast<size_t>(row_end - row_begin) * size; ++at)
        overlapping[b] += covers[at] >= 2;
      if (reach == 0) continue;  // a gutter of one texel: neighbours may belong to any chart
      violations[b] = gutterBreaks(s, size, reach, row_begin, row_end, grown_begin, grown_end);
      if (worker == 0 && progress) progress(static_cast<double>(b + 1 - begin) / (end - begin));
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
  m.chart = chartsOfGroups(F, layout, groups, &m.charts);
  if (step) step();

  // Seam and 3D area.
  double area3d = 0;
  for (int f = 0; f < faces; ++f) area3d += faceArea3d(V, F, f);
  double seam = 0;
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
  m.seam = area3d > 0 ? seam / std::sqrt(area3d) : 0;
  if (step) step();

  std::vector<double> chart_area(m.charts, 0.0);
  double uv_area = 0;
  for (int f = 0; f < faces; ++f) {
    const Eigen::RowVector2d p = layout.corner(f, 0), q = layout.corner(f, 1),
                             r = layout.corner(f, 2);
    const double signed_area = 0.5 * ((q - p).x() * (r - p).y() - (q - p).y() * (r - p).x());
    chart_area[m.chart[f]] += signed_area;
    uv_area += std::abs(signed_area);
    bool outside = false;
    for (int k = 0; k < 3; ++k) {
      const Eigen::RowVector2d c = layout.corner(f, k);
      outside |= !(c.x() >= 0 && c.x() <= 1 && c.y() >= 0 && c.y() <= 1);
    }
    m.outside_faces += outside;
  }
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
