#include "border.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

#include "geometry.h"
#include "parallel.h"

namespace sdp {

std::vector<BorderEdge> boundaryEdges(const Patch& patch) {
  std::vector<BorderEdge> edges;
  for (int f = 0; f < patch.real_face_count; ++f)
    for (int c = 0; c < 3; ++c) {
      const int across = patch.face_across[f][c];
      if (across < 0 || across >= patch.real_face_count)
        edges.push_back({patch.face[f][c], patch.face[f][(c + 1) % 3]});
    }
  return edges;
}

namespace {

using Edge = BorderEdge;

double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return cross2(b - a, c - a);
}

bool within(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

// Closed segments ab and cd share a point (touching counts: it is not a simple boundary).
bool segmentsMeet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                  const Eigen::Vector2d& d) {
  const double d1 = orient(a, b, c), d2 = orient(a, b, d), d3 = orient(c, d, a),
               d4 = orient(c, d, b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  return (d1 == 0 && within(a, b, c)) || (d2 == 0 && within(a, b, d)) ||
         (d3 == 0 && within(c, d, a)) || (d4 == 0 && within(c, d, b));
}

// Distance from p to the closed segment ab.
double pointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Calls meet(e, g, slot) for pairs of the edges that cross or touch (or come closer than
// `clearance` > 0), apart from neighbours at their shared vertex, until one call returns false:
// a sweep along x, each edge tested against the later edges whose x range starts before its own
// ends, grown by the clearance (a boundary curve meets few of them). Those whose y ranges, so
// grown, do not overlap are passed over from the edges' boxes, read in sweep order: a whole
// atlas's border (a million edges at millions of faces) meets hundreds in x per edge, each test
// reading its four corners from anywhere in memory. The sweep runs in slots of consecutive edges
// on every core (slot < the number of slots, for the caller's per-slot lists); the pairs found
// do not depend on how edges of equal x are ordered, nor on the slots.
template <class Meet>
void forMeetingEdges(std::vector<BorderEdge> edges, const LocalUVs& uv, double clearance,
                     Meet&& meet, int slots) {
  const int n = static_cast<int>(edges.size());
  std::vector<std::pair<double, int>> order(n);
  parallelFor(n, 16384, [&](int first, int last, int) {
    for (int i = first; i < last; ++i)
      order[i] = {std::min(uv[edges[i][0]].x(), uv[edges[i][1]].x()), i};
  });
  sortOnTwoCores(order);  // the keys are distinct
  struct Box {
    double low_x, high_x, low_y, high_y;
  };
  std::vector<Box> box(n);
  std::vector<BorderEdge> sorted(n);
  parallelFor(n, 16384, [&](int first, int last, int) {
    for (int i = first; i < last; ++i) {
      sorted[i] = edges[order[i].second];
      const Eigen::Vector2d &a = uv[sorted[i][0]], &b = uv[sorted[i][1]];
      box[i] = {std::min(a.x(), b.x()), std::max(a.x(), b.x()), std::min(a.y(), b.y()),
                std::max(a.y(), b.y())};
    }
  });
  edges = std::vector<BorderEdge>();
  std::atomic<bool> stop{false};
  auto sweep = [&](int first_slot, int last_slot, int) {
    for (int slot = first_slot; slot < last_slot; ++slot) {
      const int begin = static_cast<int>(static_cast<long long>(n) * slot / slots);
      const int end = static_cast<int>(static_cast<long long>(n) * (slot + 1) / slots);
      for (int i = begin; i < end && !stop.load(std::memory_order_relaxed); ++i) {
        const Edge& e = sorted[i];
        const double high = box[i].high_x + clearance;
        const double below = box[i].low_y - clearance, above = box[i].high_y + clearance;
        for (int j = i + 1; j < n && box[j].low_x <= high; ++j) {
          if (box[j].low_y > above || box[j].high_y < below) continue;
          const Edge& g = sorted[j];
          if (e[0] == g[0] || e[0] == g[1] || e[1] == g[0] || e[1] == g[1]) continue;
          const Eigen::Vector2d &a = uv[e[0]], &b = uv[e[1]], &c = uv[g[0]], &d = uv[g[1]];
          const bool close =
              segmentsMeet(a, b, c, d) ||
              (clearance > 0 &&
               std::min({pointSegmentDistance(a, c, d), pointSegmentDistance(b, c, d),
                         pointSegmentDistance(c, a, b), pointSegmentDistance(d, a, b)}) <
                   clearance);
          if (close && !meet(e, g, slot)) {
            stop.store(true, std::memory_order_relaxed);
            return;
          }
        }
      }
    }
  };
  if (slots > 1)
    parallelForDynamic(slots, 1, sweep);
  else
    sweep(0, 1, 0);  // a chart's border: no threads started
}

// Slots of the border sweep: one per 16384 edges.
int sweepSlots(const std::vector<BorderEdge>& edges) {
  return faceSumSlots(static_cast<int>(edges.size()));
}

}  // namespace

bool edgesAreSimple(std::vector<BorderEdge> edges, const LocalUVs& uv, double clearance) {
  std::atomic<bool> simple{true};
  const int slots = sweepSlots(edges);
  forMeetingEdges(
      std::move(edges), uv, clearance,
      [&](const Edge&, const Edge&, int) {
        simple.store(false);
        return false;
      },
      slots);
  return simple.load();
}

std::vector<int> verticesOfMeetingEdges(std::vector<BorderEdge> edges, const LocalUVs& uv) {
  const int slots = sweepSlots(edges);
  std::vector<std::vector<int>> found(slots);
  forMeetingEdges(
      std::move(edges), uv, 0,
      [&](const Edge& e, const Edge& g, int slot) {
        found[slot].insert(found[slot].end(), {e[0], e[1], g[0], g[1]});
        return true;
      },
      slots);
  std::vector<int> vertices = joinedInOrder(found);
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

double borderClearance(const std::vector<BorderEdge>& edges, const LocalUVs& uv) {
  Eigen::Vector2d lowest = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d highest = -lowest;
  for (const Edge& e : edges)
    for (int v : e) lowest = lowest.cwiseMin(uv[v]), highest = highest.cwiseMax(uv[v]);
  return edges.empty() ? 0.0 : kBorderClearance * (highest - lowest).norm();
}

bool boundaryIsSimple(const Patch& patch, const LocalUVs& uv) {
  return edgesAreSimple(boundaryEdges(patch), uv);
}

}  // namespace sdp
