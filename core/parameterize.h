// The one entry point of the core: indexed triangles in, UVs + report out (docs/method.md §1).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/common/error.h"
#include "core/common/layout.h"
#include "core/common/options.h"
#include "core/common/report.h"

namespace sdp {

struct Result {
  // Per face corner (layout.h). A disk patch has no seam: layout.uv has one row per input vertex
  // (unreferenced vertices: 0, 0) and layout.face_uv is F.
  Layout layout;
  std::vector<double> face_stretch;  // per input face: normalized L2 stretch (1 = isometric)
  Report report;
};

// docs/method.md §5 measures of any per-vertex UVs on the patch (ours after rounding, or another
// tool's): the same metric code every report uses. Throws like parameterize() when (V, F) is no
// patch.
struct UVMeasures {
  double l2_stretch = 0;
  double linf_stretch = 0;
  int flipped_faces = 0;             // against the layout's majority orientation
  std::vector<double> face_stretch;  // per input face, normalized L2
};
UVMeasures measureUVs(const Positions& V, const Triangles& F, const UVs& uv);

// Flattens a disk-shaped patch and stores it as the options ask: flattenDisk(), then the store
// step (storage.h) with options.storage. Throws ParameterizationError with a one-line reason
// when the input is not a valid patch, a coordinate is not finite, or no one-to-one map could be
// made or stored: a returned Result is always one-to-one as stored (report.flipped_faces == 0),
// and its report describes the stored values.
Result parameterize(const Positions& V, const Triangles& F, const Options& options = {});

// The disk pipeline alone (connectivity, weights, boundary, solve, refinement): the layout at the
// mesh's natural scale (3D units) in double, one texture coordinate per vertex, with its
// measures; options.storage is not applied (store() does that, e.g. for an atlas over all its
// charts at once). The progress callback gets every stage but the last ("storage", "done").
Result flattenDisk(const Positions& V, const Triangles& F, const Options& options = {});

}  // namespace sdp
