#include "patch_topology.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/common/error.h"

namespace sdp {
namespace {

[[noreturn]] void fail(const std::string& reason) {
  throw ParameterizationError(reason);
}

struct HalfEdge {
  int target;
  int face;
};

using PositionMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using TriangleMatrix = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

std::string inputName(const Patch& p, int local) {
  return std::to_string(p.input_vertex[local]);
}

// Every face names three distinct vertices of the mesh; the referenced vertices, with finite
// coordinates, become the patch's, in input order so results map back by index.
void compactVertices(const PositionMatrix& V, const TriangleMatrix& F, Patch& p) {
  const int input_vertices = static_cast<int>(V.rows());
  const int faces = static_cast<int>(F.rows());
  p.local_vertex.assign(input_vertices, -1);
  p.face.resize(faces);
  for (int f = 0; f < faces; ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = F(f, c);
      if (v < 0 || v >= input_vertices)
        fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
             ", but the mesh has " + std::to_string(input_vertices) + " vertices");
    }
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 0) == F(f, 2))
      fail("face " + std::to_string(f) + " uses the same vertex twice (a degenerate face)");
  }
  // Compact to referenced vertices, keeping input order so results map back by index.
  for (int f = 0; f < faces; ++f)
    for (int c = 0; c < 3; ++c) p.local_vertex[F(f, c)] = 0;
  for (int v = 0; v < input_vertices; ++v) {
    if (p.local_vertex[v] < 0) continue;
    if (!std::isfinite(V(v, 0)) || !std::isfinite(V(v, 1)) || !std::isfinite(V(v, 2)))
      fail("vertex " + std::to_string(v) + " has a non-finite coordinate (NaN or infinity)");
    p.local_vertex[v] = static_cast<int>(p.input_vertex.size());
    p.input_vertex.push_back(v);
    p.position.emplace_back(V(v, 0), V(v, 1), V(v, 2));
  }
  for (int f = 0; f < faces; ++f)
    for (int c = 0; c < 3; ++c) p.face[f][c] = p.local_vertex[F(f, c)];
}

// Centre the coordinates and bring the largest extent to 1: a scan far from the origin would
// lose digits in every difference, and one in nanometres or light years would underflow or
// overflow in areas and products. The results are similarity-invariant anyway.
void normalizeFrame(Patch& p) {
  Eigen::Vector3d low = p.position[0], high = p.position[0];
  for (const auto& q : p.position) low = low.cwiseMin(q), high = high.cwiseMax(q);
  const Eigen::Vector3d centre = 0.5 * low + 0.5 * high;
  const double extent = (0.5 * high - 0.5 * low).maxCoeff() * 2;
  if (!std::isfinite(extent))
    fail("the coordinates are too large to compute with (their range overflows)");
  // The map is returned in the mesh's units (UV area = 3D area), so its areas must stay
  // normal doubles: a mesh spanning 1e290 units would give infinite UV areas.
  constexpr double kLargestExtent = 1e100, kSmallestExtent = 1e-100;
  if (extent > kLargestExtent || (extent > 0 && extent < kSmallestExtent)) {
    char numbers[128];
    std::snprintf(numbers, sizeof numbers,
                  "the mesh spans %.3g units; 1e-100 to 1e100 are supported (areas in its "
                  "units would leave the double range)",
                  extent);
    fail(numbers);
  }
  p.unit = extent > 0 ? extent : 1.0;
  for (auto& q : p.position) q = (q - centre) / p.unit;
}

// Outgoing half-edges per vertex, sorted by target so twins are found by binary search and
// repeated edges sit side by side.
class HalfEdges {
 public:
  explicit HalfEdges(const Patch& p) {
    const int n = p.vertexCount();
    const int faces = static_cast<int>(p.face.size());
    begin_.assign(n + 1, 0);
    for (const auto& t : p.face)
      for (int c = 0; c < 3; ++c) ++begin_[t[c] + 1];
    for (int v = 0; v < n; ++v) begin_[v + 1] += begin_[v];
    out_.resize(begin_[n]);
    std::vector<int> fill(begin_.begin(), begin_.end() - 1);
    for (int f = 0; f < faces; ++f)
      for (int c = 0; c < 3; ++c) out_[fill[p.face[f][c]]++] = {p.face[f][(c + 1) % 3], f};
    for (int v = 0; v < n; ++v) {
      auto first = out_.begin() + begin_[v], last = out_.begin() + begin_[v + 1];
      std::sort(first, last, [](const HalfEdge& a, const HalfEdge& b) {
        return a.target != b.target ? a.target < b.target : a.face < b.face;
      });
    }
  }
  const HalfEdge* find(int from, int to) const {
    auto first = out_.begin() + begin_[from], last = out_.begin() + begin_[from + 1];
    auto it = std::lower_bound(first, last, to,
                               [](const HalfEdge& h, int target) { return h.target < target; });
    return (it != last && it->target == to) ? &*it : nullptr;
  }
  int begin(int v) const { return begin_[v]; }
  int end(int v) const { return begin_[v + 1]; }
  const HalfEdge& operator[](int k) const { return out_[k]; }

 private:
  std::vector<int> begin_;
  std::vector<HalfEdge> out_;
};

// An edge used twice in the same direction: duplicate faces, a non-manifold edge, or faces
// oriented inconsistently.
void checkEdges(const Patch& p, const HalfEdges& out) {
  for (int v = 0; v < p.vertexCount(); ++v) {
    for (int k = out.begin(v) + 1; k < out.end(v); ++k) {
      if (out[k].target != out[k - 1].target) continue;
      const int w = out[k].target, f1 = out[k - 1].face, f2 = out[k].face;
      auto sorted = [&](int f) {
        auto t = p.face[f];
        std::sort(t.begin(), t.end());
        return t;
      };
      const std::string edge = "(" + inputName(p, v) + ", " + inputName(p, w) + ")";
      if (sorted(f1) == sorted(f2))
        fail("faces " + std::to_string(f1) + " and " + std::to_string(f2) + " are duplicates");
      if (out.find(w, v))
        fail("edge " + edge + " is shared by more than two faces (a non-manifold edge)");
      fail("faces " + std::to_string(f1) + " and " + std::to_string(f2) +
           " are oriented inconsistently at edge " + edge);
    }
  }
}

// face_across from the twins; returns the number of boundary half-edges.
int linkFaces(Patch& p, const HalfEdges& out) {
  const int faces = static_cast<int>(p.face.size());
  p.face_across.resize(faces);
  int boundary_half_edges = 0;
  for (int f = 0; f < faces; ++f) {
    for (int c = 0; c < 3; ++c) {
      const HalfEdge* twin = out.find(p.face[f][(c + 1) % 3], p.face[f][c]);
      p.face_across[f][c] = twin ? twin->face : -1;
      boundary_half_edges += twin ? 0 : 1;
    }
  }
  return boundary_half_edges;
}

// One connected piece (through edges).
void checkConnected(const Patch& p) {
  const int faces = static_cast<int>(p.face.size());
  const int n = p.vertexCount();
  std::vector<char> seen(faces, 0);
  std::vector<int> stack;
  int components = 0;
  for (int start = 0; start < faces; ++start) {
    if (seen[start]) continue;
    ++components;
    seen[start] = 1;
    stack.push_back(start);
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      for (int g : p.face_across[f])
        if (g >= 0 && !seen[g]) seen[g] = 1, stack.push_back(g);
    }
  }
  if (components > 1 && components == faces && n == 3 * faces)
    fail("the mesh has " + std::to_string(components) +
         " connected components: its faces share no edges (merge duplicate vertices first)");
  if (components > 1)
    fail("the mesh has " + std::to_string(components) +
         " connected components; a patch must be one piece (select one component, or use the atlas "
         "filter: Straightest Distances Atlas; --atlas in the CLI)");
}

// Boundary loops: every boundary vertex has exactly one outgoing boundary edge. Fills
// on_boundary, boundary_next and the first loop; returns the number of loops (every loop, as
// input vertex indices, in `all_loops` when given).
int findBoundaryLoops(Patch& p, int boundary_half_edges, std::vector<int>& boundary_next,
                      std::vector<std::vector<int>>* all_loops) {
  const int faces = static_cast<int>(p.face.size());
  const int n = p.vertexCount();
  boundary_next.assign(n, -1);
  p.on_boundary.assign(n, 0);
  for (int f = 0; f < faces; ++f) {
    for (int c = 0; c < 3; ++c) {
      if (p.face_across[f][c] >= 0) continue;
      const int a = p.face[f][c], b = p.face[f][(c + 1) % 3];
      if (boundary_next[a] >= 0)
        fail("vertex " + inputName(p, a) +
             " is non-manifold (two parts of the surface meet only at this vertex)");
      boundary_next[a] = b;
      p.on_boundary[a] = 1;
    }
  }
  if (boundary_half_edges == 0)
    fail(
        "the mesh is closed (it has no boundary); cut it open into a disk-shaped patch first, or "
        "use the atlas filter (Straightest Distances Atlas; --atlas in the CLI)");
  int loops = 0;
  std::vector<char> visited(n, 0);
  for (int start = 0; start < n; ++start) {
    if (!p.on_boundary[start] || visited[start]) continue;
    ++loops;
    std::vector<int> loop;
    for (int v = start; !visited[v]; v = boundary_next[v]) {
      visited[v] = 1;
      loop.push_back(v);
    }
    if (all_loops) {
      all_loops->emplace_back();
      for (int v : loop) all_loops->back().push_back(p.input_vertex[v]);
    }
    if (loops == 1) p.boundary_loop.swap(loop);
  }
  return loops;
}

// Ordered 1-rings, walking counter-clockwise from the boundary edge (or any edge); each must be
// one fan.
void buildRings(Patch& p, const HalfEdges& out, const std::vector<int>& boundary_next) {
  const int n = p.vertexCount();
  p.ring_begin.assign(n + 1, 0);
  for (int v = 0; v < n; ++v)
    p.ring_begin[v + 1] = p.ring_begin[v] + (out.end(v) - out.begin(v)) + p.on_boundary[v];
  p.ring_vertex.resize(p.ring_begin[n]);
  p.ring_face.resize(p.ring_begin[n]);
  auto cornerOf = [&](int f, int v) { return p.face[f][0] == v ? 0 : (p.face[f][1] == v ? 1 : 2); };
  for (int v = 0; v < n; ++v) {
    int f = out[out.begin(v)].face;
    if (p.on_boundary[v]) {
      const HalfEdge* boundary_out = out.find(v, boundary_next[v]);
      f = boundary_out->face;
    }
    const int start_face = f;
    int k = p.ring_begin[v];
    const int end = p.ring_begin[v + 1];
    bool closed = false;
    while (k < end) {
      const int c = cornerOf(f, v);
      p.ring_vertex[k] = p.face[f][(c + 1) % 3];
      p.ring_face[k] = f;
      ++k;
      const int next = p.face_across[f][(c + 2) % 3];
      if (next < 0) {  // reached the boundary: the last neighbour closes the open fan
        if (k < end) {
          p.ring_vertex[k] = p.face[f][(c + 2) % 3];
          p.ring_face[k] = -1;
          ++k;
        }
        break;
      }
      if (next == start_face) {
        closed = true;
        break;
      }
      f = next;
    }
    const bool complete = (k == end) && (p.on_boundary[v] ? !closed : closed);
    if (!complete)
      fail("vertex " + inputName(p, v) +
           " is non-manifold (its faces do not form a single fan around it)");
  }
}

// The whole check and build, each check in the order its reason should win. With `all_loops`
// given and more than one boundary loop, it stops after finding the loops (as input vertex
// indices) and returns an incomplete patch.
Patch analyzePatch(const PositionMatrix& V, const TriangleMatrix& F,
                   std::vector<std::vector<int>>* all_loops) {
  const int faces = static_cast<int>(F.rows());
  if (faces == 0) fail("the mesh has no faces");
  Patch p;
  compactVertices(V, F, p);
  normalizeFrame(p);
  const HalfEdges out(p);
  checkEdges(p, out);
  const int boundary_half_edges = linkFaces(p, out);
  checkConnected(p);
  std::vector<int> boundary_next;
  const int loops = findBoundaryLoops(p, boundary_half_edges, boundary_next, all_loops);
  if (loops > 1 && all_loops) return p;
  if (all_loops) all_loops->clear();
  if (loops > 1)
    fail("the patch has " + std::to_string(loops) +
         " boundary loops (holes); only disk-shaped patches with one boundary loop are supported");
  buildRings(p, out, boundary_next);

  const int n = p.vertexCount();
  const long long edges = (3LL * faces + boundary_half_edges) / 2;
  const long long euler = static_cast<long long>(n) - edges + faces;
  if (euler != 1)
    fail("the patch has Euler characteristic " + std::to_string(euler) + " (genus " +
         std::to_string((1 - euler) / 2) + "); it must be a topological disk (characteristic 1)");
  p.real_vertex_count = n;
  p.real_face_count = faces;
  return p;
}

double loopLength(const PositionMatrix& V, const std::vector<int>& loop) {
  double length = 0;
  for (size_t k = 0; k < loop.size(); ++k)
    length += (V.row(loop[(k + 1) % loop.size()]) - V.row(loop[k])).norm();
  return length;
}

}  // namespace

Patch buildPatch(const PositionMatrix& V, const TriangleMatrix& F, const PatchOptions& options) {
  std::vector<std::vector<int>> loops;
  Patch first = analyzePatch(V, F, options.fill_holes ? &loops : nullptr);
  if (loops.size() <= 1) return first;

  // Outer loop: the one holding the user's vertex, else the longest.
  size_t outer = 0;
  for (size_t l = 0; l < loops.size(); ++l) {
    const bool holds =
        std::find(loops[l].begin(), loops[l].end(), options.outer_vertex) != loops[l].end();
    if (options.outer_vertex >= 0 ? holds : loopLength(V, loops[l]) > loopLength(V, loops[outer]))
      outer = l;
  }
  if (options.outer_vertex >= 0 && std::find(loops[outer].begin(), loops[outer].end(),
                                             options.outer_vertex) == loops[outer].end())
    fail("outer boundary vertex " + std::to_string(options.outer_vertex) +
         " is not on a boundary loop");

  // Fill every other loop with a fan to its centroid. A loop runs with the faces on its left,
  // so the fan face over boundary edge a -> b is (b, a, centre).
  const int holes = static_cast<int>(loops.size()) - 1;
  size_t fan_faces = 0;
  for (size_t l = 0; l < loops.size(); ++l)
    if (l != outer) fan_faces += loops[l].size();
  PositionMatrix filled_V(V.rows() + holes, 3);
  filled_V.topRows(V.rows()) = V;
  TriangleMatrix filled_F(F.rows() + fan_faces, 3);
  filled_F.topRows(F.rows()) = F;
  int centre = static_cast<int>(V.rows()), row = static_cast<int>(F.rows());
  for (size_t l = 0; l < loops.size(); ++l) {
    if (l == outer) continue;
    const auto& loop = loops[l];
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (int v : loop) sum += V.row(v);
    filled_V.row(centre) = sum / static_cast<double>(loop.size());
    for (size_t k = 0; k < loop.size(); ++k)
      filled_F.row(row++) << loop[(k + 1) % loop.size()], loop[k], centre;
    ++centre;
  }
  Patch p = analyzePatch(filled_V, filled_F, nullptr);
  // Virtual centres were appended to the input, so they are the last local vertices.
  p.real_vertex_count = p.vertexCount() - holes;
  p.real_face_count = static_cast<int>(F.rows());
  p.holes_filled = holes;
  for (int v = p.real_vertex_count; v < p.vertexCount(); ++v) p.input_vertex[v] = -1;
  p.local_vertex.resize(V.rows());
  return p;
}

}  // namespace sdp
