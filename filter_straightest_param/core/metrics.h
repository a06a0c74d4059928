// SPEC §5: Sander et al. 2001 texture stretch, normalized so that 1.0 is isometric, and the
// flipped/degenerate face count that certifies a one-to-one map.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "patch.h"

namespace sdp {

struct FaceStretch {
  double l2 = 0;      // sqrt((a + c) / 2), infinite for a collapsed (zero-area) face
  double linf = 0;    // largest singular value of the 2D -> 3D map
  double area2d = 0;  // signed
  double area3d = 0;
};

// One triangle: 3D corners q, 2D corners p (same order).
FaceStretch faceStretch(const Eigen::Vector3d q[3], const Eigen::Vector2d p[3]);

struct StretchMetrics {
  double l2 = 0;                  // area-weighted L2 over the mesh, normalized
  double linf = 0;                // worst face, normalized
  int flipped_faces = 0;          // signed UV area <= tiny (flipped or degenerate)
  std::vector<double> face_l2;    // per face, normalized (same scale as l2)
  std::vector<double> vertex_l2;  // per vertex: area-weighted L2 of its faces, normalized
};

// UVs are per patch vertex. A face counts as flipped when its signed area is not above
// 1e-14 of the total (that includes degenerate faces a renderer cannot invert).
StretchMetrics stretchMetrics(const Patch& patch, const std::vector<Eigen::Vector2d>& uv);

}  // namespace sdp
