#include "metrics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry.h"
#include "parallel.h"

namespace sdp {

FaceStretch faceStretch(const Eigen::Vector3d q[3], const Eigen::Vector2d p[3]) {
  FaceStretch r;
  const double s1 = p[0].x(), t1 = p[0].y(), s2 = p[1].x(), t2 = p[1].y(), s3 = p[2].x(),
               t3 = p[2].y();
  r.area2d = 0.5 * ((s2 - s1) * (t3 - t1) - (s3 - s1) * (t2 - t1));
  r.area3d = triangleArea3d(q[0], q[1], q[2]);
  // A flipped face still has a well-defined stretch (the signs cancel), which keeps peers'
  // folded maps comparable; only a collapsed face stretches infinitely.
  if (!(r.area2d != 0) || !std::isfinite(r.area2d)) {
    r.l2 = r.linf = std::numeric_limits<double>::infinity();
    return r;
  }
  const Eigen::Vector3d Ss =
      (q[0] * (t2 - t3) + q[1] * (t3 - t1) + q[2] * (t1 - t2)) / (2 * r.area2d);
  const Eigen::Vector3d St =
      (q[0] * (s3 - s2) + q[1] * (s1 - s3) + q[2] * (s2 - s1)) / (2 * r.area2d);
  const double a = Ss.dot(Ss), b = Ss.dot(St), c = St.dot(St);
  r.l2 = std::sqrt((a + c) / 2);
  r.linf = std::sqrt(((a + c) + std::sqrt((a - c) * (a - c) + 4 * b * b)) / 2);
  return r;
}

namespace {

// The whole map's measures from its faces' stretch: a face is flipped by its chart's rule
// (chart_area[chart_of(f)] is that chart's signed UV area), and L2 and L-infinity are normalized
// once by sqrt(sum of |chart areas| / 3D area).
template <class ChartOf>
void summarize(const std::vector<FaceStretch>& stretch, const std::vector<double>& chart_area,
               double area3d, ChartOf&& chart_of, StretchMetrics& m) {
  std::vector<FlipRule> rule;
  double area2d = 0, weighted = 0, worst = 0;
  for (double total : chart_area) {
    rule.emplace_back(total);
    area2d += std::abs(total);
  }
  const int faces = static_cast<int>(stretch.size());
  for (int f = 0; f < faces; ++f) {
    if (rule[chart_of(f)].flipped(stretch[f].area2d)) ++m.flipped_faces;
    weighted += stretch[f].l2 * stretch[f].l2 * stretch[f].area3d;
    worst = std::max(worst, stretch[f].linf);
  }
  // Stretch scales with 1/size of the UV layout; this factor makes 1.0 the isometric optimum.
  const double normalize = std::sqrt(area2d / area3d);
  m.l2 = std::sqrt(weighted / area3d) * normalize;
  m.linf = worst * normalize;
  m.face_l2.resize(faces);
  for (int f = 0; f < faces; ++f) m.face_l2[f] = stretch[f].l2 * normalize;
}

}  // namespace

namespace {

// The fill faces of holes turned inside out: seen from its fill, the hole's border runs against
// the real faces (the sum of the fill's signed areas is the border polygon's own, wherever the
// virtual centre lies, and has the other sign or none). The faces around such a hole then cover
// it a second time though none of them is flipped and no border edges cross: a refinement step
// can carry a small hole through itself (a 192-face chart of the truck with two 5-edge holes).
int invertedHoleFaces(const Patch& patch, const std::vector<Eigen::Vector2d>& uv,
                      double real_area) {
  if (patch.holes_filled == 0) return 0;
  const int centres = patch.vertexCount() - patch.real_vertex_count;
  std::vector<double> area(centres, 0.0);
  std::vector<int> fill_faces(centres, 0);
  for (int f = patch.real_face_count; f < patch.faceCount(); ++f) {
    const auto& t = patch.face[f];
    for (int v : t)
      if (patch.isVirtual(v)) {
        area[v - patch.real_vertex_count] += signedArea(uv[t[0]], uv[t[1]], uv[t[2]]);
        ++fill_faces[v - patch.real_vertex_count];
      }
  }
  int inverted = 0;
  for (int h = 0; h < centres; ++h)
    if (!(area[h] * real_area > 0)) inverted += fill_faces[h];
  return inverted;
}

}  // namespace

StretchMetrics stretchMetrics(const Patch& patch, const std::vector<Eigen::Vector2d>& uv) {
  const int faces = patch.real_face_count;  // virtual hole fills do not count
  StretchMetrics m;
  std::vector<FaceStretch> stretch(faces);
  // Fixed ranges of about 16k faces, their area sums added in order: the same total whatever
  // the number of cores (parallel.h).
  const int slots = faceSumSlots(faces);
  std::vector<Eigen::Vector2d> area_sums(slots, Eigen::Vector2d::Zero());
  parallelForSlots(faces, slots, [&](int first, int last, int slot) {
    Eigen::Vector2d sums = Eigen::Vector2d::Zero();
    for (int f = first; f < last; ++f) {
      const auto& t = patch.face[f];
      const Eigen::Vector3d q[3] = {patch.position[t[0]], patch.position[t[1]],
                                    patch.position[t[2]]};
      const Eigen::Vector2d p[3] = {uv[t[0]], uv[t[1]], uv[t[2]]};
      stretch[f] = faceStretch(q, p);
      sums += Eigen::Vector2d(stretch[f].area2d, stretch[f].area3d);
    }
    area_sums[slot] = sums;
  });
  double area2d = 0, area3d = 0;
  for (const Eigen::Vector2d& sums : area_sums) area2d += sums.x(), area3d += sums.y();
  summarize(
      stretch, {area2d}, area3d, [](int) { return 0; }, m);
  // A hole turned inside out folds the map as a flipped face does: its fill's faces count.
  m.flipped_faces += invertedHoleFaces(patch, uv, area2d);

  std::vector<double> vertex_sum(patch.vertexCount(), 0.0), vertex_area(patch.vertexCount(), 0.0);
  for (int f = 0; f < faces; ++f)
    for (int v : patch.face[f]) {
      vertex_sum[v] += m.face_l2[f] * m.face_l2[f] * stretch[f].area3d;
      vertex_area[v] += stretch[f].area3d;
    }
  m.vertex_l2.resize(patch.vertexCount());
  for (int v = 0; v < patch.vertexCount(); ++v)
    m.vertex_l2[v] = vertex_area[v] > 0 ? std::sqrt(vertex_sum[v] / vertex_area[v]) : 1.0;
  return m;
}

StretchMetrics layoutStretch(const Positions& V, const Triangles& F, const Layout& layout) {
  const int faces = static_cast<int>(F.rows());
  StretchMetrics m;
  std::vector<FaceStretch> stretch(faces);
  std::vector<double> chart_area;
  double area3d = 0;
  auto chartOf = [&](int f) { return layout.chart.empty() ? 0 : layout.chart[f]; };
  // Both frames centred and scaled to unit size first (the normalized stretch does not change):
  // a mesh at 1e-90 or 1e90 would otherwise underflow or overflow in the squared lengths.
  Eigen::RowVector3d low3 = Eigen::RowVector3d::Constant(std::numeric_limits<double>::max());
  Eigen::RowVector3d high3 = -low3;
  Eigen::RowVector2d low2 = Eigen::RowVector2d::Constant(std::numeric_limits<double>::max());
  Eigen::RowVector2d high2 = -low2;
  for (int f = 0; f < faces; ++f)
    for (int k = 0; k < 3; ++k) {
      low3 = low3.cwiseMin(V.row(F(f, k)));
      high3 = high3.cwiseMax(V.row(F(f, k)));
      low2 = low2.cwiseMin(layout.corner(f, k));
      high2 = high2.cwiseMax(layout.corner(f, k));
    }
  const double size3 = std::max((high3 - low3).maxCoeff(), std::numeric_limits<double>::min());
  const double size2 = std::max((high2 - low2).maxCoeff(), std::numeric_limits<double>::min());
  const Eigen::RowVector3d centre3 = 0.5 * (low3 + high3);
  const Eigen::RowVector2d centre2 = 0.5 * (low2 + high2);
  // Each face on its own, in parallel; the sums below in face order (the same on any cores).
  parallelFor(faces, 16384, [&](int first, int last, int) {
    for (int f = first; f < last; ++f) {
      Eigen::Vector3d q[3];
      Eigen::Vector2d p[3];
      for (int k = 0; k < 3; ++k) {
        q[k] = ((V.row(F(f, k)) - centre3) / size3).transpose();
        p[k] = ((layout.corner(f, k) - centre2) / size2).transpose();
      }
      stretch[f] = faceStretch(q, p);
    }
  });
  for (int f = 0; f < faces; ++f) {
    const int c = chartOf(f);
    if (c >= static_cast<int>(chart_area.size())) chart_area.resize(c + 1, 0.0);
    chart_area[c] += stretch[f].area2d;
    area3d += stretch[f].area3d;
  }
  summarize(stretch, chart_area, area3d, chartOf, m);
  return m;
}

bool hasFlippedFace(const Patch& patch, const std::vector<Eigen::Vector2d>& uv) {
  const int faces = patch.real_face_count;
  // With no face, the empty range's largest area (-inf) would read as flipped.
  if (faces == 0) return false;
  // One pass: per fixed range (as in stretchMetrics) the total signed area and the smallest and
  // largest face's; the rule's tiny area and side follow from the total, summed in range order.
  const int slots = faceSumSlots(faces);
  struct Range {
    double total = 0, least = std::numeric_limits<double>::infinity();
    double most = -std::numeric_limits<double>::infinity();
    bool not_a_number = false;
  };
  std::vector<Range> ranges(slots);
  parallelForSlots(faces, slots, [&](int first, int last, int slot) {
    Range r;
    for (int f = first; f < last; ++f) {
      const auto& t = patch.face[f];
      const double area = signedArea(uv[t[0]], uv[t[1]], uv[t[2]]);
      r.total += area;
      r.least = std::min(r.least, area);
      r.most = std::max(r.most, area);
      r.not_a_number |= std::isnan(area);
    }
    ranges[slot] = r;
  });
  Range all;
  for (const Range& r : ranges) {
    all.total += r.total;
    all.least = std::min(all.least, r.least);
    all.most = std::max(all.most, r.most);
    all.not_a_number |= r.not_a_number;
  }
  const FlipRule rule(all.total);
  // The rule's margin is monotone in the area: the face nearest the wrong side decides.
  return all.not_a_number || rule.flipped(all.least) || rule.flipped(all.most) ||
         invertedHoleFaces(patch, uv, all.total) > 0;
}

}  // namespace sdp
