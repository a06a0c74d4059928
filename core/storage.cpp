#include "storage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "error.h"
#include "free_boundary.h"
#include "geometry.h"
#include "metrics.h"

namespace sdp {

namespace {

// Rounds coordinates to what the storage holds: `memory` is the value kept in the mesh, `text`
// (FloatAndSixDecimals) the 6 decimals the OBJ exporter writes of it; the two differ by under
// 3e-8 in the unit square, and a face must be positive in both.
// The nearest float. Through a volatile: GCC 12 at -O2 folded the plain double -> float ->
// double casts of this file away (seen in its assembly), which would skip the rounding.
double nearestFloat(double x) {
  volatile float f = static_cast<float>(x);
  return f;
}

class Rounding {
 public:
  explicit Rounding(UVStorage storage) : storage_(storage) {}

  double text(double x) const {
    // printf("%f") of the stored float gives back this text: a float lies within 3e-8 of it
    // for |x| < 8, well inside the half unit 5e-7 of the sixth decimal.
    return storage_ == UVStorage::FloatAndSixDecimals ? std::nearbyint(x * 1e6) / 1e6 : memory(x);
  }
  double memory(double x) const {
    switch (storage_) {
      case UVStorage::Double:
        return x;
      case UVStorage::Float:
        return nearestFloat(x);
      case UVStorage::FloatAndSixDecimals:
        return nearestFloat(std::nearbyint(x * 1e6) / 1e6);
    }
    return x;
  }
  Eigen::Vector2d memory(const Eigen::Vector2d& p) const {
    return Eigen::Vector2d(memory(p.x()), memory(p.y()));
  }
  Eigen::Vector2d text(const Eigen::Vector2d& p) const {
    return Eigen::Vector2d(text(p.x()), text(p.y()));
  }

 private:
  UVStorage storage_;
};

class StoredMap {
 public:
  StoredMap(const Patch& patch, LocalUVs& uv, UVStorage storage)
      : patch_(patch), uv_(uv), rounding_(storage), text_(uv.size()) {
    double total = 0;
    for (int f = 0; f < patch.real_face_count; ++f) {
      const auto& t = patch.face[f];
      total += signedArea(uv[t[0]], uv[t[1]], uv[t[2]]);
    }
    orientation_ = total < 0 ? -1.0 : 1.0;
    // The flip rule of metrics.h: positive by more than 1e-14 of the total.
    tiny_ = 1e-14 * std::abs(total);
    for (int v = 0; v < patch.real_vertex_count; ++v) place(v, uv[v]);
  }

  // Moves v to the storable position nearest p.
  void place(int v, const Eigen::Vector2d& p) {
    const Eigen::Vector2d memory = rounding_.memory(p), text = rounding_.text(p);
    uv_[v] = memory;
    text_[v] = text;
  }

  // How far face f is from degenerate as stored (memory and text); positive means valid.
  double margin(int f) const {
    const auto& t = patch_.face[f];
    const double memory = orientation_ * signedArea(uv_[t[0]], uv_[t[1]], uv_[t[2]]);
    const double text = orientation_ * signedArea(text_[t[0]], text_[t[1]], text_[t[2]]);
    return std::min(memory, text) - tiny_;
  }
  bool valid(int f) const { return margin(f) > 0; }

  // The smallest margin of the real faces around v.
  double vertexMargin(int v) const {
    double lowest = std::numeric_limits<double>::infinity();
    for (int k = patch_.ring_begin[v]; k < patch_.ring_begin[v + 1]; ++k) {
      const int f = patch_.ring_face[k];
      if (f >= 0 && f < patch_.real_face_count) lowest = std::min(lowest, margin(f));
    }
    return lowest;
  }

  // Tries moving v a fraction of the way to the centroid of its real neighbours; keeps the
  // first (longest) move that raises the smallest margin around v.
  bool improve(int v) {
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    int count = 0;
    for (int k = patch_.ring_begin[v]; k < patch_.ring_begin[v + 1]; ++k) {
      const int n = patch_.ring_vertex[k];
      if (n < patch_.real_vertex_count) {
        centroid += uv_[n];
        ++count;
      }
    }
    if (count == 0) return false;
    centroid /= count;
    const Eigen::Vector2d origin = uv_[v], origin_text = text_[v];
    const double before = vertexMargin(v);
    for (int halvings = 0; halvings <= 6; ++halvings) {
      const Eigen::Vector2d p = origin + std::ldexp(1.0, -halvings) * (centroid - origin);
      place(v, p);
      if (uv_[v] == origin) break;  // closer moves round to where v already is
      if (vertexMargin(v) > before) return true;
    }
    uv_[v] = origin;
    text_[v] = origin_text;
    return false;
  }

 private:
  const Patch& patch_;
  LocalUVs& uv_;
  Rounding rounding_;
  LocalUVs text_;
  double orientation_ = 1, tiny_ = 0;
};

}  // namespace

StorageCounts roundForStorage(const Patch& patch, LocalUVs& uv, UVStorage storage) {
  StorageCounts counts;
  if (storage == UVStorage::Double) return counts;
  StoredMap map(patch, uv, storage);
  std::vector<int> bad;
  for (int f = 0; f < patch.real_face_count; ++f)
    if (!map.valid(f)) bad.push_back(f);
  counts.degenerate_faces = static_cast<int>(bad.size());

  // Active vertices: the corners of the faces still degenerate, grown by one ring after each
  // sweep that fixed none of them (the tiny faces sit in a cluster that needs room around it).
  std::vector<char> moved(patch.real_vertex_count, 0), active(patch.real_vertex_count, 0);
  int rings = 0;
  constexpr int kMaxSweeps = 200, kMaxRings = 12;
  while (!bad.empty() && counts.rounds < kMaxSweeps) {
    ++counts.rounds;
    std::vector<int> vertices;
    std::fill(active.begin(), active.end(), 0);
    for (int f : bad)
      for (int v : patch.face[f])
        if (!active[v]) {
          active[v] = 1;
          vertices.push_back(v);
        }
    for (int ring = 0; ring < rings; ++ring) {
      const size_t end = vertices.size();
      for (size_t i = 0; i < end; ++i)
        for (int k = patch.ring_begin[vertices[i]]; k < patch.ring_begin[vertices[i] + 1]; ++k) {
          const int n = patch.ring_vertex[k];
          if (n < patch.real_vertex_count && !active[n]) {
            active[n] = 1;
            vertices.push_back(n);
          }
        }
    }
    for (int v : vertices)
      if (map.improve(v)) moved[v] = 1;
    std::vector<int> still;
    for (int f : bad)
      if (!map.valid(f)) still.push_back(f);
    // Moves may push a neighbouring face below zero: look at every face around the active set.
    for (int v : vertices)
      for (int k = patch.ring_begin[v]; k < patch.ring_begin[v + 1]; ++k) {
        const int f = patch.ring_face[k];
        if (f >= 0 && f < patch.real_face_count && !map.valid(f)) still.push_back(f);
      }
    std::sort(still.begin(), still.end());
    still.erase(std::unique(still.begin(), still.end()), still.end());
    if (still.size() >= bad.size()) rings = std::min(rings + 1, kMaxRings);
    bad.swap(still);
  }
  counts.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  const char* name = uvStorageName(storage);
  if (!bad.empty())
    throw ParameterizationError("no one-to-one map as stored (" + std::string(name) +
                                " texture coordinates): " + std::to_string(bad.size()) +
                                " faces stay flipped or degenerate after moving " +
                                std::to_string(counts.moved_vertices) +
                                " vertices (the map compresses them too much)");
  if (!boundaryIsSimple(patch, uv))
    throw ParameterizationError("no one-to-one map as stored (" + std::string(name) +
                                " texture coordinates): the rounded boundary touches itself");
  return counts;
}

}  // namespace sdp
