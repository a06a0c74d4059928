// The measures of any atlas, from its per-corner texture coordinates alone (ours as stored, or
// another tool's file): the same code scores every method in the bench and certifies our own
// output (docs/method.md §7).
//   chart            faces joined across edges whose two sides carry the same UV values
//   seam             3D length of the edges whose two sides carry different UVs (each edge once,
//                    the mesh's own boundary left out), divided by sqrt(3D area)
//   mirrored chart   total signed UV area negative, faces wound as in the file
//   flipped face     UV area of the opposite sign to its chart's, or zero
//   overlapping      pixel centres at size x size covered by two or more triangles (top-left rule)
//   gutter           violated at a covered pixel of one chart with another chart's covered pixel
//                    within gutter - 1 pixels (Chebyshev distance)
//   efficiency       total UV area over the unit square
//   L2, L-infinity   whole-atlas Sander stretch, normalized by one global scale
#pragma once

#include <functional>
#include <vector>

#include "core/common/layout.h"

namespace sdp::atlas {

struct AtlasMeasures {
  int charts = 0;
  double seam = 0;  // normalized by sqrt(3D area)
  int mirrored_charts = 0;
  int flipped_faces = 0;
  long long overlapping_pixels = 0;
  long long gutter_violations = 0;  // pixels
  int outside_faces = 0;            // faces with a corner outside [0,1]^2
  double efficiency = 0;
  double l2 = 0, linf = 0;
  std::vector<int> chart;  // per face, numbered in order of first face
};

// Charts by UV values (above), numbered by first face.
std::vector<int> chartsByUVs(const Triangles& F, const Layout& layout, int* count = nullptr);

// Charts, seam, mirrored charts, faces outside the square and efficiency: everything above but
// the stretch, the flips and the pixel counts.
// `step`, when given, is called twice midway, on the calling thread (a progress bar).
AtlasMeasures measureLayout(const Positions& V, const Triangles& F, const Layout& layout,
                            const std::function<void()>& step = {});

// Everything above; the pixel counts at `texture_size` (0: skipped) with `gutter` texels.
AtlasMeasures measureAtlas(const Positions& V, const Triangles& F, const Layout& layout,
                           int texture_size, int gutter);

// Only the pixel measures, charts as given (per face, `layout.chart` when not empty).
struct PixelMeasures {
  long long overlapping_pixels = 0;
  long long gutter_violations = 0;
};
// `progress`, when given, gets the share of the calling thread's rows done, on that thread.
PixelMeasures measurePixels(const Layout& layout, const std::vector<int>& chart, int texture_size,
                            int gutter, const std::function<void(double)>& progress = {});

}  // namespace sdp::atlas
