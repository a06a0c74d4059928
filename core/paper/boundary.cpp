#include "boundary.h"

#include "core/common/border.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

#include "core/common/geometry.h"
#include "core/common/metrics.h"
#include "straightest.h"
#include "weights.h"

namespace sdp {
namespace {

// 3D lengths of the boundary edges b_k -> b_{k+1}, floored so that a zero-length edge cannot
// put two boundary vertices on one point.
std::vector<double> boundarySpacing(const Patch& patch) {
  const auto& loop = patch.boundary_loop;
  const int n = static_cast<int>(loop.size());
  std::vector<double> length(n);
  for (int k = 0; k < n; ++k)
    length[k] = (patch.position[loop[(k + 1) % n]] - patch.position[loop[k]]).norm();
  const double mean = std::accumulate(length.begin(), length.end(), 0.0) / n;
  const double floor = mean > 0 ? 1e-3 * mean : 1.0;
  for (double& l : length) l = std::max(l, floor);
  return length;
}

// Turn angle at b between a -> b and b -> c (positive: left turn).
double turnAngle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  const Eigen::Vector2d u = b - a, v = c - b;
  return std::atan2(cross2(u, v), u.dot(v));
}

// Angles that sum to 2 pi with no gap above `cap`: the excess of capped gaps is spread over the
// others in proportion (a gap of pi or more would leave S outside the polygon).
std::vector<double> cappedGaps(std::vector<double> gap, double cap) {
  const int n = static_cast<int>(gap.size());
  std::vector<char> capped(n, 0);
  for (int round = 0; round < n; ++round) {
    double free_sum = 0, capped_sum = 0;
    for (int k = 0; k < n; ++k) (capped[k] ? capped_sum : free_sum) += gap[k];
    const double scale = (2 * kPi - capped_sum) / free_sum;
    bool changed = false;
    for (int k = 0; k < n; ++k) {
      if (capped[k]) continue;
      gap[k] *= scale;
      if (gap[k] > cap) gap[k] = cap, capped[k] = 1, changed = true;
    }
    if (!changed) break;
  }
  return gap;
}

}  // namespace

double earStretch(const Patch& patch, const Polygon& polygon) {
  const auto& loop = patch.boundary_loop;
  std::vector<int> position(patch.vertexCount(), -1);
  for (size_t k = 0; k < loop.size(); ++k) position[loop[k]] = static_cast<int>(k);
  const double mesh_area = patchArea3d(patch);
  const double scale = std::sqrt(mesh_area / std::abs(polygonArea(polygon)));
  double weighted = 0, area = 0;
  for (int f = 0; f < patch.real_face_count; ++f) {
    const auto& t = patch.face[f];
    if (position[t[0]] < 0 || position[t[1]] < 0 || position[t[2]] < 0) continue;
    const Eigen::Vector3d q[3] = {patch.position[t[0]], patch.position[t[1]], patch.position[t[2]]};
    const Eigen::Vector2d p[3] = {scale * polygon[position[t[0]]], scale * polygon[position[t[1]]],
                                  scale * polygon[position[t[2]]]};
    const FaceStretch s = faceStretch(q, p);
    weighted += s.l2 * s.l2 * s.area3d;
    area += s.area3d;
  }
  return area > 0 ? std::sqrt(weighted / area) : 0.0;
}

double polygonArea(const Polygon& polygon) {
  double twice = 0;
  const size_t n = polygon.size();
  for (size_t k = 0; k < n; ++k) twice += cross2(polygon[k], polygon[(k + 1) % n]);
  return 0.5 * twice;
}

Polygon circleBoundary(const Patch& patch) {
  const std::vector<double> length = boundarySpacing(patch);
  const double total = std::accumulate(length.begin(), length.end(), 0.0);
  Polygon circle(length.size());
  double run = 0;
  for (size_t k = 0; k < length.size(); ++k) {
    const double phi = 2 * kPi * run / total;
    circle[k] = {std::cos(phi), std::sin(phi)};
    run += length[k];
  }
  return circle;
}

Polygon squareBoundary(const Patch& patch) {
  const std::vector<double> length = boundarySpacing(patch);
  const int n = static_cast<int>(length.size());
  if (n < 4) return {};
  std::vector<double> arc(n + 1, 0.0);
  for (int k = 0; k < n; ++k) arc[k + 1] = arc[k] + length[k];
  const double total = arc[n];
  // Corner q sits at the vertex nearest to q/4 of the perimeter, strictly after corner q-1 and
  // leaving room for the corners still to come.
  int corner[5];
  corner[0] = 0;
  for (int q = 1; q < 4; ++q) {
    const double target = total * q / 4;
    int best = corner[q - 1] + 1;
    for (int k = best; k <= n - (4 - q); ++k)
      if (std::abs(arc[k] - target) < std::abs(arc[best] - target)) best = k;
    corner[q] = best;
  }
  corner[4] = n;
  const Eigen::Vector2d square[5] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
  Polygon result(n);
  for (int q = 0; q < 4; ++q) {
    const double side = arc[corner[q + 1]] - arc[corner[q]];
    for (int k = corner[q]; k < corner[q + 1]; ++k) {
      const double t = (arc[k] - arc[corner[q]]) / side;
      result[k] = (1 - t) * square[q] + t * square[q + 1];
    }
  }
  return result;
}

namespace {

// Min-heap of vertices keyed by tentative distance, with decrease-key: each vertex is in it at
// most once (a lazy std::priority_queue holds every improvement, about twice as many entries,
// and its pops were a tenth of the whole run at 414k vertices). Four children per node: fewer
// levels, and the children sit in one cache line.
class VertexHeap {
 public:
  explicit VertexHeap(int vertices) : slot_(vertices, -1) {}
  bool empty() const { return heap_.empty(); }
  // Inserts v or lowers its key.
  void push(int v, double key) {
    int at = slot_[v];
    if (at < 0) {
      at = static_cast<int>(heap_.size());
      heap_.push_back({key, v});
    } else {
      heap_[at].key = key;
    }
    siftUp(at);
  }
  int pop() {
    const int top = heap_.front().vertex;
    slot_[top] = -2;  // settled
    const Node last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) {
      heap_.front() = last;
      slot_[last.vertex] = 0;
      siftDown(0);
    }
    return top;
  }

 private:
  struct Node {
    double key;
    int vertex;
  };
  void place(int at, const Node& node) {
    heap_[at] = node;
    slot_[node.vertex] = at;
  }
  void siftUp(int at) {
    const Node node = heap_[at];
    while (at > 0) {
      const int parent = (at - 1) / 4;
      if (!(node.key < heap_[parent].key)) break;
      place(at, heap_[parent]);
      at = parent;
    }
    place(at, node);
  }
  void siftDown(int at) {
    const Node node = heap_[at];
    const int size = static_cast<int>(heap_.size());
    while (true) {
      const int first = 4 * at + 1;
      if (first >= size) break;
      int best = first;
      for (int c = first + 1; c < std::min(first + 4, size); ++c)
        if (heap_[c].key < heap_[best].key) best = c;
      if (!(heap_[best].key < node.key)) break;
      place(at, heap_[best]);
      at = best;
    }
    place(at, node);
  }
  std::vector<Node> heap_;
  std::vector<int> slot_;  // heap position, -1 never queued, -2 settled
};

}  // namespace

std::vector<double> edgeGraphDistances(const Patch& patch, const std::vector<int>& sources) {
  std::vector<double> dist(patch.vertexCount(), std::numeric_limits<double>::infinity());
  VertexHeap heap(patch.vertexCount());
  for (int s : sources) {
    dist[s] = 0;
    heap.push(s, 0.0);
  }
  while (!heap.empty()) {
    const int v = heap.pop();
    const double d = dist[v];
    const Eigen::Vector3d& p = patch.position[v];
    for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) {
      const int w = patch.ring_vertex[k];
      const double nd = d + (patch.position[w] - p).norm();
      if (nd < dist[w]) {
        dist[w] = nd;
        heap.push(w, nd);
      }
    }
  }
  return dist;
}

int chooseSourceVertex(const Patch& patch, SourceRule rule) {
  const int n = patch.vertexCount();
  int best = -1;
  if (rule == SourceRule::FarthestFromBoundary) {
    const std::vector<double> dist = edgeGraphDistances(patch, patch.boundary_loop);
    for (int v = 0; v < n; ++v)
      if (!patch.on_boundary[v] && !patch.isVirtual(v) && (best < 0 || dist[v] > dist[best]))
        best = v;
  } else {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int b : patch.boundary_loop) centroid += patch.position[b];
    centroid /= static_cast<double>(patch.boundary_loop.size());
    double best_d = 0;
    for (int v = 0; v < n; ++v) {
      if (patch.on_boundary[v] || patch.isVirtual(v)) continue;
      const double d = (patch.position[v] - centroid).squaredNorm();
      if (best < 0 || d < best_d) best = v, best_d = d;
    }
  }
  return best;
}

double planeWalkDistance(const Patch& patch, int source, const Eigen::Vector3d& normal, int b) {
  const auto& P = patch.position;
  const Eigen::Vector3d S = P[source], B = P[b];
  const Eigen::Vector3d e = B - S;
  Eigen::Vector3d t = e - e.dot(normal) * normal;
  if (!(t.norm() > 1e-12 * e.norm())) return -1;
  t.normalize();
  const Eigen::Vector3d plane_normal = t.cross(normal).normalized();
  auto height = [&](int v) { return plane_normal.dot(P[v] - S); };
  // Symbolic perturbation: a vertex exactly on the plane counts as above it, so the walk
  // always crosses edges, never runs through vertices.
  auto above = [&](int v) { return height(v) >= 0; };
  auto crossing = [&](int u, int w) {
    const double hu = height(u), hw = height(w);
    return Eigen::Vector3d(P[u] + hu / (hu - hw) * (P[w] - P[u]));
  };

  // The plane leaves S's ring through (usually) two edges. The one towards b comes first; on a
  // curved patch its half of the plane curve can meet the boundary elsewhere while the other
  // half reaches b, so every start is tried, best aligned first.
  struct Start {
    double cosine;
    int face, u, w;
    Eigen::Vector3d x;
  };
  std::vector<Start> starts;
  for (int k = patch.ring_begin[source]; k < patch.ring_begin[source + 1]; ++k) {
    const int f = patch.ring_face[k];
    if (f < 0) continue;
    const int a = patch.ring_vertex[k];
    const int c =
        patch.ring_vertex[k + 1 < patch.ring_begin[source + 1] ? k + 1 : patch.ring_begin[source]];
    if (above(a) == above(c)) continue;
    const Eigen::Vector3d y = crossing(a, c);
    const double len = (y - S).norm();
    if (!(len > 0)) continue;
    starts.push_back({(y - S).dot(t) / len, f, a, c, y});
  }
  std::sort(starts.begin(), starts.end(),
            [](const Start& p, const Start& q) { return p.cosine > q.cosine; });
  for (const Start& start : starts) {
    int face = start.face, u = start.u, w = start.w;
    Eigen::Vector3d x = start.x;
    double length = (x - S).norm();
    for (int step = 0; step <= patch.faceCount(); ++step) {
      if (u == b || w == b) return length + (B - x).norm();  // the plane contains b: arrived
      const auto& tri = patch.face[face];
      int slot = 0;
      while (!((tri[slot] == u && tri[(slot + 1) % 3] == w) ||
               (tri[slot] == w && tri[(slot + 1) % 3] == u)))
        ++slot;
      const int next = patch.face_across[face][slot];
      if (next < 0) break;  // left the patch elsewhere than at b
      // Back in the first face: the plane's curve is a closed loop (around an arm or a handle of
      // the patch) that misses b; the walk is reversible, so it would only go round again.
      if (next == start.face) break;
      const auto& nt = patch.face[next];
      const int z = nt[0] != u && nt[0] != w ? nt[0] : (nt[1] != u && nt[1] != w ? nt[1] : nt[2]);
      if (above(z) == above(u))
        u = z;
      else
        w = z;
      const Eigen::Vector3d y = crossing(u, w);
      length += (y - x).norm();
      x = y;
      face = next;
    }
  }
  return -1;
}

std::vector<std::pair<int, int>> dividingEdges(const Patch& patch) {
  const auto& loop = patch.boundary_loop;
  const int n = static_cast<int>(loop.size());
  std::vector<int> position(patch.vertexCount(), -1);
  for (int k = 0; k < n; ++k) position[loop[k]] = k;
  std::vector<std::pair<int, int>> edges;
  for (int k = 0; k < n; ++k) {
    const int v = loop[k];
    for (int r = patch.ring_begin[v]; r < patch.ring_begin[v + 1]; ++r) {
      const int m = position[patch.ring_vertex[r]];
      if (m > k && m != k + 1 && !(k == 0 && m == n - 1)) edges.emplace_back(k, m);
    }
  }
  return edges;
}

namespace {

// The convex hull's vertices (Andrew's monotone chain; collinear points are not hull vertices),
// in polygon order: for a simple polygon this is also the hull's order.
std::vector<int> hullCorners(const Polygon& polygon) {
  const int n = static_cast<int>(polygon.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return polygon[a].x() != polygon[b].x() ? polygon[a].x() < polygon[b].x()
                                            : polygon[a].y() < polygon[b].y();
  });
  std::vector<int> hull;
  for (int pass = 0; pass < 2; ++pass) {
    const size_t base = hull.size();
    for (int i = 0; i < n; ++i) {
      const int k = pass == 0 ? order[i] : order[n - 1 - i];
      while (hull.size() >= base + 2 &&
             cross2(polygon[hull[hull.size() - 1]] - polygon[hull[hull.size() - 2]],
                    polygon[k] - polygon[hull[hull.size() - 1]]) <= 0)
        hull.pop_back();
      hull.push_back(k);
    }
    hull.pop_back();
  }
  std::vector<char> on_hull(n, 0);
  for (int k : hull) on_hull[k] = 1;
  std::vector<int> corners;
  for (int k = 0; k < n; ++k)
    if (on_hull[k]) corners.push_back(k);
  return corners;
}

// Corners that barely turn (rounding noise on a straight side) would get a bulge too small to
// survive rounding: they become side points (dropping a corner keeps the hull convex). `turn`
// gets the kept corners' turns. False when fewer than 3 corners stay or a corner turns the wrong
// way (the input was not a simple star-shaped polygon).
bool dropFlatCorners(const Polygon& polygon, std::vector<int>& corners, std::vector<double>& turn) {
  constexpr double kMinTurn = 1e-6;
  for (bool dropped = true; dropped;) {
    dropped = false;
    const int m = static_cast<int>(corners.size());
    if (m < 3) return false;
    turn.assign(m, 0);
    for (int c = 0; c < m; ++c) {
      turn[c] = turnAngle(polygon[corners[(c + m - 1) % m]], polygon[corners[c]],
                          polygon[corners[(c + 1) % m]]);
      if (!(turn[c] > -kMinTurn)) return false;
    }
    for (int c = 0; c < m; ++c)
      if (turn[c] < kMinTurn) {
        corners.erase(corners.begin() + c);
        dropped = true;
        break;
      }
  }
  return true;
}

// Side c runs from corners[c] to corners[c+1]; a dividing edge with both ends on one side
// (corners included) asks that side for room.
std::vector<char> sidesNeedingRoom(int n, const std::vector<int>& corners,
                                   const std::vector<std::pair<int, int>>& dividing_edges) {
  const int m = static_cast<int>(corners.size());
  std::vector<int> side_of(n);
  for (int c = 0; c < m; ++c)
    for (int k = corners[c]; k != corners[(c + 1) % m]; k = (k + 1) % n) side_of[k] = c;
  std::vector<char> is_corner(n, 0);
  for (int k : corners) is_corner[k] = 1;
  std::vector<char> needs_room(m, 0);
  auto onSide = [&](int k, int c) {
    return side_of[k] == c || (is_corner[k] && side_of[k] == (c + 1) % m);
  };
  for (const auto& [a, b] : dividing_edges) {
    const int sa = side_of[a];
    if (onSide(b, sa)) needs_room[sa] = 1;
    if (is_corner[a]) {  // a corner also ends the previous side
      const int prev = (sa + m - 1) % m;
      if (onSide(b, prev)) needs_room[prev] = 1;
    }
  }
  return needs_room;
}

}  // namespace

Polygon makeStrictlyConvex(const Polygon& polygon, const std::vector<double>& spacing,
                           const std::vector<std::pair<int, int>>& dividing_edges) {
  const int n = static_cast<int>(polygon.size());
  std::vector<int> corners = hullCorners(polygon);
  std::vector<double> turn;
  if (!dropFlatCorners(polygon, corners, turn)) return {};
  const int m = static_cast<int>(corners.size());
  const std::vector<char> needs_room = sidesNeedingRoom(n, corners, dividing_edges);
  Polygon result(polygon);
  for (int c = 0; c < m; ++c) {
    const int from = corners[c], to = corners[(c + 1) % m];
    const Eigen::Vector2d A = polygon[from], B = polygon[to];
    const Eigen::Vector2d ab = B - A;
    const double L = ab.norm();
    const Eigen::Vector2d outward(ab.y() / L, -ab.x() / L);
    // A parabolic bulge of height eps * L: its end tangents turn by atan(4 eps), kept below a
    // third of the hull's turn at either end so the corners stay strictly convex. Tiny where it
    // only has to make a straight run strictly convex (a planar patch stays isometric), larger
    // where a dividing edge would otherwise flatten triangles on this side.
    const double cap = needs_room[c] ? 0.05 : 1e-4;
    const double eps = std::min(cap, std::tan(std::min(turn[c], turn[(c + 1) % m]) / 3) / 4);
    double total = 0;
    for (int k = from; k != to; k = (k + 1) % n) total += spacing[k];
    double run = spacing[from];
    for (int k = (from + 1) % n; k != to; k = (k + 1) % n) {
      const double t = run / total;
      result[k] = A + t * ab + eps * L * 4 * t * (1 - t) * outward;
      run += spacing[k];
    }
  }
  return result;
}

namespace {

// An ear apex b (a boundary vertex of one face, a-b-c) has no interior neighbour: the linear
// solve never sees it, so it need not lie on the convex polygon. The convex polygon is made over
// the other boundary vertices (the ear's chord a-c becomes one of its sides, so the rest of the
// map stays one-to-one by Tutte/Floater) and b goes across the chord, outside, with the ear's
// own 3D shape. Ears that would overlap one another are flattened towards their chords, halving
// their height; if that does not help, no ear is unfolded.
Polygon convexWithUnfoldedEars(const Patch& patch, const Polygon& polar, MeasuredCounts& counts) {
  const auto& loop = patch.boundary_loop;
  const int n = static_cast<int>(loop.size());
  const std::vector<double> spacing = boundarySpacing(patch);
  auto withoutUnfolding = [&] { return makeStrictlyConvex(polar, spacing, dividingEdges(patch)); };
  std::vector<char> apex(n, 0);
  int apexes = 0;
  for (int k = 0; k < n; ++k) {
    const int v = loop[k];
    const bool ear = patch.ringSize(v) == 2 && patch.ring_face[patch.ring_begin[v]] >= 0 &&
                     patch.ring_face[patch.ring_begin[v]] < patch.real_face_count;
    // Never two neighbours (a chord must join kept vertices), and keep at least 3.
    if (ear && !apex[(k + n - 1) % n] && !(k == n - 1 && apex[0]) && n - apexes > 3) {
      apex[k] = 1;
      ++apexes;
    }
  }
  if (apexes == 0) return withoutUnfolding();

  std::vector<int> kept_of(n, -1), kept;
  for (int k = 0; k < n; ++k)
    if (!apex[k]) {
      kept_of[k] = static_cast<int>(kept.size());
      kept.push_back(k);
    }
  const int m = static_cast<int>(kept.size());
  Polygon sub(m);
  std::vector<double> sub_spacing(m, 0);
  for (int i = 0; i < m; ++i) {
    sub[i] = polar[kept[i]];
    for (int k = kept[i]; k != kept[(i + 1) % m]; k = (k + 1) % n) sub_spacing[i] += spacing[k];
  }
  std::vector<std::pair<int, int>> sub_dividing;
  for (const auto& [a, b] : dividingEdges(patch)) {
    const int i = kept_of[a], j = kept_of[b];
    if (i < 0 || j < 0) continue;
    const bool chord = (j - i == 1) || (i == 0 && j == m - 1);  // an ear's chord: now a side
    if (!chord) sub_dividing.emplace_back(std::min(i, j), std::max(i, j));
  }
  const Polygon convex = makeStrictlyConvex(sub, sub_spacing, sub_dividing);
  if (convex.empty()) return {};

  Polygon full(n);
  for (int i = 0; i < m; ++i) full[kept[i]] = convex[i];
  std::vector<BorderEdge> edges(n);
  for (int k = 0; k < n; ++k) edges[k] = {k, (k + 1) % n};
  for (double height = 1; height > 1.0 / 64; height /= 2) {
    for (int k = 0; k < n; ++k) {
      if (!apex[k]) continue;
      const int a = (k + n - 1) % n, c = (k + 1) % n;
      const Eigen::Vector3d A = patch.position[loop[a]], B = patch.position[loop[k]],
                            C = patch.position[loop[c]];
      const Eigen::Vector3d chord3 = C - A;
      const double length3 = chord3.norm();
      const Eigen::Vector2d chord2 = full[c] - full[a];
      const double length2 = chord2.norm();
      if (!(length3 > 0) || !(length2 > 0)) return withoutUnfolding();
      const double along = (B - A).dot(chord3) / (length3 * length3);
      const double across = (B - A).cross(chord3).norm() / length3 * (length2 / length3);
      // Outside a counter-clockwise polygon: to the right of a -> c.
      const Eigen::Vector2d outward(chord2.y() / length2, -chord2.x() / length2);
      full[k] = full[a] + along * chord2 + height * across * outward;
    }
    if (edgesAreSimple(edges, full)) {
      counts.ears_unfolded = apexes;
      return full;
    }
  }
  return withoutUnfolding();
}

}  // namespace

Polygon measuredBoundary(const Patch& patch, int source, MeasuredCounts& counts) {
  const auto& loop = patch.boundary_loop;
  const int n = static_cast<int>(loop.size());
  Ring ring;
  gatherRing(patch, source, ring);
  const Eigen::Vector3d normal = baseNormal(ring);
  const Eigen::Vector3d S = patch.position[source];

  // Polar angles: the 3D angle between consecutive virtual edges, scaled to sum to 2 pi.
  std::vector<double> gap(n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d a = patch.position[loop[k]] - S;
    const Eigen::Vector3d b = patch.position[loop[(k + 1) % n]] - S;
    gap[k] = std::max(std::atan2(a.cross(b).norm(), a.dot(b)), 1e-9);
  }
  gap = cappedGaps(gap, 2 * kPi / 3);

  // Radii: straightest distances, with the edge-graph distance as fallback and sanity bound.
  const std::vector<double> graph = edgeGraphDistances(patch, {source});
  std::vector<double> radius(n);
  for (int k = 0; k < n; ++k) {
    const double walked =
        normal.squaredNorm() > 0 ? planeWalkDistance(patch, source, normal, loop[k]) : -1;
    if (walked <= 0) {
      ++counts.walk_failures;
      radius[k] = graph[loop[k]];
    } else if (walked > 1.5 * graph[loop[k]]) {
      ++counts.walk_detours;  // the plane wandered far from the shortest way
      radius[k] = graph[loop[k]];
    } else {
      radius[k] = walked;
    }
  }
  Polygon polar(n);
  double phi = 0;
  for (int k = 0; k < n; ++k) {
    polar[k] = radius[k] * Eigen::Vector2d(std::cos(phi), std::sin(phi));
    phi += gap[k];
  }
  Polygon convex = convexWithUnfoldedEars(patch, polar, counts);
  if (convex.empty()) return {};
  const double scale = std::sqrt(patchArea3d(patch) / polygonArea(convex));
  for (auto& q : convex) q *= scale;
  return convex;
}

}  // namespace sdp
