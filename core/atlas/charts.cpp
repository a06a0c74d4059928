#include "charts.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>

#include "core/common/parallel.h"

namespace sdp::atlas {
namespace {

struct Candidate {
  double cost;
  int face, region;
  double walked;
  // A min-heap with ties broken by face then region: the same growth on every run.
  bool operator>(const Candidate& o) const {
    if (cost != o.cost) return cost > o.cost;
    if (face != o.face) return face > o.face;
    return region > o.region;
  }
};
using CandidateQueue =
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>>;

// Growth of disk-shaped regions over a face list (charts.h).
class Grower {
 public:
  Grower(const FaceGraph& graph, std::vector<int>& region, double compactness, double length,
         const GrowthProgress* progress)
      : g_(graph),
        F_(*graph.F),
        region_(region),
        compactness_(compactness),
        length_(std::max(length, 1e-300)),
        progress_(progress) {}

  void seed(int face, int id) {
    region_[face] = id;
    if (id >= static_cast<int>(normal_sum_.size())) {
      normal_sum_.resize(id + 1, Eigen::Vector3d::Zero());
      mean_normal_.resize(id + 1, Eigen::Vector3d::Zero());
    }
    normal_sum_[id] += g_.area[face] * g_.growth_normal[face].cast<double>();
    if (normal_sum_[id].squaredNorm() == 0) normal_sum_[id] = g_.growth_normal[face].cast<double>();
    mean_normal_[id] = normal_sum_[id].normalized();
    pushNeighbours(face, id, 0);
  }

  void run() {
    while (!queue_.empty()) {
      const Candidate c = queue_.top();
      queue_.pop();
      if (region_[c.face] != kUnassigned) continue;
      // The region's mean normal moved since this was queued: queue again at the new cost
      // when another candidate is now cheaper.
      const double now = cost(c.face, c.region, c.walked);
      if (now > c.cost && !queue_.empty() && now > queue_.top().cost) {
        queue_.push({now, c.face, c.region, c.walked});
        continue;
      }
      if (!keepsDisk(c.face, c.region)) continue;
      region_[c.face] = c.region;
      normal_sum_[c.region] += g_.area[c.face] * g_.growth_normal[c.face].cast<double>();
      mean_normal_[c.region] = normal_sum_[c.region].normalized();
      pushNeighbours(c.face, c.region, c.walked);
      if (progress_ && ++taken_ == kFacesPerProgress) (*progress_)(taken_), taken_ = 0;
    }
    if (progress_ && taken_ > 0) (*progress_)(taken_), taken_ = 0;
  }

 private:
  double cost(int face, int id, double walked) const {
    return (1.0 - g_.growth_normal[face].cast<double>().dot(mean_normal_[id])) +
           compactness_ * walked / length_;
  }

  void pushNeighbours(int face, int id, double walked) {
    for (int k = 0; k < 3; ++k) {
      const int next = g_.across[3 * face + k];
      if (next < 0 || region_[next] != kUnassigned) continue;
      const double w = walked + (g_.centroid[next] - g_.centroid[face]).norm();
      queue_.push({cost(next, id, w), next, id, w});
    }
  }

  bool vertexIn(int v, int id) const {
    for (int k = g_.vertex_face_begin[v]; k < g_.vertex_face_begin[v + 1]; ++k)
      if (region_[g_.vertex_face[k]] == id) return true;
    return false;
  }
  bool edgeIn(int a, int b, int id) const {
    for (int k = g_.vertex_face_begin[a]; k < g_.vertex_face_begin[a + 1]; ++k) {
      const int f = g_.vertex_face[k];
      if (region_[f] == id && (F_(f, 0) == b || F_(f, 1) == b || F_(f, 2) == b)) return true;
    }
    return false;
  }

  // The region stays a disk with `face` added: it shares one edge and brings a new vertex, or
  // shares two edges and its third edge is not yet the region's (which would close a loop).
  bool keepsDisk(int face, int id) const {
    int shared = 0, mask = 0;
    for (int k = 0; k < 3; ++k) {
      const int other = g_.across[3 * face + k];
      if (other >= 0 && region_[other] == id) ++shared, mask |= 1 << k;
    }
    if (shared == 1) {
      const int k = mask == 1 ? 0 : mask == 2 ? 1 : 2;
      return !vertexIn(F_(face, (k + 2) % 3), id);
    }
    if (shared == 2) {
      const int k = mask == 6 ? 0 : mask == 5 ? 1 : 2;  // the edge not shared
      return !edgeIn(F_(face, k), F_(face, (k + 1) % 3), id);
    }
    return false;
  }

  const FaceGraph& g_;
  const Triangles& F_;
  std::vector<int>& region_;
  double compactness_, length_;
  std::vector<Eigen::Vector3d> normal_sum_;
  // normal_sum_ normalized, kept as it changes: each cost reads it (once per face taken, not
  // per candidate weighed).
  std::vector<Eigen::Vector3d> mean_normal_;
  CandidateQueue queue_;
  static constexpr int kFacesPerProgress = 16384;
  const GrowthProgress* progress_;
  int taken_ = 0;
};

// Dual-graph distances (centroid to centroid across shared edges) from `sources` over the faces
// of the list, which `region` marks with `id`; other faces stay at infinity.
void faceDistances(const FaceGraph& g, const std::vector<int>& region, int id,
                   const std::vector<int>& sources, std::vector<double>& distance) {
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int s : sources) {
    distance[s] = 0;
    queue.push({0.0, s});
  }
  while (!queue.empty()) {
    const auto [d, f] = queue.top();
    queue.pop();
    if (d > distance[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const int next = g.across[3 * f + k];
      if (next < 0 || region[next] != id) continue;
      const double nd = d + (g.centroid[next] - g.centroid[f]).norm();
      if (nd < distance[next]) {
        distance[next] = nd;
        queue.push({nd, next});
      }
    }
  }
}

// Moves "ears" across the border between two regions of the list: a face with one edge on its
// own region and two on another's goes to the other, which shortens the cut by the triangle
// inequality and keeps both regions disks (the face leaves as the reverse of a disk-keeping
// step and fills a notch of the other). Region growth over triangles leaves a zig-zag border;
// this straightens it, so the seam is shorter (docs/method.md §7).
void smoothBorders(const FaceGraph& g, const std::vector<int>& faces, std::vector<int>& region) {
  const Triangles& F = *g.F;
  auto vertexInOther = [&](int v, int id, int except) {
    for (int k = g.vertex_face_begin[v]; k < g.vertex_face_begin[v + 1]; ++k) {
      const int f = g.vertex_face[k];
      if (f != except && region[f] == id) return true;
    }
    return false;
  };
  constexpr int kPasses = 8;
  for (int pass = 0; pass < kPasses; ++pass) {
    int moved = 0;
    for (int f : faces) {
      const int own = region[f];
      int own_edges = 0, own_k = -1, other = kOutside, other_edges = 0;
      for (int k = 0; k < 3; ++k) {
        const int n = g.across[3 * f + k];
        if (n < 0) continue;
        if (region[n] == own) {
          ++own_edges, own_k = k;
        } else if (region[n] >= 0 && (other == kOutside || region[n] == other)) {
          other = region[n], ++other_edges;
        }
      }
      if (own_edges != 1 || other_edges != 2) continue;
      // The vertex opposite the edge kept with its own region must leave that region with it.
      const int apex = F(f, (own_k + 2) % 3);
      if (vertexInOther(apex, own, f)) continue;
      region[f] = other;
      ++moved;
    }
    if (moved == 0) break;
  }
}

// Rounds of averaging face normals over the faces around each corner (each round reaches one
// ring of faces further) for the normals that charts grow by. Scanner noise tilts single faces'
// normals by tens of degrees, and growth by raw normals followed the noise: parts with ragged,
// long borders (on the scans bench's fertility x64 with noise, first parts with a border 15-20
// times the square root of their area, whose maps reached L2 10-400 and were split again). On
// armadillo x16 (1.36M faces) with noise, charts 1312 -> 1212 and seam 107 -> 87 with three
// rounds, and without noise 1189 -> 1161 (docs/measurements.md).
constexpr int kGrowthNormalRounds = 3;

// Per face the unit normal of the area-weighted normals around it after kGrowthNormalRounds
// rounds (the face's own normal where the sum vanishes), in single precision: it only steers
// growth, and at 13.6M faces each byte per face is 13.6 MB.
std::vector<Eigen::Vector3f> smoothedNormals(const FaceGraph& g, int vertices) {
  const Triangles& F = *g.F;
  const int faces = g.faceCount();
  std::vector<Eigen::Vector3d> face_sum(faces), vertex_sum(vertices);
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int f = first; f < last; ++f) face_sum[f] = g.area[f] * g.normal[f];
  });
  for (int round = 0; round < kGrowthNormalRounds; ++round) {
    parallelFor(vertices, 16384, [&](int first, int last, int) {
      for (int v = first; v < last; ++v) {
        Eigen::Vector3d sum = Eigen::Vector3d::Zero();
        for (int k = g.vertex_face_begin[v]; k < g.vertex_face_begin[v + 1]; ++k)
          sum += face_sum[g.vertex_face[k]];
        vertex_sum[v] = sum;
      }
    });
    parallelFor(faces, 16384, [&](int first, int last, int) {
      for (int f = first; f < last; ++f) {
        if (!(g.area[f] > 0)) continue;
        const Eigen::Vector3d sum = vertex_sum[F(f, 0)] + vertex_sum[F(f, 1)] + vertex_sum[F(f, 2)];
        if (sum.squaredNorm() > 0) face_sum[f] = g.area[f] * sum.normalized();
      }
    });
  }
  std::vector<Eigen::Vector3f> normal(faces);
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int f = first; f < last; ++f)
      normal[f] =
          (g.area[f] > 0 && face_sum[f].squaredNorm() > 0 ? face_sum[f].normalized() : g.normal[f])
              .cast<float>();
  });
  return normal;
}

}  // namespace

FaceGraph faceGraphGeometry(const Positions& V, const Triangles& F,
                            const std::function<void()>& step) {
  FaceGraph g;
  g.F = &F;
  const int faces = static_cast<int>(F.rows());
  g.normal.resize(faces);
  g.centroid.resize(faces);
  g.area.resize(faces);
  g.chartable.resize(faces);
  // Per face on its own, in parallel (seconds at millions of faces); the area summed in face
  // order below, the same on any number of cores.
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int f = first; f < last; ++f) {
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), d = V.row(F(f, 2));
      const Eigen::Vector3d n = (b - a).cross(d - a);
      g.area[f] = 0.5 * n.norm();
      g.centroid[f] = (a + b + d) / 3;
      g.normal[f] = g.area[f] > 0 ? Eigen::Vector3d(n.normalized()) : Eigen::Vector3d::Zero();
    }
  });
  double total_area = 0;
  for (int f = 0; f < faces; ++f) total_area += g.area[f];
  // Zero area: below a millionth of a millionth of the mean face, where a normal means nothing.
  const double tiny = 1e-12 * total_area / std::max(faces, 1);
  for (int f = 0; f < faces; ++f) {
    const bool repeated = F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2);
    g.chartable[f] = !repeated && g.area[f] > tiny;
  }
  if (step) step();
  int vertices = 0;
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) vertices = std::max(vertices, F(f, k) + 1);
  g.vertex_face_begin.assign(vertices + 1, 0);
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k)
      if (k == 0 || F(f, k) != F(f, k - 1)) ++g.vertex_face_begin[F(f, k) + 1];
  for (int v = 0; v < vertices; ++v) g.vertex_face_begin[v + 1] += g.vertex_face_begin[v];
  g.vertex_face.resize(g.vertex_face_begin[vertices]);
  std::vector<int> fill(g.vertex_face_begin.begin(), g.vertex_face_begin.end() - 1);
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k)
      if (k == 0 || F(f, k) != F(f, k - 1)) g.vertex_face[fill[F(f, k)]++] = f;
  if (step) step();
  g.growth_normal = smoothedNormals(g, vertices);
  return g;
}

void joinFacesAcrossEdges(FaceGraph& g, const Connectivity& c) {
  const Triangles& F = *g.F;
  const int faces = g.faceCount();
  g.across.assign(3 * static_cast<size_t>(faces), -1);
  parallelFor(3 * faces, 3 * 16384, [&](int first, int last, int) {
    for (int h = first; h < last; ++h) {
      const int t = c.twin[h];
      if (t < 0 || !g.chartable[h / 3] || !g.chartable[t / 3]) continue;
      // Consistent orientation: the twin runs the opposite way.
      const int from = F(h / 3, h % 3), to = F(h / 3, (h % 3 + 1) % 3);
      if (F(t / 3, t % 3) == to && F(t / 3, (t % 3 + 1) % 3) == from) g.across[h] = t / 3;
    }
  });
}

FaceGraph buildFaceGraph(const Positions& V, const Triangles& F, const Connectivity& c,
                         const std::function<void()>& step) {
  FaceGraph g = faceGraphGeometry(V, F, step);
  if (step) step();
  joinFacesAcrossEdges(g, c);
  return g;
}

int growRegions(const FaceGraph& graph, const std::vector<int>& faces,
                const std::vector<int>& seeds, int first_id, double compactness, double length,
                std::vector<int>& region, const GrowthProgress* progress) {
  Grower grower(graph, region, compactness, length, progress);
  int id = first_id;
  // All seeds grow at once from one queue, so they compete for faces; what none could take
  // seeds new regions, one at a time.
  for (int s : seeds) grower.seed(s, id++);
  grower.run();
  for (int f : faces)
    if (region[f] == kUnassigned) {
      grower.seed(f, id++);
      grower.run();
    }
  return id - first_id;
}

FaceScratch::FaceScratch(const FaceGraph& graph)
    : region(graph.faceCount(), kOutside),
      distance(graph.faceCount(), std::numeric_limits<double>::infinity()),
      vertex(graph.vertex_face_begin.size(), -1) {}

namespace {

// The face of the list farthest from the seeds so far (`distance`, which only ever decreases
// as seeds are added), the first in list order among equals: a lazy max-heap whose entries are
// bounds from above, re-queued at their current value when stale, so each pick costs a few heap
// steps instead of a pass over the list.
class FarthestFace {
 public:
  FarthestFace(const std::vector<int>& faces, const std::vector<double>& distance)
      : faces_(faces), distance_(distance) {
    for (int i = 0; i < static_cast<int>(faces.size()); ++i)
      if (std::isfinite(distance[faces[i]])) heap_.push({distance[faces[i]], i});
  }
  int next() {
    while (!heap_.empty()) {
      const Entry top = heap_.top();
      const double now = distance_[faces_[top.position]];
      if (now == top.distance) return faces_[top.position];
      heap_.pop();
      heap_.push({now, top.position});
    }
    return faces_.front();
  }

 private:
  struct Entry {
    double distance;
    int position;
    bool operator<(const Entry& o) const {
      return distance != o.distance ? distance < o.distance : position > o.position;
    }
  };
  const std::vector<int>& faces_;
  const std::vector<double>& distance_;
  std::priority_queue<Entry> heap_;
};

// Above this many parts, seeds come from a grid (splitFaces): farthest-point sampling costs a
// search per seed, 4.4 of the 10 s the scans bench's 1.36M-face armadillo x16 spent on its first
// cut into 920 parts; with grid seeds its charts stay as they were (1377 against 1389, seam
// 112.0 against 112.4, efficiency 0.608 against 0.612). At fewer parts farthest points cost
// little and did better: on fertility x64 with noise (162 parts) grid seeds made 686 charts at
// efficiency 0.571 in 30 s, farthest points 698 at 0.587 in 27 s.
constexpr int kMostFarthestSeeds = 512;
// A grid cell's side per part's length (the side of a square of a part's area): a surface
// crosses more cells than its area in cells, so the cells are a little larger than a part.
constexpr double kGridCellPerPartLength = 1.2;

// Per occupied cell of a grid of side `cell`, the face whose centroid is nearest the cell's
// centre (the first in list order among equals), in the cells' order. One hash lookup per face
// and a sort of the cells, not a sort of every face (seconds at millions of faces, on one core).
// `faces_done` is told how many faces were looked at, now and then (seconds at 13M faces).
std::vector<int> gridSeeds(const FaceGraph& graph, const std::vector<int>& faces, double cell,
                           const std::function<void(size_t)>& faces_done) {
  Eigen::Vector3d low = graph.centroid[faces.front()];
  for (int f : faces) low = low.cwiseMin(graph.centroid[f]);
  using Key = std::array<long long, 3>;
  struct KeyHash {
    size_t operator()(const Key& k) const {  // unsigned: wraps, never overflows
      const auto u = [](long long v) { return static_cast<unsigned long long>(v); };
      return static_cast<size_t>(u(k[0]) * 73856093ULL ^ u(k[1]) * 19349663ULL ^
                                 u(k[2]) * 83492791ULL);
    }
  };
  struct Nearest {
    double distance;
    int position;
  };
  std::unordered_map<Key, Nearest, KeyHash> nearest;
  for (size_t i = 0; i < faces.size(); ++i) {
    if (i % (1 << 18) == 0) faces_done(i);
    const Eigen::Vector3d p = (graph.centroid[faces[i]] - low) / cell;
    Key key;
    for (int a = 0; a < 3; ++a) key[a] = static_cast<long long>(std::floor(p[a]));
    const Eigen::Vector3d centre(key[0] + 0.5, key[1] + 0.5, key[2] + 0.5);
    const Nearest candidate{(p - centre).squaredNorm(), static_cast<int>(i)};
    const auto [at, added] = nearest.try_emplace(key, candidate);
    // Faces come in list order: a later one wins only when strictly nearer.
    if (!added && candidate.distance < at->second.distance) at->second = candidate;
  }
  std::vector<std::pair<Key, int>> cells;
  cells.reserve(nearest.size());
  for (const auto& [key, best] : nearest) cells.emplace_back(key, best.position);
  std::sort(cells.begin(), cells.end());
  std::vector<int> seeds;
  seeds.reserve(cells.size());
  for (const auto& [key, position] : cells) seeds.push_back(faces[position]);
  return seeds;
}

}  // namespace

namespace {

constexpr int kMarked = -3;
constexpr double kCompactness = 0.25;

// A split's seeds count once over its faces for the progress bar, shared out as they are found
// (a search per seed: seconds for a few hundred parts of a large piece).
struct SeedProgress {
  const GrowthProgress* progress;
  size_t faces;
  int parts;
  long long delivered = 0;
  void operator()(size_t found) {
    if (!progress) return;
    const long long due = static_cast<long long>(faces) *
                          static_cast<long long>(std::min<size_t>(found, std::max(parts, 1))) /
                          std::max(parts, 1);
    if (due > delivered) (*progress)(static_cast<int>(due - delivered));
    delivered = std::max(delivered, due);
  }
};

// Up to `parts` faces of the list far apart along the surface: farthest-point sampling, from
// the face farthest from the list's first face. The faces are marked kMarked in `region`, and
// `distance` is infinite on them on entry and on return.
std::vector<int> farthestSeeds(const FaceGraph& graph, const std::vector<int>& faces, int parts,
                               const std::vector<int>& region, std::vector<double>& distance,
                               SeedProgress& found) {
  std::vector<int> seeds;
  faceDistances(graph, region, kMarked, {faces.front()}, distance);
  seeds.push_back(FarthestFace(faces, distance).next());
  for (int f : faces) distance[f] = std::numeric_limits<double>::infinity();
  faceDistances(graph, region, kMarked, seeds, distance);
  FarthestFace farthest(faces, distance);
  while (static_cast<int>(seeds.size()) < parts) {
    const int next = farthest.next();
    if (distance[next] == 0) break;
    seeds.push_back(next);
    faceDistances(graph, region, kMarked, {next}, distance);
    found(seeds.size());
  }
  for (int f : faces) distance[f] = std::numeric_limits<double>::infinity();
  return seeds;
}

// Grows parts from `seeds` over the faces of the list (kUnassigned in `region` on entry, and
// only these are read or written), moving each seed a few Lloyd steps to the most typical face
// of its part, then straightens the borders. Leaves each face's part id in `region`; returns the
// number of parts.
int growLloydParts(const FaceGraph& graph, const std::vector<int>& faces, std::vector<int> seeds,
                   double length, std::vector<int>& region, const GrowthProgress* progress) {
  constexpr int kLloydSteps = 2;
  for (int step = 0;; ++step) {
    for (int f : faces) region[f] = kUnassigned;
    const int made = growRegions(graph, faces, seeds, 0, kCompactness, length, region, progress);
    if (step == kLloydSteps) {
      smoothBorders(graph, faces, region);
      return made;
    }
    // Each part's most typical face: close to its mean normal and to its centroid.
    const int n = static_cast<int>(seeds.size());
    std::vector<Eigen::Vector3d> normal(n, Eigen::Vector3d::Zero()),
        centre(n, Eigen::Vector3d::Zero());
    std::vector<double> part_area(n, 0.0);
    for (int f : faces)
      if (region[f] < n) {
        normal[region[f]] += graph.area[f] * graph.growth_normal[f].cast<double>();
        centre[region[f]] += graph.area[f] * graph.centroid[f];
        part_area[region[f]] += graph.area[f];
      }
    std::vector<double> best(n, -std::numeric_limits<double>::infinity());
    for (int f : faces) {
      const int p = region[f];
      if (p >= n || part_area[p] <= 0) continue;
      const double score =
          graph.growth_normal[f].cast<double>().dot(normal[p].normalized()) -
          kCompactness * (graph.centroid[f] - centre[p] / part_area[p]).norm() / length;
      if (score > best[p]) best[p] = score, seeds[p] = f;
    }
  }
}

// From this many faces a split grows its parts in two halves at once, one per core: the growth
// is one queue over the whole list, the longest step of a large scan's charts on one core (on
// the scans bench's 13.6M-face cheburashka, three growths of 22 s each). The halves are cut by
// the plane across the list's longest side through the median centroid, so the same on any
// number of cores; no part crosses that plane, which adds its length to the seam.
constexpr size_t kFewestFacesForHalves = 200000;

// The faces of the list on either side of the plane across their longest side through the
// median centroid (ties by face index), each half in list order.
std::array<std::vector<int>, 2> halves(const FaceGraph& graph, const std::vector<int>& faces) {
  Eigen::Vector3d low = graph.centroid[faces.front()], high = low;
  for (int f : faces)
    low = low.cwiseMin(graph.centroid[f]), high = high.cwiseMax(graph.centroid[f]);
  int axis = 0;
  (high - low).maxCoeff(&axis);
  std::vector<std::pair<double, int>> along(faces.size());
  for (size_t i = 0; i < faces.size(); ++i) along[i] = {graph.centroid[faces[i]][axis], faces[i]};
  const auto middle = along.begin() + along.size() / 2;
  std::nth_element(along.begin(), middle, along.end());
  const std::pair<double, int> median = *middle;
  std::array<std::vector<int>, 2> half;
  for (int f : faces)
    half[std::make_pair(graph.centroid[f][axis], f) < median ? 0 : 1].push_back(f);
  return half;
}

}  // namespace

std::vector<std::vector<int>> splitFaces(const FaceGraph& graph, const std::vector<int>& faces,
                                         int parts, FaceScratch& scratch,
                                         const GrowthProgress* progress) {
  std::vector<std::vector<int>> result;
  if (faces.empty()) return result;
  std::vector<int>& region = scratch.region;
  std::vector<double>& distance = scratch.distance;
  double area = 0;
  for (int f : faces) area += graph.area[f];
  const double length = std::sqrt(area / std::max(parts, 1));

  // Seeds far apart along the surface: farthest-point sampling from the first face; for many
  // parts, one seed per occupied cell of a grid of the parts' size instead, which costs one
  // sort rather than a search per seed (the Lloyd steps below place them either way).
  for (int f : faces) region[f] = kMarked;
  const bool grid = parts > kMostFarthestSeeds;
  std::vector<int> seeds;
  SeedProgress seeds_found{progress, faces.size(), parts};
  // Large sets grow in two halves, one per core, each sampling its own farthest seeds.
  const bool in_halves = faces.size() >= kFewestFacesForHalves;
  if (!in_halves || grid) {
    if (grid) {
      // As if the seeds were found in proportion to the faces looked at.
      seeds = gridSeeds(graph, faces, kGridCellPerPartLength * length, [&](size_t done) {
        seeds_found(done * static_cast<size_t>(parts) / faces.size());
      });
    } else {
      seeds = farthestSeeds(graph, faces, parts, region, distance, seeds_found);
    }
    seeds_found(static_cast<size_t>(parts));
  }
  if (!in_halves || (grid && seeds.size() < 2)) {
    const int made = growLloydParts(graph, faces, std::move(seeds), length, region, progress);
    result.resize(made);
    for (int f : faces) result[region[f]].push_back(f);
  } else {
    // The second half grows over a region array of its own, in which the first half's faces
    // are outside: neither half's growth reads what the other writes. Grid seeds go to the
    // half they fall in; farthest points are sampled in each half on its own, on its core (a
    // search per seed: 1.1 of the 1.8 s the scans bench's fertility x64 took for its first cut
    // into 162 parts, on one core), each half given the parts in proportion to its faces.
    std::array<std::vector<int>, 2> half = halves(graph, faces);
    for (int f : half[1]) region[f] = kOutside;
    std::vector<int> second_region(graph.faceCount(), kOutside);
    std::array<std::vector<int>*, 2> regions = {&region, &second_region};
    std::array<std::vector<int>, 2> half_seeds;
    std::vector<double> second_distance;
    std::array<std::vector<double>*, 2> distances = {&distance, &second_distance};
    std::array<int, 2> half_parts = {0, 0};
    if (grid) {
      for (int s : seeds) half_seeds[region[s] == kMarked ? 0 : 1].push_back(s);
    } else {
      for (int f : half[1]) second_region[f] = kMarked;
      second_distance.assign(graph.faceCount(), std::numeric_limits<double>::infinity());
      const double share = static_cast<double>(half[0].size()) / static_cast<double>(faces.size());
      half_parts[0] = std::clamp(static_cast<int>(std::lround(parts * share)), 1, parts - 1);
      half_parts[1] = parts - half_parts[0];
    }
    std::array<int, 2> made = {0, 0};
    parallelFor(2, 1, [&](int begin, int end, int) {
      for (int h = begin; h < end; ++h) {
        if (!grid) {
          SeedProgress found{progress, half[h].size(), half_parts[h]};
          half_seeds[h] =
              farthestSeeds(graph, half[h], half_parts[h], *regions[h], *distances[h], found);
          found(static_cast<size_t>(half_parts[h]));
        }
        made[h] =
            growLloydParts(graph, half[h], std::move(half_seeds[h]), length, *regions[h], progress);
      }
    });
    result.resize(made[0] + made[1]);
    for (int f : half[0]) result[region[f]].push_back(f);
    for (int f : half[1]) result[made[0] + second_region[f]].push_back(f);
  }
  for (int f : faces) region[f] = kOutside;
  return result;
}

namespace {

// The patches of `patch` (per face its patch id, `count` ids) as lists, after the patches of
// fewer than `fewest` faces joined the neighbouring patch they share the most edges with (the
// lowest id among equals), in id order. Leaves `patch` kOutside on the faces.
std::vector<std::vector<int>> absorbSmallPatches(const FaceGraph& graph,
                                                 const std::vector<int>& faces, int count,
                                                 int fewest, std::vector<int>& patch) {
  std::vector<std::vector<int>> members(count);
  for (int f : faces) members[patch[f]].push_back(f);
  for (size_t p = 0; p < members.size(); ++p) {
    if (members[p].empty() || static_cast<int>(members[p].size()) >= fewest) continue;
    std::vector<int> border;  // per edge on the patch's border, the patch across
    for (int f : members[p])
      for (int k = 0; k < 3; ++k) {
        const int next = graph.across[3 * f + k];
        if (next >= 0 && patch[next] >= 0 && patch[next] != static_cast<int>(p))
          border.push_back(patch[next]);
      }
    if (border.empty()) continue;
    std::sort(border.begin(), border.end());
    int best = -1, most = 0;
    for (size_t i = 0; i < border.size();) {
      size_t j = i;
      while (j < border.size() && border[j] == border[i]) ++j;
      if (static_cast<int>(j - i) > most) most = static_cast<int>(j - i), best = border[i];
      i = j;
    }
    for (int f : members[p]) patch[f] = best;
    members[best].insert(members[best].end(), members[p].begin(), members[p].end());
    members[p].clear();
  }
  std::vector<std::vector<int>> result;
  for (std::vector<int>& m : members)
    if (!m.empty()) {
      std::sort(m.begin(), m.end());
      result.push_back(std::move(m));
    }
  for (int f : faces) patch[f] = kOutside;
  return result;
}

// Patches over `faces` (marked in `patch`), each grown from the next unassigned face of `seeds`
// across the edges from a face `f` to a neighbour `next` unless separated(f, seed, next); then
// small ones absorbed as absorbSmallPatches does.
// Floods patches over the faces `patch` marks kUnassigned, each from the next unassigned face of
// `seeds` across the edges from a face `f` to a neighbour `next` unless separated(f, seed,
// next), giving ids 0, 1, ... in `patch`; done(members) sees each patch's faces as flooded.
// Returns the number of patches.
template <class Separated, class Done>
int floodPatches(const FaceGraph& graph, const std::vector<int>& seeds, std::vector<int>& patch,
                 Separated separated, Done done) {
  int count = 0;
  std::vector<int> queue;
  for (int start : seeds) {
    if (patch[start] != kUnassigned) continue;
    const int id = count++;
    queue.assign(1, start);
    patch[start] = id;
    for (size_t i = 0; i < queue.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const int f = queue[i], next = graph.across[3 * f + k];
        if (next < 0 || patch[next] != kUnassigned || separated(f, start, next)) continue;
        patch[next] = id;
        queue.push_back(next);
      }
    done(queue);
  }
  return count;
}

// Tells `progress` (when given) of the faces of each patch flooded, in batches: a noisy scan's
// patches are some tens of faces each.
class FloodProgress {
 public:
  explicit FloodProgress(const GrowthProgress* progress) : progress_(progress) {}
  void add(size_t faces) {
    pending_ += static_cast<int>(faces);
    if (pending_ >= kBatch) flush();
  }
  // Tells the rest (the progress may throw: a cancel; never from a destructor).
  void flush() {
    const int faces = pending_;
    pending_ = 0;
    if (progress_ && faces > 0) (*progress_)(faces);
  }

 private:
  static constexpr int kBatch = 1 << 16;
  const GrowthProgress* progress_;
  int pending_ = 0;
};

template <class Separated>
std::vector<std::vector<int>> growPatches(const FaceGraph& graph, const std::vector<int>& faces,
                                          const std::vector<int>& seeds, int fewest,
                                          std::vector<int>& patch, Separated separated,
                                          const GrowthProgress* progress = nullptr) {
  for (int f : faces) patch[f] = kUnassigned;
  FloodProgress flooded(progress);
  const int count =
      floodPatches(graph, seeds, patch, separated,
                   [&](const std::vector<int>& members) { flooded.add(members.size()); });
  flooded.flush();
  return absorbSmallPatches(graph, faces, count, fewest, patch);
}

// Whether the edge between two faces is sharp (featurePatches' separation).
bool sharpEdge(const FaceGraph& graph, int f, int next, double sharp_cos) {
  return graph.normal[f].dot(graph.normal[next]) < sharp_cos;
}

}  // namespace

std::vector<std::vector<int>> featurePatches(const FaceGraph& graph, const std::vector<int>& faces,
                                             double sharp_cos, int fewest, FaceScratch& scratch,
                                             const GrowthProgress* progress) {
  return growPatches(
      graph, faces, faces, fewest, scratch.region,
      [&](int f, int, int next) { return sharpEdge(graph, f, next, sharp_cos); }, progress);
}

double secondFeaturePatchShare(const FaceGraph& graph, const std::vector<int>& faces,
                               double sharp_cos, int fewest, FaceScratch& scratch,
                               const GrowthProgress* progress) {
  std::vector<int>& patch = scratch.region;
  for (int f : faces) patch[f] = kUnassigned;
  double total = 0, largest = 0, second = 0;
  FloodProgress flooded(progress);
  floodPatches(
      graph, faces, patch,
      [&](int f, int, int next) { return sharpEdge(graph, f, next, sharp_cos); },
      [&](const std::vector<int>& members) {
        flooded.add(members.size());
        double area = 0;
        for (int f : members) area += graph.area[f];
        total += area;
        if (static_cast<int>(members.size()) < fewest) return;  // it would join a neighbour
        if (area > largest) {
          second = largest, largest = area;
        } else {
          second = std::max(second, area);
        }
      });
  flooded.flush();
  for (int f : faces) patch[f] = kOutside;
  return total > 0 ? second / total : 0;
}

std::vector<std::vector<int>> flatPatches(const FaceGraph& graph, const std::vector<int>& faces,
                                          double cone_cos, int fewest, FaceScratch& scratch) {
  // Seeds largest first (a CAD part's flat faces before its fillets' strips), ties by index.
  std::vector<int> seeds = faces;
  std::stable_sort(seeds.begin(), seeds.end(),
                   [&](int a, int b) { return graph.area[a] > graph.area[b]; });
  return growPatches(graph, faces, seeds, fewest, scratch.region, [&](int, int seed, int next) {
    return graph.normal[seed].dot(graph.normal[next]) < cone_cos;
  });
}

bool regionIsDisk(const FaceGraph& graph, const std::vector<int>& faces, FaceScratch& scratch) {
  return regionHoles(graph, faces, scratch) == 0;
}

int regionEulerCharacteristic(const FaceGraph& graph, const std::vector<int>& faces,
                              FaceScratch& scratch) {
  const Triangles& F = *graph.F;
  std::vector<int>& region = scratch.region;
  std::vector<int>& seen = scratch.vertex;
  for (int f : faces) region[f] = kMarked;
  long long vertices = 0, joined_half_edges = 0, border_edges = 0;
  for (int f : faces)
    for (int k = 0; k < 3; ++k) {
      int& v = seen[F(f, k)];
      if (v < 0) v = 0, ++vertices;
      const int next = graph.across[3 * f + k];
      if (next >= 0 && region[next] == kMarked)
        ++joined_half_edges;
      else
        ++border_edges;
    }
  for (int f : faces) {
    region[f] = kOutside;
    for (int k = 0; k < 3; ++k) seen[F(f, k)] = -1;
  }
  const long long edges = joined_half_edges / 2 + border_edges;
  return static_cast<int>(vertices - edges + static_cast<long long>(faces.size()));
}

int regionHoles(const FaceGraph& graph, const std::vector<int>& faces, FaceScratch& scratch) {
  const Triangles& F = *graph.F;
  std::vector<int>& local = scratch.vertex;
  Triangles sub(faces.size(), 3);
  int vertices = 0;
  for (size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      int& l = local[F(faces[i], k)];
      if (l < 0) l = vertices++;
      sub(i, k) = l;
    }
  for (int f : faces)
    for (int k = 0; k < 3; ++k) local[F(f, k)] = -1;
  return analyzeConnectivity(sub, vertices).diskHoles();
}

}  // namespace sdp::atlas
