#include "connectivity.h"

#include <algorithm>
#include <array>
#include <numeric>

#include "disjoint_sets.h"

namespace sdp {
namespace {

// The distinct values of `values`, counted.
int distinctCount(std::vector<int>& values) {
  std::sort(values.begin(), values.end());
  return static_cast<int>(std::unique(values.begin(), values.end()) - values.begin());
}

}  // namespace

bool Connectivity::isDisk() const {
  return components == 1 && boundary_loops == 1 && non_manifold_edges == 0 &&
         non_manifold_vertices == 0 && inconsistent_edges == 0 && degenerate_faces == 0 &&
         genus(0) == 0;
}

Connectivity analyzeConnectivity(const Triangles& F, int vertex_count) {
  Connectivity c;
  const int faces = static_cast<int>(F.rows());
  c.faces = faces;
  c.twin.assign(3 * static_cast<size_t>(faces), -1);
  auto from = [&](int h) { return F(h / 3, h % 3); };
  auto to = [&](int h) { return F(h / 3, (h % 3 + 1) % 3); };

  std::vector<char> used(vertex_count, 0);
  for (int f = 0; f < faces; ++f) {
    const int a = F(f, 0), b = F(f, 1), d = F(f, 2);
    if (a == b || b == d || a == d) ++c.degenerate_faces;
    used[a] = used[b] = used[d] = 1;
  }
  c.vertices = static_cast<int>(std::count(used.begin(), used.end(), 1));

  // Undirected edges: the half-edges sorted by their end points.
  struct Key {
    int low, high, half_edge;
  };
  std::vector<Key> keys;
  keys.reserve(3 * static_cast<size_t>(faces));
  for (int h = 0; h < 3 * faces; ++h)
    if (from(h) != to(h)) keys.push_back({std::min(from(h), to(h)), std::max(from(h), to(h)), h});
  std::sort(keys.begin(), keys.end(), [](const Key& x, const Key& y) {
    return x.low != y.low     ? x.low < y.low
           : x.high != y.high ? x.high < y.high
                              : x.half_edge < y.half_edge;
  });
  DisjointSets face_sets(faces), boundary_sets(vertex_count);
  std::vector<int> boundary_half_edges;
  std::vector<std::pair<size_t, size_t>> edge_groups;  // [begin, end) into keys
  for (size_t i = 0; i < keys.size();) {
    size_t j = i;
    while (j < keys.size() && keys[j].low == keys[i].low && keys[j].high == keys[i].high) ++j;
    edge_groups.emplace_back(i, j);
    const size_t count = j - i;
    if (count == 1) {
      ++c.boundary_edges;
      boundary_half_edges.push_back(keys[i].half_edge);
      boundary_sets.join(keys[i].low, keys[i].high);
    } else if (count == 2) {
      const int h = keys[i].half_edge, g = keys[i + 1].half_edge;
      c.twin[h] = g;
      c.twin[g] = h;
      if (from(h) == from(g)) ++c.inconsistent_edges;
      face_sets.join(h / 3, g / 3);
    } else {
      ++c.non_manifold_edges;
    }
    i = j;
  }
  c.edges = static_cast<int>(edge_groups.size());

  // Components, numbered in order of their first face.
  c.component.assign(faces, -1);
  std::vector<int> number_of_root(faces, -1);
  for (int f = 0; f < faces; ++f) {
    const int root = face_sets.find(f);
    if (number_of_root[root] < 0) number_of_root[root] = c.components++;
    c.component[f] = number_of_root[root];
  }

  // Boundary loops, each given to the component of one of its faces.
  c.component_loops.assign(c.components, 0);
  std::vector<char> loop_seen(vertex_count, 0);
  for (int h : boundary_half_edges) {
    const int root = boundary_sets.find(from(h));
    if (loop_seen[root]) continue;
    loop_seen[root] = 1;
    ++c.boundary_loops;
    ++c.component_loops[c.component[h / 3]];
  }

  // Per vertex, its faces in fans joined across two-face edges at the vertex: more than one fan
  // is a non-manifold vertex (two cones touching at a point). Also the components it is in.
  std::vector<int> face_begin(vertex_count + 1, 0), face_list(3 * static_cast<size_t>(faces));
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) ++face_begin[F(f, k) + 1];
  for (int v = 0; v < vertex_count; ++v) face_begin[v + 1] += face_begin[v];
  std::vector<int> fill(face_begin.begin(), face_begin.end() - 1);
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) face_list[fill[F(f, k)]++] = f;
  c.euler_characteristic.assign(c.components, 0);
  std::vector<int> local, parts;
  for (int v = 0; v < vertex_count; ++v) {
    const int begin = face_begin[v], end = face_begin[v + 1];
    if (begin == end) continue;
    local.assign(face_list.begin() + begin, face_list.begin() + end);
    DisjointSets fans(end - begin);
    auto indexOf = [&](int f) {
      return static_cast<int>(std::find(local.begin(), local.end(), f) - local.begin());
    };
    for (int i = 0; i < end - begin; ++i) {
      const int f = local[i];
      for (int k = 0; k < 3; ++k) {
        const int h = 3 * f + k;
        if ((from(h) == v || to(h) == v) && c.twin[h] >= 0) {
          const int other = indexOf(c.twin[h] / 3);
          if (other < end - begin) fans.join(i, other);
        }
      }
    }
    int fan_count = 0;
    for (int i = 0; i < end - begin; ++i) fan_count += fans.find(i) == i;
    if (fan_count > 1) ++c.non_manifold_vertices;
    parts.clear();
    for (int f : local) parts.push_back(c.component[f]);
    const int distinct = distinctCount(parts);
    for (int i = 0; i < distinct; ++i) ++c.euler_characteristic[parts[i]];  // V
  }
  for (const auto& [begin, end] : edge_groups) {  // - E, once per component the edge is in
    parts.clear();
    for (size_t i = begin; i < end; ++i) parts.push_back(c.component[keys[i].half_edge / 3]);
    const int distinct = distinctCount(parts);
    for (int i = 0; i < distinct; ++i) --c.euler_characteristic[parts[i]];
  }
  for (int f = 0; f < faces; ++f) ++c.euler_characteristic[c.component[f]];  // + F
  return c;
}

}  // namespace sdp
