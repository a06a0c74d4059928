// The small geometry every stage uses, written once.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "layout.h"
#include "patch.h"

namespace sdp {

constexpr double kPi = 3.14159265358979323846;

// The z of (a, 0) x (b, 0): twice the signed area of the triangle 0, a, b.
inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Signed area of the triangle abc: positive when counter-clockwise.
inline double signedArea(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                         const Eigen::Vector2d& c) {
  return 0.5 * cross2(b - a, c - a);
}

// The area of the 3D triangle abc.
inline double triangleArea3d(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  return 0.5 * (b - a).cross(c - a).norm();
}

// The 3D area of face f, of a patch or of indexed triangles.
inline double faceArea3d(const Patch& patch, int f) {
  const auto& t = patch.face[f];
  return triangleArea3d(patch.position[t[0]], patch.position[t[1]], patch.position[t[2]]);
}
inline double faceArea3d(const Positions& V, const Triangles& F, int f) {
  return triangleArea3d(V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
}

// The 3D area of the real faces (the user's, not the virtual hole fills).
inline double patchArea3d(const Patch& patch) {
  double area = 0;
  for (int f = 0; f < patch.real_face_count; ++f) area += faceArea3d(patch, f);
  return area;
}

// The signed UV area of the real faces.
inline double patchAreaUV(const Patch& patch, const std::vector<Eigen::Vector2d>& uv) {
  double area = 0;
  for (int f = 0; f < patch.real_face_count; ++f) {
    const auto& t = patch.face[f];
    area += signedArea(uv[t[0]], uv[t[1]], uv[t[2]]);
  }
  return area;
}

}  // namespace sdp
