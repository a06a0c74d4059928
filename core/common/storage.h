// The last stage: the map one-to-one as the front end stores it (docs/method.md §5). MeshLab
// holds texture coordinates in single precision and its OBJ exporter writes 6 decimals; PLY
// holds floats. Rounding moves each corner by up to half a unit in the last place, which can
// flip or collapse the tiniest triangles of a strongly compressed map even though the map is
// one-to-one in double. This stage rounds the map to its storage and, where a face would
// degenerate, repairs it: the corners of such faces move (to storable positions) towards the
// centroid of their neighbours, each move kept only when it raises the smallest stored area
// around that vertex; the neighbourhood grows ring by ring while that is not enough. It works
// on the layout's own triangles (face_uv), so seams and several charts need nothing more.
#pragma once

#include <functional>
#include <string>

#include "layout.h"
#include "options.h"

namespace sdp {

struct StorageCounts {
  int degenerate_faces = 0;  // faces flipped or degenerate once rounded, before the repair
  int moved_vertices = 0;    // distinct texture coordinates (layout rows) the repair moved
  int rounds = 0;            // repair sweeps
};

// The store step, over a whole layout (all its charts at once): fits it (policy), rounds every
// texture coordinate a face uses to a value the storage holds exactly (for FloatAndSixDecimals:
// the float of the 6-decimal text, which the exporter writes back as that text), repairs the
// faces that rounding would degenerate, then certifies the stored values: no face of a chart
// flipped or degenerate against that chart's orientation, and no two edges of the charts'
// borders crossing or touching (within a chart or between charts). Throws ParameterizationError
// with what failed; on success `layout` holds exactly the stored values.
// `step`, when given, is called between its steps on the calling thread (a progress bar).
StorageCounts store(Layout& layout, const StoragePolicy& policy,
                    const std::function<void()>& step = {});

}  // namespace sdp
