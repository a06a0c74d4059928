// Charts: a triangle mesh of any topology cut into disk-shaped pieces (docs/method.md §7). The
// cut works on faces joined across edges that have exactly two faces running opposite ways
// (connectivity.h), so a chart never crosses a non-manifold edge or an orientation flip: those
// are split here, inside the core, and the user's mesh is not touched.
//
// Charts are grown face by face from seeds, and a face joins a chart only when the chart stays a
// topological disk: it shares one edge with the chart and brings a new vertex, or it shares two
// edges and fills a notch. So every chart is a disk by construction (one boundary loop, no
// handle, no pinched vertex), whatever the mesh's genus or pieces.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "core/common/connectivity.h"
#include "core/common/layout.h"

namespace sdp::atlas {

// What growing needs per face and per vertex.
struct FaceGraph {
  const Triangles* F = nullptr;
  std::vector<Eigen::Vector3d> normal;  // unit, zero for a zero-area face
  // The normals charts grow by (growRegions): smoothed over a few rings of faces, so that
  // noise at the scale of single faces does not steer the growth (charts.cpp).
  std::vector<Eigen::Vector3f> growth_normal;
  std::vector<Eigen::Vector3d> centroid;  //
  std::vector<double> area;
  // Per half-edge 3 f + k: the face across that edge when the two faces may share a chart (a
  // two-face edge, consistently oriented), else -1.
  std::vector<int> across;
  // Faces a chart can hold: three distinct vertices and a positive area. The others (repeated
  // vertex, zero area) get a chart of their own.
  std::vector<char> chartable;
  // Faces around each vertex (CSR).
  std::vector<int> vertex_face_begin, vertex_face;

  int faceCount() const { return static_cast<int>(area.size()); }
};

// `step`, when given, is called between its four passes (a progress bar).
FaceGraph buildFaceGraph(const Positions& V, const Triangles& F, const Connectivity& c,
                         const std::function<void()>& step = {});

// buildFaceGraph in two parts: all but `across`, which needs no connectivity (so it can be built
// while the connectivity is analysed; `step` between its passes), then `across` from the twins.
FaceGraph faceGraphGeometry(const Positions& V, const Triangles& F,
                            const std::function<void()>& step = {});
void joinFacesAcrossEdges(FaceGraph& graph, const Connectivity& c);

// Per face a region id, or one of these.
constexpr int kUnassigned = -1;  // may be grown into
constexpr int kOutside = -2;     // not part of the faces being split

// Grows a region from each seed (ids first_id, first_id + 1, ...) into the faces of the list
// that `region` marks kUnassigned, each region kept a disk; faces no region could take seed new
// regions until none is left. Growth prefers faces whose normal is close to the region's mean
// normal, and `compactness` weighs the distance walked from the seed (in units of `length`).
// Returns the number of regions made.
// Told, now and then, how much of a split's work was done since it last told, in faces: the
// seeds count once over the faces, each growth once (a split makes three); called from the
// thread that does the work (a split into halves grows on two).
using GrowthProgress = std::function<void(int faces)>;

int growRegions(const FaceGraph& graph, const std::vector<int>& faces,
                const std::vector<int>& seeds, int first_id, double compactness, double length,
                std::vector<int>& region, const GrowthProgress* progress = nullptr);

// Per-face and per-vertex scratch, sized to the mesh once and reset entry by entry, so that
// splitting or checking a set of faces costs in proportion to the set, not to the mesh (a
// million-face scan is split a thousand times). Each thread needs its own.
struct FaceScratch {
  explicit FaceScratch(const FaceGraph& graph);
  std::vector<int> region;       // kOutside on entry and on return
  std::vector<double> distance;  // +infinity on entry and on return
  std::vector<int> vertex;       // -1 on entry and on return
};

// Splits the faces of the list into `parts` (at least 2) disk-shaped pieces, seeded far apart
// along the surface and improved by a few Lloyd steps (each seed moved to the most typical face
// of its piece). More pieces than asked come back when growth left faces over.
std::vector<std::vector<int>> splitFaces(const FaceGraph& graph, const std::vector<int>& faces,
                                         int parts, FaceScratch& scratch,
                                         const GrowthProgress* progress = nullptr);

// The faces of the list in patches joined across smooth edges: edges whose two faces' normals
// make an angle below the one whose cosine is `sharp_cos` (a sharp edge bounds a patch). A patch
// of fewer than `fewest` faces joins the neighbouring patch it shares the most border with (in
// patch order), so a crease that does not close, or noise, leaves one patch. In list order.
// `progress`, when given, is told of the faces flooded as it goes (some 65,536 at a time).
std::vector<std::vector<int>> featurePatches(const FaceGraph& graph, const std::vector<int>& faces,
                                             double sharp_cos, int fewest, FaceScratch& scratch,
                                             const GrowthProgress* progress = nullptr);

// The area of the second largest of the patches featurePatches grows, among those of at least
// `fewest` faces (the others would join a neighbour), over the faces' area: 0 for one patch. One
// pass over the faces, keeping no lists (a scan's whole piece is millions of faces).
double secondFeaturePatchShare(const FaceGraph& graph, const std::vector<int>& faces,
                               double sharp_cos, int fewest, FaceScratch& scratch,
                               const GrowthProgress* progress = nullptr);

// The faces of the list in patches that each face about one way: grown from the largest faces
// first, each across the edges to faces whose normal is within the angle whose cosine is
// `cone_cos` of its seed face's. Small patches join a neighbour as in featurePatches. For a
// piece with no sharp edges left to cut along, as a CAD part's faces joined by fillets are.
std::vector<std::vector<int>> flatPatches(const FaceGraph& graph, const std::vector<int>& faces,
                                          double cone_cos, int fewest, FaceScratch& scratch);

// True when the faces form a disk (one consistently oriented manifold piece with
// one boundary loop and Euler characteristic 1).
bool regionIsDisk(const FaceGraph& graph, const std::vector<int>& region_faces,
                  FaceScratch& scratch);

// V - E + F of the faces of the list, counting as edges the graph's joins between them and their
// border edges: their Euler characteristic when every edge two faces of the mesh share is one
// the graph joins (no non-manifold or inconsistent edge). A disk has 1. Linear in the faces: a
// check before regionHoles, which builds the faces' own mesh.
int regionEulerCharacteristic(const FaceGraph& graph, const std::vector<int>& region_faces,
                              FaceScratch& scratch);

// The holes of the faces when they form a disk with holes (as above, with one or more boundary
// loops): the loops but one; -1 when they do not.
int regionHoles(const FaceGraph& graph, const std::vector<int>& region_faces, FaceScratch& scratch);

}  // namespace sdp::atlas
