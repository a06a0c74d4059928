// docs/method.md §5: Sander et al. 2001 texture stretch, normalized so that 1.0 is isometric, and
// the flipped/degenerate face count that certifies a one-to-one map.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "layout.h"
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
  int flipped_faces = 0;          // signed UV area <= tiny (flipped or degenerate); with holes,
                                  // also the fill faces of a hole turned inside out
  std::vector<double> face_l2;    // per face, normalized (same scale as l2)
  std::vector<double> vertex_l2;  // per vertex: area-weighted L2 of its faces, normalized
};

// The flip rule: a face counts as flipped unless its signed UV area lies on the layout's
// majority side by more than 1e-14 of the total (so degenerate faces, which a renderer cannot
// invert, count too). A mirrored layout is still one-to-one; our own maps are counter-clockwise.
class FlipRule {
 public:
  explicit FlipRule(double total_signed_area)
      : orientation_(total_signed_area < 0 ? -1.0 : 1.0),
        tiny_(1e-14 * (total_signed_area < 0 ? -total_signed_area : total_signed_area)) {}
  bool flipped(double signed_area) const { return !(margin(signed_area) > 0); }
  // How far a face is from flipped (positive: valid).
  double margin(double signed_area) const { return orientation_ * signed_area - tiny_; }

 private:
  double orientation_, tiny_;
};

// UVs are per patch vertex; flipped faces by FlipRule.
StretchMetrics stretchMetrics(const Patch& patch, const std::vector<Eigen::Vector2d>& uv);

// The same measures of a layout on the input triangles (V, F): per face its corners' rows, the
// flip rule per chart, one normalization over the whole layout (vertex_l2 left empty).
StretchMetrics layoutStretch(const Positions& V, const Triangles& F, const Layout& layout);

// Whether stretchMetrics would count a flipped face (same rule), without the stretch.
bool hasFlippedFace(const Patch& patch, const std::vector<Eigen::Vector2d>& uv);

}  // namespace sdp
