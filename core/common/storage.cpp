#include "storage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "border.h"
#include "error.h"
#include "geometry.h"
#include "metrics.h"
#include "parallel.h"

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

// The layout's triangles as a mesh of their own: rows of layout.uv are its vertices, face_uv
// its faces. Per row the faces around it and the rows next to it; the border edges (an edge of
// one face only: chart outlines, holes, seams); per chart the flip rule of metrics.h.
struct UvMesh {
  explicit UvMesh(const Layout& layout) : face(layout.face_uv) {
    const int rows = static_cast<int>(layout.uv.rows());
    const int faces = layout.faceCount();
    used.assign(rows, 0);
    // Faces around each row, in face order, on every core (parallel.h).
    face_begin = bucketsInOrder(
        faces, rows,
        [&](int begin, int end, auto&& emit) {
          for (int f = begin; f < end; ++f)
            for (int k = 0; k < 3; ++k) emit(face(f, k), f);
        },
        [&](int total) { face_list.resize(total); },
        [&](int position, int f) { face_list[position] = f; });
    parallelFor(rows, 16384, [&](int first, int last, int) {
      for (int r = first; r < last; ++r) used[r] = face_begin[r + 1] > face_begin[r] ? 1 : 0;
    });
    // Per row, the other ends of the edges at it in its faces: an edge met once is a border
    // edge, and the distinct ends are the row's neighbours (a local sort per row, no global one).
    // Slices of rows on every core, joined in row order: the same lists on any machine.
    const int slots = faceSumSlots(rows);
    std::vector<Neighbours> slice(slots);
    parallelForSlots(rows, slots, [&](int begin, int end, int slot) {
      slice[slot] = neighboursOfRows(begin, end);
    });
    std::vector<size_t> listed(slots + 1, 0), bordered(slots + 1, 0);
    for (int s = 0; s < slots; ++s) {
      listed[s + 1] = listed[s] + slice[s].list.size();
      bordered[s + 1] = bordered[s] + slice[s].border.size();
    }
    neighbour_begin.assign(rows + 1, 0);
    for (const Neighbours& part : slice)
      for (size_t i = 0; i < part.count.size(); ++i)
        neighbour_begin[part.first_row + i + 1] =
            neighbour_begin[part.first_row + i] + part.count[i];
    neighbour_list.resize(listed[slots]);
    border.resize(bordered[slots]);
    parallelFor(slots, 1, [&](int first, int last, int) {
      for (int s = first; s < last; ++s) {
        std::copy(slice[s].list.begin(), slice[s].list.end(), neighbour_list.begin() + listed[s]);
        std::copy(slice[s].border.begin(), slice[s].border.end(), border.begin() + bordered[s]);
        slice[s] = Neighbours();
      }
    });
    chart = layout.chart.empty() ? std::vector<int>(faces, 0) : layout.chart;
  }

  // The neighbours and border edges of rows [begin, end).
  struct Neighbours {
    int first_row = 0;
    std::vector<int> count, list;  // per row its neighbours' count; all rows' neighbours
    std::vector<BorderEdge> border;
  };
  Neighbours neighboursOfRows(int begin, int end) const {
    Neighbours out;
    out.first_row = begin;
    out.count.reserve(end - begin);
    std::vector<int> ends;
    for (int r = begin; r < end; ++r) {
      ends.clear();
      for (int i = face_begin[r]; i < face_begin[r + 1]; ++i) {
        const int f = face_list[i];
        for (int k = 0; k < 3; ++k)
          if (face(f, k) == r) {
            ends.push_back(face(f, (k + 1) % 3));
            ends.push_back(face(f, (k + 2) % 3));
          }
      }
      std::sort(ends.begin(), ends.end());
      const size_t listed = out.list.size();
      for (size_t i = 0; i < ends.size();) {
        size_t j = i;
        while (j < ends.size() && ends[j] == ends[i]) ++j;
        out.list.push_back(ends[i]);
        if (j - i == 1 && r < ends[i]) out.border.push_back({r, ends[i]});
        i = j;
      }
      out.count.push_back(static_cast<int>(out.list.size() - listed));
    }
    return out;
  }

  const Triangles& face;
  std::vector<char> used;                            // the row is a corner of some face
  std::vector<int> face_begin, face_list;            // faces around each row
  std::vector<int> neighbour_begin, neighbour_list;  // rows sharing a face with each row
  std::vector<BorderEdge> border;
  std::vector<int> chart;  // per face
};

class StoredMap {
 public:
  StoredMap(const UvMesh& mesh, LocalUVs& uv, UVStorage storage)
      : mesh_(mesh), uv_(uv), rounding_(storage), text_(uv.size()) {
    // Faces' areas on every core, summed per chart in face order (the same on any machine).
    const int faces = static_cast<int>(mesh.face.rows());
    std::vector<double> face_area(faces);
    parallelFor(faces, 16384, [&](int first, int last, int) {
      for (int f = first; f < last; ++f) face_area[f] = area(uv, f);
    });
    std::vector<double> chart_area;
    for (int f = 0; f < faces; ++f) {
      const int c = mesh.chart[f];
      if (c >= static_cast<int>(chart_area.size())) chart_area.resize(c + 1, 0.0);
      chart_area[c] += face_area[f];
    }
    for (double total : chart_area) rule_.emplace_back(total);
    parallelFor(static_cast<int>(uv.size()), 16384, [&](int first, int last, int) {
      for (int r = first; r < last; ++r)
        if (mesh.used[r]) place(r, uv[r]);
    });
  }

  // Moves row r to the storable position nearest p.
  void place(int r, const Eigen::Vector2d& p) {
    uv_[r] = rounding_.memory(p);
    text_[r] = rounding_.text(p);
  }

  // How far face f is from degenerate as stored (memory and text); positive means valid.
  double margin(int f) const {
    const FlipRule& rule = rule_[mesh_.chart[f]];
    return std::min(rule.margin(area(uv_, f)), rule.margin(area(text_, f)));
  }
  bool valid(int f) const { return margin(f) > 0; }

  // The smallest margin of the faces around row r.
  double rowMargin(int r) const {
    double lowest = std::numeric_limits<double>::infinity();
    for (int i = mesh_.face_begin[r]; i < mesh_.face_begin[r + 1]; ++i)
      lowest = std::min(lowest, margin(mesh_.face_list[i]));
    return lowest;
  }

  // The centroid of r's neighbours; false when r has none.
  bool neighbourCentroid(int r, Eigen::Vector2d& centroid) const {
    const int count = mesh_.neighbour_begin[r + 1] - mesh_.neighbour_begin[r];
    if (count == 0) return false;
    centroid = Eigen::Vector2d::Zero();
    for (int i = mesh_.neighbour_begin[r]; i < mesh_.neighbour_begin[r + 1]; ++i)
      centroid += uv_[mesh_.neighbour_list[i]];
    centroid /= count;
    return true;
  }

  // Tries moving r a fraction of the way to the centroid of its neighbours; keeps the first
  // (longest) move that raises the smallest margin around r.
  bool improve(int r) {
    Eigen::Vector2d centroid;
    if (!neighbourCentroid(r, centroid)) return false;
    const Eigen::Vector2d origin = uv_[r], origin_text = text_[r];
    const double before = rowMargin(r);
    for (int halvings = 0; halvings <= 6; ++halvings) {
      const Eigen::Vector2d p = origin + std::ldexp(1.0, -halvings) * (centroid - origin);
      place(r, p);
      if (uv_[r] == origin) break;  // closer moves round to where r already is
      if (rowMargin(r) > before) return true;
    }
    uv_[r] = origin;
    text_[r] = origin_text;
    return false;
  }

  // Moves r towards the centroid of its neighbours, `fraction` of the way or less (halving),
  // keeping the first move that leaves every face around it valid: a border vertex moves into
  // its own faces, away from a border its rounding made it touch.
  bool separate(int r, double fraction) {
    Eigen::Vector2d centroid;
    if (!neighbourCentroid(r, centroid)) return false;
    const Eigen::Vector2d origin = uv_[r], origin_text = text_[r];
    for (int halvings = 0; halvings <= 6; ++halvings) {
      place(r, origin + std::ldexp(fraction, -halvings) * (centroid - origin));
      if (uv_[r] == origin) break;
      if (rowMargin(r) > 0) return true;
    }
    uv_[r] = origin;
    text_[r] = origin_text;
    return false;
  }

 private:
  double area(const LocalUVs& uv, int f) const {
    return signedArea(uv[mesh_.face(f, 0)], uv[mesh_.face(f, 1)], uv[mesh_.face(f, 2)]);
  }

  const UvMesh& mesh_;
  LocalUVs& uv_;
  Rounding rounding_;
  LocalUVs text_;
  std::vector<FlipRule> rule_;  // per chart
};

// Uniform scale and translation of the used rows into [0,1] on the longer side, centred.
void fitUnitSquare(const UvMesh& mesh, LocalUVs& uv) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d high = -low;
  for (size_t r = 0; r < uv.size(); ++r)
    if (mesh.used[r]) {
      low = low.cwiseMin(uv[r]);
      high = high.cwiseMax(uv[r]);
    }
  const double extent = (high - low).maxCoeff();
  if (!(extent > 0) || !std::isfinite(extent))
    throw ParameterizationError("the parameterization has no extent");
  const Eigen::Vector2d centre = 0.5 * (low + high);
  for (auto& p : uv) p = (p - centre) / extent + Eigen::Vector2d::Constant(0.5);
}

// Moves the corners of the faces that storage leaves flipped or degenerate (`bad`, replaced by
// those still so) until none are or the sweeps run out; marks the moved rows.
void repairDegenerateFaces(const UvMesh& mesh, StoredMap& map, std::vector<int>& bad,
                           std::vector<char>& moved, StorageCounts& counts) {
  // Active rows: the corners of the faces still degenerate, grown by one ring after each sweep
  // that fixed none of them (the tiny faces sit in a cluster that needs room around it).
  std::vector<char> active(moved.size(), 0);
  int rings = 0;
  constexpr int kMaxSweeps = 200, kMaxRings = 12;
  while (!bad.empty() && counts.rounds < kMaxSweeps) {
    ++counts.rounds;
    std::vector<int> rows;
    std::fill(active.begin(), active.end(), 0);
    for (int f : bad)
      for (int k = 0; k < 3; ++k)
        if (!active[mesh.face(f, k)]) {
          active[mesh.face(f, k)] = 1;
          rows.push_back(mesh.face(f, k));
        }
    for (int ring = 0; ring < rings; ++ring) {
      const size_t end = rows.size();
      for (size_t i = 0; i < end; ++i)
        for (int k = mesh.neighbour_begin[rows[i]]; k < mesh.neighbour_begin[rows[i] + 1]; ++k) {
          const int n = mesh.neighbour_list[k];
          if (!active[n]) {
            active[n] = 1;
            rows.push_back(n);
          }
        }
    }
    for (int r : rows)
      if (map.improve(r)) moved[r] = 1;
    std::vector<int> still;
    for (int f : bad)
      if (!map.valid(f)) still.push_back(f);
    // Moves may push a neighbouring face below zero: look at every face around the active set.
    for (int r : rows)
      for (int i = mesh.face_begin[r]; i < mesh.face_begin[r + 1]; ++i)
        if (!map.valid(mesh.face_list[i])) still.push_back(mesh.face_list[i]);
    std::sort(still.begin(), still.end());
    still.erase(std::unique(still.begin(), still.end()), still.end());
    if (still.size() >= bad.size()) rings = std::min(rings + 1, kMaxRings);
    bad.swap(still);
  }
}

// Whether the border is simple as stored, after moving the vertices of edges that meet.
bool separateBorder(const UvMesh& mesh, StoredMap& map, LocalUVs& uv, std::vector<char>& moved) {
  // Rounding can also make a border touch itself (two copies of a vertex split at a pinch,
  // a notch a hair's breadth wide): the vertices of the edges that meet move into their own
  // faces, by a 64th of the way to their neighbours' centroid and twice as far each sweep
  // they still meet (on the scans bench's 13.6M-face scan at 8192² in 6-decimal storage a
  // few vertices did, after minutes of work).
  constexpr int kSeparationSweeps = 10;
  for (int sweep = 0; sweep < kSeparationSweeps; ++sweep) {
    const std::vector<int> rows = verticesOfMeetingEdges(mesh.border, uv);
    if (rows.empty()) return true;  // the same test as edgesAreSimple's: not run twice
    const double fraction = std::ldexp(1.0, std::min(sweep, 6) - 6);
    for (int r : rows)
      if (map.separate(r, fraction)) moved[r] = 1;
  }
  return false;
}

}  // namespace

StorageCounts store(Layout& layout, const StoragePolicy& policy,
                    const std::function<void()>& step) {
  StorageCounts counts;
  const UvMesh mesh(layout);
  if (step) step();
  const int rows = static_cast<int>(layout.uv.rows());
  LocalUVs uv(rows);
  parallelFor(rows, 16384, [&](int first, int last, int) {
    for (int r = first; r < last; ++r) uv[r] = layout.uv.row(r).transpose();
  });
  if (policy.fit_unit_square) fitUnitSquare(mesh, uv);
  const int faces = layout.faceCount();
  StoredMap map(mesh, uv, policy.precision);
  // The faces storage leaves degenerate, found in slots on every core, listed in face order.
  const int slots = faceSumSlots(faces);
  std::vector<std::vector<int>> bad_in_slot(slots);
  parallelForSlots(faces, slots, [&](int begin, int end, int slot) {
    for (int f = begin; f < end; ++f)
      if (!map.valid(f)) bad_in_slot[slot].push_back(f);
  });
  std::vector<int> bad = joinedInOrder(bad_in_slot);
  counts.degenerate_faces = static_cast<int>(bad.size());
  if (step) step();

  std::vector<char> moved(uv.size(), 0);
  repairDegenerateFaces(mesh, map, bad, moved, counts);
  const char* name = uvStorageName(policy.precision);
  bool border_simple = false;
  if (step) step();
  if (bad.empty()) border_simple = separateBorder(mesh, map, uv, moved);
  counts.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  if (!bad.empty())
    throw ParameterizationError("no one-to-one map as stored (" + std::string(name) +
                                " texture coordinates): " + std::to_string(bad.size()) +
                                " faces stay flipped or degenerate after moving " +
                                std::to_string(counts.moved_vertices) +
                                " vertices (the map compresses them too much)");
  if (!border_simple && !edgesAreSimple(mesh.border, uv))
    throw ParameterizationError("no one-to-one map as stored (" + std::string(name) +
                                " texture coordinates): the rounded boundary touches itself");
  parallelFor(rows, 16384, [&](int first, int last, int) {
    for (int r = first; r < last; ++r) layout.uv.row(r) = uv[r].transpose();
  });
  return counts;
}

}  // namespace sdp
