#include "pack.h"

#include <algorithm>
#include <atomic>
#include <climits>
#include <cmath>
#include <mutex>
#include <numeric>
#include <string>

#include "convex_cut.h"
#include "core/common/error.h"
#include "core/common/geometry.h"
#include "core/common/parallel.h"
#include "raster.h"

namespace sdp::atlas {
namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

}  // namespace

bool xThenY(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() != b.x() ? a.x() < b.x() : a.y() < b.y();
}

std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), xThenY);
  return convexHullOfSorted(std::move(points));
}

std::vector<Eigen::Vector2d> convexHullOfSorted(std::vector<Eigen::Vector2d> points) {
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], points[i - 1]) <= 0) --k;
    hull[k++] = points[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

namespace {

// An axis-aligned rectangle, by its lowest and highest corners.
struct Bounds {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d high = -low;
  Eigen::Vector2d extent() const { return high - low; }
};
// The rectangle around `points`, each first turned by `turn`.
Bounds boundsOf(const std::vector<Eigen::Vector2d>& points,
                const Eigen::Matrix2d& turn = Eigen::Matrix2d::Identity()) {
  Bounds b;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d q = turn * p;
    b.low = b.low.cwiseMin(q), b.high = b.high.cwiseMax(q);
  }
  return b;
}

Eigen::Matrix2d rotationBy(double angle) {
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

}  // namespace

Eigen::Matrix2d smallestBoxRotation(const std::vector<Eigen::Vector2d>& uv) {
  const std::vector<Eigen::Vector2d> hull = convexHull(uv);
  double best_area = std::numeric_limits<double>::infinity();
  Eigen::Matrix2d best = Eigen::Matrix2d::Identity();
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d e = hull[(i + 1) % hull.size()] - hull[i];
    if (e.squaredNorm() == 0) continue;
    const Eigen::Matrix2d r = rotationBy(-std::atan2(e.y(), e.x()));
    const Eigen::Vector2d size = boundsOf(hull, r).extent();
    if (size.x() * size.y() < best_area * (1 - 1e-9)) {
      best_area = size.x() * size.y();
      best = size.x() >= size.y() ? r : Eigen::Matrix2d(rotationBy(kPi / 2) * r);
    }
  }
  return best;
}

namespace {

const Eigen::Matrix2d& quarterTurn(int q) {
  static const Eigen::Matrix2d turns[4] = {(Eigen::Matrix2d() << 1, 0, 0, 1).finished(),
                                           (Eigen::Matrix2d() << 0, -1, 1, 0).finished(),
                                           (Eigen::Matrix2d() << -1, 0, 0, -1).finished(),
                                           (Eigen::Matrix2d() << 0, 1, -1, 0).finished()};
  return turns[q];
}

// A chart's border half-edges (from, to), into its points.
using Edges = std::vector<std::pair<int, int>>;

// Cell runs [low, high] per column, sorted and disjoint.
using Runs = std::vector<std::pair<int, int>>;

// Merges the runs of runs[first, end), already sorted, that overlap or touch, in place;
// returns the new end.
size_t joinTouchingFrom(Runs& runs, size_t first) {
  size_t kept = first;
  for (size_t i = first; i < runs.size(); ++i)
    if (kept > first && runs[i].first <= runs[kept - 1].second + 1)
      runs[kept - 1].second = std::max(runs[kept - 1].second, runs[i].second);
    else
      runs[kept++] = runs[i];
  runs.resize(kept);
  return kept;
}

// Sorts runs[first, end) and merges those that overlap or touch, in place; returns the new end.
size_t mergeRunsFrom(Runs& runs, size_t first) {
  // A column's runs are few (a footprint's grown column gathers 2 x gutter - 1 columns of one or
  // two runs each): an insertion sort, without std::sort's set-up for each. Either sort gives
  // the same order, the runs being compared whole.
  if (runs.size() - first <= 16) {
    for (size_t i = first + 1; i < runs.size(); ++i)
      for (size_t j = i; j > first && runs[j] < runs[j - 1]; --j) std::swap(runs[j], runs[j - 1]);
  } else {
    std::sort(runs.begin() + first, runs.end());
  }
  return joinTouchingFrom(runs, first);
}

// Runs per column in one array, as a footprint's are: column i's are runs[begin[i] ..
// begin[i + 1]), sorted, disjoint and not touching. One allocation per footprint, not one per
// column (the packer builds four footprints per chart and scale tried; allocating per column
// was a third of the packing's time on small CAD parts).
struct ColumnRuns {
  std::vector<int> begin = {0};
  std::vector<std::pair<int, int>> runs;

  struct Column {
    const std::pair<int, int>*first, *last;
    const std::pair<int, int>* begin() const { return first; }
    const std::pair<int, int>* end() const { return last; }
    bool empty() const { return first == last; }
    const std::pair<int, int>& front() const { return *first; }
    const std::pair<int, int>& back() const { return last[-1]; }
  };
  Column operator[](int i) const { return {runs.data() + begin[i], runs.data() + begin[i + 1]}; }
  int columns() const { return static_cast<int>(begin.size()) - 1; }

  // Ends the next column: the runs appended since the last one, sorted and merged.
  void closeColumn() { begin.push_back(static_cast<int>(mergeRunsFrom(runs, begin.back()))); }
  // No columns, the memory kept for the next footprint.
  void clear() {
    begin.assign(1, 0);
    runs.clear();
  }
};

// A footprint's temporaries, kept per thread: the packer builds four footprints per chart and
// scale tried, and allocating them anew each time (megabytes for a chart across a 4096 texture)
// cost page faults for a seventh of a small part's packing.
struct FootprintScratch {
  std::vector<std::array<int, 3>> spans;          // (column, low, high)
  std::vector<std::pair<int, double>> crossings;  // (column, y)
  std::vector<double> along;
  std::vector<int> start, fill;
  std::vector<std::pair<int, int>> sorted;
};
FootprintScratch& footprintScratch() {
  thread_local FootprintScratch scratch;
  return scratch;
}

// The items' values grouped by column (a counting sort, in the items' order within a column):
// column c's are out[start[c] .. start[c + 1]). `fill` is scratch.
template <class Item, class Value, class ColumnOf, class ValueOf>
void bucketByColumn(int columns, const std::vector<Item>& items, ColumnOf column_of,
                    ValueOf value_of, std::vector<int>& start, std::vector<int>& fill,
                    std::vector<Value>& out) {
  start.assign(columns + 1, 0);
  for (const Item& item : items) ++start[column_of(item) + 1];
  for (int c = 0; c < columns; ++c) start[c + 1] += start[c];
  out.resize(items.size());
  fill.assign(start.begin(), start.end() - 1);
  for (const Item& item : items) out[fill[column_of(item)]++] = value_of(item);
}

// Runs given as (column, low, high) in any order, per column, into `out`.
void byColumn(int columns, const std::vector<std::array<int, 3>>& spans, ColumnRuns& out) {
  FootprintScratch& scratch = footprintScratch();
  std::vector<int>& start = scratch.start;
  std::vector<std::pair<int, int>>& sorted = scratch.sorted;
  bucketByColumn(
      columns, spans, [](const std::array<int, 3>& s) { return s[0]; },
      [](const std::array<int, 3>& s) { return std::make_pair(s[1], s[2]); }, start, scratch.fill,
      sorted);
  out.clear();
  out.runs.reserve(spans.size());
  for (int c = 0; c < columns; ++c) {
    out.runs.insert(out.runs.end(), sorted.begin() + start[c], sorted.begin() + start[c + 1]);
    out.closeColumn();
  }
}

// A chart at one scale and turn, as the packer sees it: per cell column the runs of cells it
// touches, and the runs of those cells grown by the gutter (the columns reach further out too).
struct Footprint {
  int width = 0, height = 0;  // cells, without the gutter
  int reach = 0;              // gutter - 1
  Eigen::Vector2d base;       // the cell grid's origin in the turned, scaled frame
  ColumnRuns cells;           // per column [0, width)
  ColumnRuns grown;           // per column [-reach, width + reach), shifted by reach
};

// The footprint of a chart whose points, turned and scaled, are `p`. Each triangle touches one
// run of cells per column (it is convex), found by the row spans of the transposed triangle, so
// the cost follows the triangles' outlines, not the chart's area in texels. With the chart's
// border `edges` (its outline and holes: the chart is one-to-one), only they are rastered, and
// the cells between them in a column are those whose centre line lies inside (a cell that
// touches the chart either meets its border or is inside it): the cost follows the border.
// Built into `fp`, whose memory is reused.
void footprint(const std::vector<Eigen::Vector2d>& p,
               const std::vector<std::array<int, 3>>& triangles, const Edges& edges, double margin,
               int reach, int size, Footprint& fp) {
  fp.cells.clear();
  fp.grown.clear();
  fp.base = Eigen::Vector2d::Zero();
  fp.reach = reach;
  const auto [low, high] = boundsOf(p);
  // Larger than the texture (or not finite): it cannot be placed, and is not rastered.
  const Eigen::Vector2d extent = high - low;
  if (!(extent.maxCoeff() < size)) {
    fp.width = fp.height = size + 1;
    return;
  }
  fp.base = (low - Eigen::Vector2d::Constant(margin)).array().floor();
  fp.width = static_cast<int>(std::floor(high.x() + margin - fp.base.x())) + 1;
  fp.height = static_cast<int>(std::floor(high.y() + margin - fp.base.y())) + 1;
  // Transposed: a row of q is a column of cells.
  auto transposed = [&](int v) {
    const Eigen::Vector2d r = p[v] - fp.base;
    return Eigen::Vector2d(r.y(), r.x());
  };
  FootprintScratch& scratch = footprintScratch();
  std::vector<std::array<int, 3>>& spans = scratch.spans;
  spans.clear();
  auto addSpan = [&](int x, int y0, int y1) { spans.push_back({x, y0, y1}); };
  if (edges.size() >= 3) {
    std::vector<std::pair<int, double>>& crossings = scratch.crossings;
    crossings.clear();
    for (const auto& [from, to] : edges) {
      const Eigen::Vector2d a = p[from] - fp.base, b = p[to] - fp.base;
      conservativeSegmentSpans(transposed(from), transposed(to), margin, fp.height, fp.width,
                               addSpan);
      // Where the edge crosses the centre lines x = c + 1/2 of the columns it spans.
      const int c0 = std::max(0, static_cast<int>(std::ceil(std::min(a.x(), b.x()) - 0.5)));
      const int c1 = std::min(fp.width - 1, static_cast<int>(std::floor(std::max(a.x(), b.x()))));
      for (int c = c0; c <= c1; ++c) {
        const double line = c + 0.5;
        if ((a.x() < line) != (b.x() < line))
          crossings.emplace_back(c, a.y() + (b.y() - a.y()) * (line - a.x()) / (b.x() - a.x()));
      }
    }
    // Per column its crossings in y order: bucketed by column, then each column sorted (one
    // sort of every crossing by (column, y) was a third of a small part's footprint).
    std::vector<int>& start = scratch.start;
    std::vector<double>& along = scratch.along;
    bucketByColumn(
        fp.width, crossings, [](const std::pair<int, double>& c) { return c.first; },
        [](const std::pair<int, double>& c) { return c.second; }, start, scratch.fill, along);
    for (int c = 0; c < fp.width; ++c) {
      std::sort(along.begin() + start[c], along.begin() + start[c + 1]);
      for (int k = start[c]; k + 1 < start[c + 1]; k += 2) {
        const int y0 = std::max(0, static_cast<int>(std::floor(along[k])));
        const int y1 = std::min(fp.height - 1, static_cast<int>(std::floor(along[k + 1])));
        if (y0 <= y1) addSpan(c, y0, y1);
      }
    }
  } else {
    for (const auto& t : triangles) {
      const Eigen::Vector2d q[3] = {transposed(t[0]), transposed(t[1]), transposed(t[2])};
      conservativeSpans(q, margin, fp.height, fp.width, addSpan);
    }
  }
  byColumn(fp.width, spans, fp.cells);
  // Grown: column j gathers the runs of columns j - 2 reach ... j, each widened by reach.
  fp.grown.runs.reserve(fp.cells.runs.size() * (2 * reach + 1));
  for (int j = 0; j < fp.width + 2 * reach; ++j) {
    for (int i = std::max(0, j - 2 * reach); i <= std::min(fp.width - 1, j); ++i)
      for (const auto& [lo, hi] : fp.cells[i]) fp.grown.runs.emplace_back(lo - reach, hi + reach);
    fp.grown.closeColumn();
  }
}

// The texture's occupied cells (grown by the gutter) as runs per column.
class Occupancy {
 public:
  explicit Occupancy(int size) : columns_(size) {}

  // The lowest y >= 0 at which the chart's cells, moved by (x, y), miss every occupied cell.
  // Returns INT_MAX early once y cannot stay below `give_up`.
  int lowestFree(const Footprint& fp, int x, int give_up = INT_MAX) const {
    // Every move below is to the lowest spot that clears one occupied run in the way, so none
    // passes over a free spot, and the moves may come in any order. Columns spread across the
    // chart come first: a run in the way is usually met there at a fraction of a full pass's
    // cost (most spots tried cannot beat the best so far, and end as soon as that is known).
    // Every 8th column, fewer for narrow charts (every 32nd of the width was as fast on the
    // scans bench's 1.36M-face armadillo, but tested every column of the narrow charts of larger
    // meshes: on its 5.47M-face twin pack and store 65 -> 48 s).
    const int sample = std::clamp(fp.width / 4, 1, kSampleStep);
    int y = 0;
    if (raise(fp, x, sample, give_up, y) == kGaveUp) return INT_MAX;
    for (int pass = 0; pass < kPasses; ++pass) {
      const Move move = clear(fp, x, sample, give_up, y);
      if (move == kGaveUp) return INT_MAX;
      if (move == kStayed) break;
    }
    if (raise(fp, x, 1, give_up, y) == kGaveUp) return INT_MAX;
    // A hole is searched for a few passes over every column; past them the chart goes above
    // every cell of its columns, which is always free.
    for (int pass = 0;; ++pass) {
      if (pass == kPasses) {
        for (int i = 0; i < fp.width; ++i)
          if (!columns_[x + i].empty() && !fp.cells[i].empty())
            y = std::max(y, columns_[x + i].back().second + 1 - fp.cells[i].front().first);
        return y >= give_up ? INT_MAX : y;
      }
      const Move move = clear(fp, x, 1, give_up, y);
      if (move == kGaveUp) return INT_MAX;
      if (move == kStayed) return y;
    }
  }

  void occupy(const Footprint& fp, int x, int y) {
    for (int j = 0; j < fp.grown.columns(); ++j) {
      const int column = x + j - fp.reach;
      if (column < 0 || column >= static_cast<int>(columns_.size())) continue;
      Runs& runs = columns_[column];
      const size_t before = runs.size();
      for (const auto& [lo, hi] : fp.grown[j]) {
        runs.emplace_back(y + lo, y + hi);
        top_ = std::max(top_, y + hi + 1 - fp.reach);
      }
      // Both the column's runs and the chart's are sorted: merged in order, not sorted anew
      // (a full column's sort per chart placed); the same runs either way.
      std::inplace_merge(runs.begin(), runs.begin() + before, runs.end());
      joinTouchingFrom(runs, 0);
    }
  }
  int top() const { return top_; }  // one above the highest chart cell
  // The height of the column's filled bottom (0 when its lowest cell is free).
  int floor(int column) const {
    const Runs& runs = columns_[column];
    return !runs.empty() && runs.front().first == 0 ? runs.front().second + 1 : 0;
  }

 private:
  static constexpr int kPasses = 4;
  static constexpr int kSampleStep = 8;
  enum Move { kStayed, kMoved, kGaveUp };

  // Raises y above each column's filled bottom (the run from row 0), every `step`-th column:
  // only holes above it are searched.
  Move raise(const Footprint& fp, int x, int step, int give_up, int& y) const {
    for (int i = 0; i < fp.width; i += step) {
      const Runs& column = columns_[x + i];
      if (!fp.cells[i].empty() && !column.empty() && column.front().first == 0)
        y = std::max(y, column.front().second + 1 - fp.cells[i].front().first);
    }
    return y >= give_up ? kGaveUp : kStayed;
  }

  // One pass over every `step`-th column, moving y above each occupied run in the way.
  Move clear(const Footprint& fp, int x, int step, int give_up, int& y) const {
    Move move = kStayed;
    for (int i = 0; i < fp.width; i += step) {
      const Runs& column = columns_[x + i];
      for (const auto& [lo, hi] : fp.cells[i]) {
        // The first occupied run ending at or above this run's bottom.
        auto it =
            std::lower_bound(column.begin(), column.end(), y + lo,
                             [](const std::pair<int, int>& r, int v) { return r.second < v; });
        if (it != column.end() && it->first <= y + hi) {
          y = it->second + 1 - lo;
          if (y >= give_up) return kGaveUp;
          move = kMoved;
        }
      }
    }
    return move;
  }

  std::vector<Runs> columns_;
  int top_ = 0;
};

// Charts with at least this many texture coordinates, or this many texels across, are searched
// by parallel workers: a search's cost follows the footprint's size, and a CAD part's flat face
// is a few points over hundreds of texels.
constexpr size_t kFewestPointsForParallelSearch = 100;
constexpr double kFewestTexelsForParallelSearch = 32;

bool worthParallelSearch(const std::vector<Eigen::Vector2d>& p) {
  if (p.size() >= kFewestPointsForParallelSearch) return true;
  Eigen::Vector2d low = p.front(), high = p.front();
  for (const Eigen::Vector2d& q : p) low = low.cwiseMin(q), high = high.cwiseMax(q);
  return (high - low).maxCoeff() >= kFewestTexelsForParallelSearch;
}

// Whether a chart whose smallest rectangle is `extent`, at `scale`, is too long for the texture
// along the rectangle's sides and shorter across its diagonal (a long strip: a CAD part's side
// face of two triangles, which no cut can shorten).
bool diagonalFits(const Eigen::Vector2d& extent, double scale, int size) {
  const double along = extent.maxCoeff() * scale;
  return along > size - 2 && extent.sum() * scale / std::sqrt(2.0) < along;
}

// The length of texture a chart needs: along its rectangle, or across it when that is shorter.
double neededLength(const Eigen::Vector2d& extent) {
  return std::min(extent.maxCoeff(), extent.sum() / std::sqrt(2.0));
}

// The columns tried first in each turn are shared out in this many slices, so that both cores
// work on one chart whatever its turns cost.
constexpr int kSlicesPerTurn = 2;

// Calls task(0) ... task(n - 1), on every core when `parallel`, each exactly once.
template <class Task>
void runTasks(int n, bool parallel, const Task& task) {
  if (!parallel) {
    for (int t = 0; t < n; ++t) task(t);
    return;
  }
  parallelForDynamic(n, 1, [&](int begin, int end, int) {
    for (int t = begin; t < end; ++t) task(t);
  });
}

struct Spot {
  int top = INT_MAX, y = 0, x = 0, turn = 0;
  bool operator<(const Spot& o) const {
    return top != o.top ? top < o.top : y != o.y ? y < o.y : x < o.x;
  }
};

// The lowest free spot for a chart whose points, framed and scaled, are `p` (see packAt), and
// in `turned` its footprint at each quarter turn.
Spot lowestSpot(const Occupancy& occupancy, const ChartShape& chart, const Edges& border,
                const std::vector<Eigen::Vector2d>& p, const PackOptions& options, int reach,
                Footprint (&turned)[4]) {
  const int size = options.texture_size;
  // Each quarter turn and slice searched on its own (so in parallel), each keeping its lowest
  // spot; a spot is skipped only when it cannot beat the lowest its slice has found, so the
  // lowest of all is the same whatever the order, on any number of cores.
  Spot spots[4][kSlicesPerTurn];
  // Per turn, the lowest top either of its slices has found: a spot above it cannot be the
  // turn's lowest, so both slices skip it (the turn's lowest is the same in any order).
  std::atomic<int> turn_top[4];
  for (std::atomic<int>& top : turn_top) top = INT_MAX;
  auto tryAt = [&](const Footprint& fp, int turn, int x, Spot& local) {
    const int top = std::min(local.top, turn_top[turn].load(std::memory_order_relaxed));
    const int y = occupancy.lowestFree(fp, x, top == INT_MAX ? INT_MAX : top - fp.height + 1);
    if (y == INT_MAX) return;
    const Spot spot{y + fp.height, y, x, turn};
    if (spot < local) local = spot;
    for (int seen = turn_top[turn].load();
         spot.top < seen && !turn_top[turn].compare_exchange_weak(seen, spot.top);)
      ;
  };
  auto stride = [&](const Footprint& fp) {
    return std::max({1, fp.width / 8, size / 256});  // at most 256 columns first
  };
  auto build = [&](int turn) {
    std::vector<Eigen::Vector2d> q = p;
    // A quarter turn (x, y) -> (-y, x) is exact in floating point.
    for (int t = 0; t < turn; ++t)
      for (Eigen::Vector2d& v : q) v = Eigen::Vector2d(-v.y(), v.x());
    footprint(q, chart.triangles, border, options.margin, reach, size, turned[turn]);
  };
  std::once_flag built[4];
  auto scanSlice = [&](int task) {
    const int turn = task % 4, slice = task / 4;  // turns first: footprints built at once
    std::call_once(built[turn], build, turn);
    const Footprint& fp = turned[turn];
    if (fp.width > size || fp.height > size) return;
    const int step = stride(fp), columns = (size - fp.width) / step + 1;
    // Lowest floor under the chart's middle first: a low spot found early lets most of the
    // others end at their first test. The order changes only how soon.
    std::vector<std::pair<int, int>> tries;
    for (int k = columns * slice / kSlicesPerTurn; k < columns * (slice + 1) / kSlicesPerTurn; ++k)
      tries.emplace_back(occupancy.floor(k * step + fp.width / 2), k);
    std::sort(tries.begin(), tries.end());
    for (const auto& [floor, k] : tries) tryAt(fp, turn, k * step, spots[turn][slice]);
  };
  // Around each turn's lowest spot in halving steps.
  auto refine = [&](int turn, Spot& local) {
    const Footprint& fp = turned[turn];
    if (fp.width > size || fp.height > size) return;
    const int last = size - fp.width;
    for (int step = stride(fp) / 2; step >= 1; step /= 2) {
      const int around = local.x;
      if (around - step >= 0) tryAt(fp, turn, around - step, local);
      if (around + step <= last) tryAt(fp, turn, around + step, local);
    }
  };
  Spot lowest[4];
  auto searchTurn = [&](int turn) {
    for (int slice = 0; slice < kSlicesPerTurn; ++slice)
      if (spots[turn][slice] < lowest[turn]) lowest[turn] = spots[turn][slice];
    refine(turn, lowest[turn]);
  };
  // Threads only pay for themselves on larger charts. A turn's footprint is built by the
  // first of its slices to start, and the turn refined by the last to end (each turn on its
  // own: refined one after another they were an eighth of the columns tested on one core, the
  // scans bench's 1.36M-face armadillo), in one start of threads per chart.
  std::atomic<int> slices_left[4];
  for (std::atomic<int>& left : slices_left) left = kSlicesPerTurn;
  const bool parallel = worthParallelSearch(p);
  runTasks(4 * kSlicesPerTurn, parallel, [&](int task) {
    scanSlice(task);
    if (slices_left[task % 4].fetch_sub(1) == 1) searchTurn(task % 4);
  });
  Spot best;
  for (int turn = 0; turn < 4; ++turn)
    if (lowest[turn] < best) best = lowest[turn];
  return best;
}

// The turn a chart is packed in: its smallest rectangle's. A chart too long for the texture
// along the rectangle's sides may fit across its diagonal: turned by 45 degrees (the footprint
// is its cells, not its rectangle, so the corners it leaves stay free for others).
Eigen::Matrix2d chartFrame(const Eigen::Matrix2d& box, const Eigen::Vector2d& extent, double scale,
                           int size) {
  return diagonalFits(extent, scale, size) ? Eigen::Matrix2d(rotationBy(kPi / 4) * box) : box;
}

std::vector<Eigen::Vector2d> framedPoints(const ChartShape& chart, const Eigen::Matrix2d& frame,
                                          double scale) {
  std::vector<Eigen::Vector2d> p(chart.uv.size());
  for (size_t i = 0; i < p.size(); ++i) p[i] = frame * chart.uv[i] * scale;
  return p;
}

// Packs every chart at `scale` into a strip as wide as the texture, each at a low free spot
// (lowest top, then lowest, then leftmost, of those searched over four quarter turns: every
// stride-th column, then a halving search around the best); returns the strip's used height,
// or INT_MAX when a chart is wider than the texture or, with `give_up_above`, as soon as the
// height passes it (the height only grows as charts are placed).
int packAt(const std::vector<ChartShape>& charts, const std::vector<Eigen::Matrix2d>& box,
           const std::vector<Eigen::Vector2d>& extent, const std::vector<Edges>& borders,
           const std::vector<int>& order, double scale, const PackOptions& options, int attempt,
           std::vector<Placement>& placements, int give_up_above = INT_MAX) {
  const int size = options.texture_size;
  const int reach = std::max(options.gutter - 1, 0);
  Occupancy occupancy(size);
  const int n = static_cast<int>(order.size());
  Footprint turned[4];  // the charts' in turn, their memory reused
  double total_weight = 0, placed_weight = 0;
  auto weight = [&](int c) { return std::sqrt(static_cast<double>(charts[c].uv.size())); };
  for (int c : order) total_weight += weight(c);
  for (int placed = 0; placed < n; ++placed) {
    const int c = order[placed];
    // A few calls per pack: enough for a progress bar to move during a long one.
    if (options.progress && placed % 16 == 0)
      options.progress(0.25 * placed_weight / std::max(total_weight, 1.0) +
                           0.75 * static_cast<double>(placed) / n,
                       attempt);
    placed_weight += weight(c);
    const Eigen::Matrix2d frame = chartFrame(box[c], extent[c], scale, size);
    const std::vector<Eigen::Vector2d> p = framedPoints(charts[c], frame, scale);
    const Spot best = lowestSpot(occupancy, charts[c], borders[c], p, options, reach, turned);
    const Footprint& chosen = turned[best.turn];
    if (best.top == INT_MAX) return INT_MAX;
    occupancy.occupy(chosen, best.x, best.y);
    if (occupancy.top() > give_up_above) return INT_MAX;
    placements[c].rotation = quarterTurn(best.turn) * frame;
    placements[c].offset = Eigen::Vector2d(best.x, best.y) - chosen.base;
  }
  return occupancy.top();
}

// Texture coordinates of all charts up to which the scale is searched finely (pack.cpp's
// largestFittingScale): the atlas bench's models (up to 86k faces) all are.
constexpr size_t kMostPointsForFinePacking = 200000;

// The cells the charts' footprints cover at `scale`, each in its packing frame (chartFrame),
// summed in chart order: the same on any number of cores.
double coveredCells(const std::vector<ChartShape>& charts, const std::vector<Eigen::Matrix2d>& box,
                    const std::vector<Eigen::Vector2d>& extent, const std::vector<Edges>& borders,
                    double scale, const PackOptions& options) {
  const int n = static_cast<int>(charts.size()), size = options.texture_size;
  std::vector<double> cells(n, 0.0);
  parallelForDynamic(n, 16, [&](int begin, int end, int) {
    Footprint fp;
    for (int c = begin; c < end; ++c) {
      const Eigen::Matrix2d frame = chartFrame(box[c], extent[c], scale, size);
      footprint(framedPoints(charts[c], frame, scale), charts[c].triangles, borders[c],
                options.margin, 0, size, fp);
      for (const auto& [low, high] : fp.cells.runs) cells[c] += high - low + 1;
    }
  });
  double total = 0;
  for (double c : cells) total += c;
  return total;
}

// Whether a try at packing the charts takes seconds (kMostPointsForFinePacking).
bool costlyToPack(const std::vector<ChartShape>& charts) {
  size_t points = 0;
  for (const ChartShape& chart : charts) points += chart.uv.size();
  return points > kMostPointsForFinePacking;
}

// The first try's scale for a costly pack (costlyToPack), refined from `aim`.
double aimedByCells(const std::vector<ChartShape>& charts, const std::vector<Eigen::Matrix2d>& box,
                    const std::vector<Eigen::Vector2d>& extent, const std::vector<Edges>& borders,
                    double aim, const PackOptions& options) {
  const int n = static_cast<int>(charts.size()), size = options.texture_size;
  // Where a try costs seconds the charts are thousands, and their cells (whole texels, the
  // chart's outline rounded out) are far more than their area: aimed by area the first try
  // missed the band kept (largestFittingScale) on every mesh of the scans bench, and a second
  // pack of 2-25 s followed. It is aimed by cells instead. The packer fills its strip the
  // denser the smaller the charts, which fill the gaps between larger ones: the placed cells
  // filled 65.4% of the used strip at 102k cells a chart (fertility x64), 65.9-66.7% at 35k
  // (armadillo x16), 69.5% at 10.5k (armadillo x64) and 74.1% at 4.5k (cheburashka x1024),
  // about 0.631 + 7.39 / sqrt(cells a chart); the try aims at 98% of that.
  auto fill = [n](double cells) {
    return std::min(0.9, 0.98 * (0.631 + 7.39 / std::sqrt(cells / n)));
  };
  for (int step = 0; step < 3; ++step) {
    const double cells = std::max(coveredCells(charts, box, extent, borders, aim, options), 1.0);
    aim *= std::sqrt(fill(cells) * size * size / cells);
  }
  return aim;
}

// Finds the largest scale at which the charts, dropped in `order`, fit the texture, and their
// places there; `aim` is a scale to try first, and with `must_beat` the search stops when the
// charts do not fit at it. Returns 0 when nothing fit.
double largestFittingScale(const std::vector<ChartShape>& charts,
                           const std::vector<Eigen::Matrix2d>& box,
                           const std::vector<Eigen::Vector2d>& extent,
                           const std::vector<Edges>& borders, const std::vector<int>& order,
                           double aim, bool must_beat, const PackOptions& options,
                           std::vector<Placement>& placements, int& attempts) {
  const int size = options.texture_size;
  // Packed into a strip as wide as the texture, the used height grows about as the scale: each
  // try aims at the height of the texture from the last, between the largest scale that fit and
  // the smallest that did not.
  // A fit that fills all but `full_enough` of the height is kept: the next try would aim a
  // little higher and cost a whole pack (seconds at a million faces; 8 more tries were seen, for
  // 0.2%). Where packs are cheap (kMostPointsForFinePacking) the band is narrow and each try
  // aims at its top. Where they are costly it is wider and each try aims at its middle: the
  // height of a pack varies by about 1% from one scale to a nearby one, so a try aimed at the
  // very top overflowed as often as not and a third was needed (the scans bench's armadillo
  // x16: 3 packs, 16.3 s; 2, 9.1 s, for 0.6% of the texels).
  const bool costly = costlyToPack(charts);
  const double full_enough = costly ? 0.03 : 0.02;
  const double aimed_height = costly ? 1 - 0.5 * full_enough : 0.998 * 0.998;
  std::vector<Placement> trial(charts.size());
  double fits = 0, fails = std::numeric_limits<double>::infinity(), scale = aim;
  // Until a scale fits, tries go on (up to kMostTriesToFit), each from the last two heights:
  // many small charts are held apart by their gutters, so the height falls far more slowly than
  // the scale squared, and tries aimed by the square crept down (1025 separate triangles in a
  // 128-texel texture were refused after ten tries, though they fit at a fifth of the scale).
  constexpr int kMostTries = 10, kMostTriesToFit = 40;
  double last_scale = 0, last_height = 0;
  for (int attempt = 0; attempt < (fits > 0 ? kMostTries : kMostTriesToFit) && fails > 1.005 * fits;
       ++attempt) {
    // A try that must beat an earlier order and has not yet fit ends the search when it fails,
    // whatever its height: it stops as soon as it overflows (same result, a fraction of the work;
    // most such tries fail).
    const int give_up_above = must_beat && fits == 0 ? size : INT_MAX;
    const int height = packAt(charts, box, extent, borders, order, scale, options, attempts++,
                              trial, give_up_above);
    if (height <= size) {
      fits = scale;
      placements = trial;
      if (height >= (1 - full_enough) * size) break;
    } else {
      fails = scale;
      if (must_beat && fits == 0) return 0;
    }
    double next = height == INT_MAX ? 0.5 * scale : scale * std::sqrt(aimed_height * size / height);
    if (fits == 0 && height != INT_MAX && last_height > size && last_scale > scale) {
      if (height >= last_height && last_scale > 1.05 * scale) {
        // No lower at a clearly smaller scale: the footprints are texels and gutters. (At
        // nearby scales the height's ups and downs of a few percent decide it: halving there
        // cost a turbine blade's atlas eight more packs.)
        next = 0.5 * scale;
      } else if (last_scale > 1.05 * scale) {
        // The height's growth with the scale, over tries far enough apart that the height's
        // ups and downs of about 1% do not decide it; below linear the gutters dominate.
        const double growth = std::log(last_height / height) / std::log(last_scale / scale);
        if (growth < 1) next = scale * std::pow(aimed_height * size / height, 1 / growth);
      }
    }
    if (!(next > fits && next < fails))
      next = std::isfinite(fails) ? 0.5 * (fits + fails) : 1.05 * scale;
    last_scale = scale;
    last_height = height == INT_MAX ? 0 : height;
    scale = next;
  }
  return fits;
}

}  // namespace

double uvArea(const std::vector<Eigen::Vector2d>& uv,
              const std::vector<std::array<int, 3>>& triangles) {
  double area = 0;
  for (const auto& t : triangles) area += 0.5 * std::abs(cross(uv[t[0]], uv[t[1]], uv[t[2]]));
  return area;
}

Packing packCharts(const std::vector<ChartShape>& charts, const PackOptions& options) {
  Packing packing;
  const int n = static_cast<int>(charts.size());
  packing.placements.resize(n);
  if (n == 0) return packing;
  std::vector<Eigen::Matrix2d> box(n);
  std::vector<Edges> borders(n);
  std::vector<Eigen::Vector2d> extent(n);
  std::vector<double> area(n, 0.0);
  double total = 0, longest = 0;
  parallelForDynamic(n, 16, [&](int begin, int end, int) {
    for (int c = begin; c < end; ++c) {
      box[c] = smallestBoxRotation(charts[c].uv);
      borders[c] = borderEdges(charts[c].triangles);
      extent[c] = boundsOf(charts[c].uv, box[c]).extent();
      area[c] = uvArea(charts[c].uv, charts[c].triangles);
    }
  });
  for (int c = 0; c < n; ++c) {  // in chart order: the same sum on any number of cores
    total += area[c];
    longest = std::max(longest, neededLength(extent[c]));
  }
  const int size = options.texture_size;
  // At `full` the charts' area would fill the square exactly: no packing does better.
  const double full =
      size / std::sqrt(std::max(total, std::numeric_limits<double>::min())) * options.shrink;
  // The first try aims at filling 0.85^2 = 72% of the texture with the charts' area.
  double aim = 0.85 * full;
  if (costlyToPack(charts)) aim = aimedByCells(charts, box, extent, borders, aim, options);
  // No chart can be longer than the texture: the first try is below that, not found by halving.
  if (longest > 0 && aim * longest > size - 2) aim = (size - 2) / longest;

  // A greedy packer's result turns on the order the charts come in: four orders, largest first
  // by area, by long side, by short side and by bounding rectangle, each kept only when it packs
  // at a larger scale than the best so far (one try each when it does not). Ties by index, so the
  // same order on every run. Above kMostChartsForOrders charts, where a try is long and many
  // small charts fill the gaps whatever the order, by area only.
  constexpr int kMostChartsForOrders = 50;
  const int orders = n <= kMostChartsForOrders ? 4 : 1;
  std::vector<Placement> trial(n);
  double fits = 0;
  for (int kind = 0; kind < orders; ++kind) {
    std::vector<double> key(n);
    for (int c = 0; c < n; ++c)
      key[c] = kind == 0   ? area[c]
               : kind == 1 ? extent[c].maxCoeff()
               : kind == 2 ? extent[c].minCoeff()
                           : extent[c].prod();
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] > key[b]; });
    const double scale =
        largestFittingScale(charts, box, extent, borders, order, kind == 0 ? aim : 1.005 * fits,
                            kind > 0, options, trial, packing.attempts);
    if (scale > fits) {
      fits = scale;
      packing.placements = trial;
    }
  }
  if (fits == 0)
    throw ParameterizationError(std::to_string(n) + " charts do not fit a " + std::to_string(size) +
                                " texel texture with a " + std::to_string(options.gutter) +
                                " texel gutter");
  packing.texels_per_unit = fits;
  footprintScratch() = FootprintScratch{};  // the caller's thread (MeshLab's) keeps no megabytes
  return packing;
}

}  // namespace sdp::atlas
