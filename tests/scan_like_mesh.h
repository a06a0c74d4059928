// A scan-like mesh made from a clean closed one, as scanners hand meshes over before any
// cleaning (the scans bench's recipe, bench/scan_meshes.py, small enough for the suite): 1-to-4
// midpoint subdivision, noise along the vertex normals (sigma x the mean edge length), small
// holes (a random face with every face at its vertices removed), and floating debris (two-
// triangle quads about 3 edge lengths across). Seeded, with its own generator, so the same mesh
// comes out with every standard library.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "bench/midpoint_subdivision.h"  // the benches' own 1-to-4 subdivision

namespace sdp::test {

struct ScanLikeOptions {
  int subdivisions = 3;
  double sigma = 0.15;  // noise, in mean edge lengths
  int holes = 60;
  int debris = 30;
  std::uint64_t seed = 1;
};

class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return (next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
  double normal() {                                                         // Box-Muller
    const double u = 1.0 - uniform(), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
  }

 private:
  std::uint64_t state_;
};

inline void makeScanLike(Positions& V, Triangles& F, const ScanLikeOptions& o) {
  for (int i = 0; i < o.subdivisions; ++i) sdp::bench::subdivideMidpoint(V, F);
  double edges = 0;
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) edges += (V.row(F(f, k)) - V.row(F(f, (k + 1) % 3))).norm();
  const double edge = edges / (3.0 * F.rows());
  // Separate streams, so that sigma does not move the holes or the debris.
  SplitMix64 noise(o.seed * 3), holes(o.seed * 3 + 1), debris(o.seed * 3 + 2);
  if (o.sigma > 0) {
    Positions normals = Positions::Zero(V.rows(), 3);
    for (int f = 0; f < F.rows(); ++f) {
      const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
      const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();
      for (int k = 0; k < 3; ++k) normals.row(F(f, k)) += n;
    }
    for (int v = 0; v < V.rows(); ++v) {
      const double length = normals.row(v).norm();
      const double step = o.sigma * edge * noise.normal();
      if (length > 0) V.row(v) += normals.row(v) / length * step;
    }
  }
  std::vector<char> gone(V.rows(), 0);
  for (int h = 0; h < o.holes; ++h) {
    const int f = static_cast<int>(holes.next() % F.rows());
    for (int k = 0; k < 3; ++k) gone[F(f, k)] = 1;
  }
  std::vector<int> renumber(V.rows(), -1);
  std::vector<Eigen::RowVector3d> points;
  std::vector<Eigen::RowVector3i> faces;
  for (int f = 0; f < F.rows(); ++f) {
    if (gone[F(f, 0)] || gone[F(f, 1)] || gone[F(f, 2)]) continue;
    Eigen::RowVector3i face;
    for (int k = 0; k < 3; ++k) {
      int& index = renumber[F(f, k)];
      if (index < 0) index = static_cast<int>(points.size()), points.push_back(V.row(F(f, k)));
      face[k] = index;
    }
    faces.push_back(face);
  }
  const Eigen::RowVector3d low = V.colwise().minCoeff(), high = V.colwise().maxCoeff();
  for (int d = 0; d < o.debris; ++d) {
    Eigen::Vector3d centre, u, w;
    for (int k = 0; k < 3; ++k) centre[k] = low[k] + debris.uniform() * (high[k] - low[k]);
    for (int k = 0; k < 3; ++k) u[k] = debris.normal();
    for (int k = 0; k < 3; ++k) w[k] = debris.normal();
    u.normalize();
    w = u.cross(w).normalized();
    const int base = static_cast<int>(points.size());
    for (const auto& [su, sw] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
      points.push_back((centre + 1.5 * edge * (su * u + sw * w)).transpose());
    faces.emplace_back(base, base + 1, base + 2);
    faces.emplace_back(base, base + 2, base + 3);
  }
  V.resize(points.size(), 3);
  for (size_t v = 0; v < points.size(); ++v) V.row(v) = points[v];
  F.resize(faces.size(), 3);
  for (size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f];
}

// Writes the mesh as text OFF (every reader of the product and MeshLab takes it).
inline bool writeOff(const std::string& path, const Positions& V, const Triangles& F) {
  std::ofstream out(path);
  out.precision(17);
  out << "OFF\n" << V.rows() << " " << F.rows() << " 0\n";
  for (int v = 0; v < V.rows(); ++v) out << V(v, 0) << " " << V(v, 1) << " " << V(v, 2) << "\n";
  for (int f = 0; f < F.rows(); ++f)
    out << "3 " << F(f, 0) << " " << F(f, 1) << " " << F(f, 2) << "\n";
  return static_cast<bool>(out);
}

}  // namespace sdp::test
