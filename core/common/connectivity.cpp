#include "connectivity.h"

#include <algorithm>
#include <array>
#include <numeric>

#include "disjoint_sets.h"
#include "parallel.h"

namespace sdp {
namespace {

// The distinct values of `values`, counted.
int distinctCount(std::vector<int>& values) {
  std::sort(values.begin(), values.end());
  return static_cast<int>(std::unique(values.begin(), values.end()) - values.begin());
}

}  // namespace

bool Connectivity::isDisk() const {
  return diskHoles() == 0;
}

int Connectivity::diskHoles() const {
  const bool disk_like = components == 1 && boundary_loops >= 1 && non_manifold_edges == 0 &&
                         non_manifold_vertices == 0 && inconsistent_edges == 0 &&
                         degenerate_faces == 0 && genus(0) == 0;
  return disk_like ? boundary_loops - 1 : -1;
}

namespace {

// The steps of analyzeConnectivity, in order, over one mesh: each fills its part of `c`.
class ConnectivityAnalysis {
 public:
  ConnectivityAnalysis(const Triangles& F, int vertex_count)
      : F_(F),
        faces_(static_cast<int>(F.rows())),
        vertex_count_(vertex_count),
        face_sets_(faces_),
        boundary_sets_(vertex_count) {
    c_.faces = faces_;
    c_.twin.assign(3 * static_cast<size_t>(faces_), -1);
  }

  Connectivity run(const std::function<void()>& step) {
    auto stepped = [&] {
      if (step) step();
    };
    countVertices();
    stepped();  // a step every second or two at 13M faces, for a front end's progress bar
    sortEdges();
    stepped();
    pairEdges();
    // The two union-finds, faces into components and corners into fans, are independent: one
    // on each core (each set is named by its least member, so the order of joins is free).
    parallelForAlongside(
        1, 1,
        [&] {
          numberComponents();
          countBoundaryLoops();
        },
        [&](int, int, int) { joinCornersIntoFans(); });
    stepped();
    fansAndEulerCharacteristics();
    return std::move(c_);
  }

 private:
  int from(int h) const { return F_(h / 3, h % 3); }
  int to(int h) const { return F_(h / 3, (h % 3 + 1) % 3); }

  void countVertices() {
    std::vector<char> used(vertex_count_, 0);
    for (int f = 0; f < faces_; ++f) {
      const int a = F_(f, 0), b = F_(f, 1), d = F_(f, 2);
      if (a == b || b == d || a == d) ++c_.degenerate_faces;
      used[a] = used[b] = used[d] = 1;
    }
    c_.vertices = static_cast<int>(std::count(used.begin(), used.end(), 1));
  }

  void sortEdges() { keys_ = sortedHalfEdges(F_, vertex_count_); }

  // One edge per run of equal keys: one half-edge is a boundary edge, two are twins (the same
  // direction twice: inconsistent orientation), more are a non-manifold edge. In slots of
  // whole runs, one per core, their lists joined in slot order: the same for any count. The
  // keys are freed after: the rest needs only the twins, the boundary and the few non-manifold
  // runs (at 13M faces the keys are half a gigabyte, and the face graph is built alongside).
  void pairEdges() {
    struct Counts {
      int edges = 0, inconsistent = 0, non_manifold = 0;
    };
    const size_t keys = keys_.size();
    const int slots = static_cast<int>(std::clamp<size_t>(keys / 65536, 1, parallelWorkers()));
    std::vector<size_t> slot_begin(slots + 1, keys);
    for (int s = 0; s < slots; ++s) {
      size_t i = keys * s / slots;  // moved on to the start of a run
      while (i > 0 && i < keys && keys_[i].low == keys_[i - 1].low &&
             keys_[i].high == keys_[i - 1].high)
        ++i;
      slot_begin[s] = std::max(i, s > 0 ? slot_begin[s - 1] : 0);
    }
    std::vector<Counts> counts(slots);
    // Per slot: its boundary half-edges; each non-manifold run's half-edges, then -1.
    std::vector<std::vector<int>> boundary(slots), non_manifold(slots);
    parallelFor(slots, 1, [&](int first, int last, int) {
      for (int s = first; s < last; ++s) {
        Counts& out = counts[s];
        for (size_t i = slot_begin[s]; i < slot_begin[s + 1];) {
          size_t j = i + 1;
          while (j < keys && keys_[j].low == keys_[i].low && keys_[j].high == keys_[i].high) ++j;
          ++out.edges;
          if (j - i == 1) {
            boundary[s].push_back(keys_[i].half_edge);
          } else if (j - i == 2) {
            const int h = keys_[i].half_edge, g = keys_[i + 1].half_edge;
            c_.twin[h] = g;
            c_.twin[g] = h;
            if (from(h) == from(g)) ++out.inconsistent;
          } else {
            ++out.non_manifold;
            for (size_t k = i; k < j; ++k) non_manifold[s].push_back(keys_[k].half_edge);
            non_manifold[s].push_back(-1);
          }
          i = j;
        }
      }
    });
    boundary_half_edges_ = joinedInOrder(boundary);
    non_manifold_runs_ = joinedInOrder(non_manifold);
    for (const Counts& out : counts) {
      c_.edges += out.edges;
      c_.inconsistent_edges += out.inconsistent;
      c_.non_manifold_edges += out.non_manifold;
    }
    c_.boundary_edges = static_cast<int>(boundary_half_edges_.size());
    keys_ = std::vector<HalfEdgeKey>();
  }

  // Components (faces joined across two-face edges), numbered in order of their first face.
  void numberComponents() {
    for (int h = 0; h < 3 * faces_; ++h)
      if (c_.twin[h] > h) face_sets_.join(h / 3, c_.twin[h] / 3);
    c_.component.assign(faces_, -1);
    std::vector<int> number_of_root(faces_, -1);
    for (int f = 0; f < faces_; ++f) {
      const int root = face_sets_.find(f);
      if (number_of_root[root] < 0) number_of_root[root] = c_.components++;
      c_.component[f] = number_of_root[root];
    }
  }

  // Boundary loops, each given to the component of one of its faces.
  void countBoundaryLoops() {
    for (int h : boundary_half_edges_) boundary_sets_.join(from(h), to(h));
    c_.component_loops.assign(c_.components, 0);
    std::vector<char> loop_seen(vertex_count_, 0);
    for (int h : boundary_half_edges_) {
      const int root = boundary_sets_.find(from(h));
      if (loop_seen[root]) continue;
      loop_seen[root] = 1;
      ++c_.boundary_loops;
      ++c_.component_loops[c_.component[h / 3]];
    }
  }

  // The corner of face f at vertex v (its first, for a face that repeats v).
  int cornerOf(int f, int v) const { return 3 * f + (F_(f, 0) == v ? 0 : F_(f, 1) == v ? 1 : 2); }

  // A vertex's faces form fans joined across two-face edges at it: its corners (3 f + k at
  // F(f, k)) joined across every twin pair at both of the pair's ends (and a face's corners at one
  // vertex, when it repeats it) are its fans, one set each, named by its least corner. One pass
  // over the half-edges, not a search per vertex among its faces (a third of the time at a
  // million faces).
  void joinCornersIntoFans() {
    corners_ = DisjointSets(3 * faces_);
    for (int h = 0; h < 3 * faces_; ++h) {
      const int t = c_.twin[h];
      if (t < h) continue;  // each pair once; -1: no twin
      const int f = h / 3, g = t / 3;
      corners_.join(cornerOf(f, from(h)), cornerOf(g, from(h)));
      corners_.join(cornerOf(f, to(h)), cornerOf(g, to(h)));
    }
    for (int f = 0; f < faces_; ++f)
      for (int k = 0; k < 3; ++k)
        for (int l = k + 1; l < 3; ++l)
          if (F_(f, k) == F_(f, l)) corners_.join(3 * f + k, 3 * f + l);
  }

  // Non-manifold vertices and the Euler characteristic V - E + F of each component (a vertex or
  // edge shared by components counts once in each), from the fans.
  void fansAndEulerCharacteristics() {
    DisjointSets& corners = corners_;
    // Per vertex its fans, counted, and one of them (its component stands for the vertex's when
    // it has one fan: a fan lies in one component).
    std::vector<int> fans(vertex_count_, 0), some_fan(vertex_count_, -1);
    for (int c = 0; c < 3 * faces_; ++c) {
      if (corners.find(c) != c) continue;
      const int v = F_(c / 3, c % 3);
      ++fans[v];
      some_fan[v] = c;
    }
    c_.euler_characteristic.assign(c_.components, 0);
    std::vector<std::pair<int, int>> shared;  // (vertex, component) at vertices of several fans
    for (int v = 0; v < vertex_count_; ++v) {
      if (fans[v] == 0) continue;
      if (fans[v] == 1) {
        ++c_.euler_characteristic[c_.component[some_fan[v] / 3]];  // V
        continue;
      }
      ++c_.non_manifold_vertices;
    }
    for (int c = 0; c < 3 * faces_; ++c) {
      if (corners.find(c) != c) continue;
      const int v = F_(c / 3, c % 3);
      if (fans[v] > 1) shared.emplace_back(v, c_.component[c / 3]);
    }
    std::sort(shared.begin(), shared.end());
    shared.erase(std::unique(shared.begin(), shared.end()), shared.end());
    for (const auto& [v, component] : shared) ++c_.euler_characteristic[component];  // V
    // - E, once per component the edge is in: a two-face edge's faces are twins, so joined into
    // one component; a boundary edge has one face; a non-manifold edge's faces may lie in several.
    for (int h = 0; h < 3 * faces_; ++h)
      if (c_.twin[h] > h) --c_.euler_characteristic[c_.component[h / 3]];
    for (int h : boundary_half_edges_) --c_.euler_characteristic[c_.component[h / 3]];
    std::vector<int> parts;
    for (size_t i = 0; i < non_manifold_runs_.size(); ++i) {
      parts.clear();
      for (; non_manifold_runs_[i] >= 0; ++i)
        parts.push_back(c_.component[non_manifold_runs_[i] / 3]);
      const int distinct = distinctCount(parts);
      for (int k = 0; k < distinct; ++k) --c_.euler_characteristic[parts[k]];
    }
    for (int f = 0; f < faces_; ++f) ++c_.euler_characteristic[c_.component[f]];  // + F
  }

  const Triangles& F_;
  const int faces_, vertex_count_;
  Connectivity c_;
  std::vector<HalfEdgeKey> keys_;  // undirected edges: the half-edges sorted by their ends
  std::vector<int> boundary_half_edges_;
  std::vector<int> non_manifold_runs_;  // each non-manifold edge's half-edges, then -1
  DisjointSets face_sets_, boundary_sets_, corners_{0};
};

}  // namespace

Connectivity analyzeConnectivity(const Triangles& F, int vertex_count,
                                 const std::function<void()>& step) {
  return ConnectivityAnalysis(F, vertex_count).run(step);
}

std::vector<HalfEdgeKey> sortedHalfEdges(const Triangles& F, int vertex_count) {
  // By lower end with a counting sort on every core (a comparison sort of every half-edge was
  // seconds at millions of faces), then each vertex's few half-edges by (high, half_edge).
  auto from = [&](int h) { return F(h / 3, h % 3); };
  auto to = [&](int h) { return F(h / 3, (h % 3 + 1) % 3); };
  std::vector<HalfEdgeKey> keys;
  auto placed = [&](int position, int h) {
    keys[position] = {std::min(from(h), to(h)), std::max(from(h), to(h)), h};
  };
  auto halfEdges = [&](int first, int last, auto&& emit) {
    for (int h = first; h < last; ++h)  // in order: each run starts sorted by half-edge
      if (from(h) != to(h)) emit(std::min(from(h), to(h)), h);
  };
  const std::vector<int> begin = bucketsInOrder(
      3 * static_cast<int>(F.rows()), vertex_count, halfEdges,
      [&](int total) { keys.resize(total); }, placed);
  // Each vertex's run on its own: on every core, the same keys.
  parallelFor(vertex_count, 16384, [&](int first_vertex, int last_vertex, int) {
    for (int v = first_vertex; v < last_vertex; ++v) {
      HalfEdgeKey* first = keys.data() + begin[v];
      HalfEdgeKey* last = keys.data() + begin[v + 1];
      if (last - first > 32) {
        std::sort(first, last, [](const HalfEdgeKey& x, const HalfEdgeKey& y) {
          return x.high != y.high ? x.high < y.high : x.half_edge < y.half_edge;
        });
        continue;
      }
      for (HalfEdgeKey* i = first + 1; i < last; ++i)  // insertion: stable, in half-edge order
        for (HalfEdgeKey* j = i; j > first && j->high < (j - 1)->high; --j) std::swap(*j, *(j - 1));
    }
  });
  return keys;
}

std::vector<HalfEdgeKey> borderHalfEdges(const Triangles& F, int vertex_count) {
  std::vector<HalfEdgeKey> keys = sortedHalfEdges(F, vertex_count);
  size_t kept = 0;
  forEachEdgeRun(keys, [&](size_t i, size_t j) {
    if (j - i == 1) keys[kept++] = keys[i];
  });
  keys.resize(kept);
  return keys;
}

std::vector<char> coherentOrientation(const Triangles& F, const Connectivity& connectivity) {
  const int faces = static_cast<int>(F.rows());
  std::vector<char> turn(faces, 0), seen(faces, 0);
  std::vector<int> piece;
  for (int start = 0; start < faces; ++start) {
    if (seen[start]) continue;
    piece.assign(1, start);
    seen[start] = 1;
    int turned = 0;
    for (size_t i = 0; i < piece.size(); ++i) {
      const int f = piece[i];
      for (int k = 0; k < 3; ++k) {
        const int g = connectivity.twin[3 * f + k];
        if (g < 0 || seen[g / 3]) continue;
        // The two faces agree when the twin runs from this half-edge's end to its start.
        const bool agree = F(g / 3, g % 3) == F(f, (k + 1) % 3);
        turn[g / 3] = static_cast<char>(turn[f] ^ !agree);
        turned += turn[g / 3];
        seen[g / 3] = 1;
        piece.push_back(g / 3);
      }
    }
    if (2 * turned > static_cast<int>(piece.size()))
      for (int f : piece) turn[f] = static_cast<char>(!turn[f]);
  }
  return turn;
}

}  // namespace sdp
