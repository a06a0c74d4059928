// The last stage: the map one-to-one as the front end stores it (docs/method.md §5). MeshLab
// holds texture coordinates in single precision and its OBJ exporter writes 6 decimals; PLY
// holds floats. Rounding moves each corner by up to half a unit in the last place, which can
// flip or collapse the tiniest triangles of a strongly compressed map even though the map is
// one-to-one in double. This stage rounds the map to its storage and, where a face would
// degenerate, repairs it: the corners of such faces move (to storable positions) towards the
// centroid of their neighbours, each move kept only when it raises the smallest stored area
// around that vertex; the neighbourhood grows ring by ring while that is not enough.
#pragma once

#include "options.h"
#include "patch.h"
#include "solve.h"

namespace sdp {

struct StorageCounts {
  int degenerate_faces = 0;  // faces flipped or degenerate once rounded, before the repair
  int moved_vertices = 0;    // distinct vertices the repair moved
  int rounds = 0;            // repair sweeps
};

// `uv` per patch vertex, in the frame that will be stored (e.g. fitted to the unit square). The
// real vertices' UVs are rounded in place to values the storage holds exactly (for
// FloatAndSixDecimals: the float of the 6-decimal text, which the exporter writes back as that
// text), then repaired. Throws ParameterizationError with the reason when some face stays
// flipped or degenerate, or the boundary would cross itself, as stored.
StorageCounts roundForStorage(const Patch& patch, LocalUVs& uv, UVStorage storage);

}  // namespace sdp
