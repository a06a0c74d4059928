// The coarse space of the Newton steps on a large patch (stretch_newton.h): displacements of a
// regular grid laid over the current map, carried to the vertices by bilinear interpolation P,
// so that a step is a smooth deformation of the plane. What freeing the boundary gains at scale
// is such a deformation: the polygon's straight sides bend to the patch's own outline and the
// interior follows. The grid's Newton system P^T H P (2 unknowns per grid node) is summed face by
// face, H never stored, and is small enough for a sparse factor: a step costs about three
// passes over the faces, where a fine step (conjugate gradients on H) costs a multigrid setup and
// several cycles. Its gradient P^T g is exact; in its Hessian a face across cell edges that is
// not stiff stands as if it lay in one cell (exact_below below), which keeps the system's
// couplings within cells.
//
// Steps are damped as in Levenberg-Marquardt, with a smoothness term in place of the identity:
// damping x (the mean diagonal) x the grid's 4-neighbour graph Laplacian, per coordinate. It
// holds back the nodes few vertices lean on (at the map's edge), whose undamped moves crushed
// faces and cut the first steps to a few percent of their length. The damping falls after a full
// step and rises after a step cut below half.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "core/common/patch.h"
#include "core/common/work.h"
#include "core/linear/solve_path.h"
#include "core/paper/solve.h"
#include "stretch_terms.h"

namespace sdp {

struct GridNewtonSettings {
  // Cells on the map's longer side. 32 and not 64: the factor's work falls twelvefold, so the
  // budget affords more steps, which gain more than the finer grid (docs/measurements.md).
  int cells = 32;
  // Once a step gains less than `finer_below` (its relative drop of the energy), or not the
  // budget's least gain, the steps go on with `finer_cells` cells: the coarse grid's steps
  // level off where the map still bends between its nodes.
  int finer_cells = 64;
  double finer_below = 0.005;
  // A face across cell edges carries its Hessian exactly to its (up to 9) nodes only when it is
  // stiff: its smaller singular value under this, the map scaled to the patch's area. The
  // others carry it as if they lay in each corner's cell, a third to each, the bilinear weights
  // extrapolated: the Hessian then couples only the nodes of one cell and the grid's factor
  // fills in 3-4 times less (docs/measurements.md). Their gradient stays exact, so the step
  // still descends; a stiff face's carry decides where the step meets the collapse cap, and an
  // approximate one cut the steps short.
  double exact_below = 0.5;
  double damping = 0.03;        // the first step's (see above)
  double damping_fall = 0.3;    // its factor after a full step...
  double damping_rise = 3;      // ... and after a step cut below half its length
  double least_damping = 1e-4;  // bounds of the damping
  double most_damping = 10;
};

// Work (work.h) per face of one grid system: the face's terms and their products with its
// (mostly four) nodes' weights, carried to them through its cell's sums. Counted against the
// other stages' units per nanosecond (bench/determinism.py) once the cell sums took the Hessian
// as its eigen-pairs (stretchModes): 100 before, which put the newton stage at 1.36 units per
// ns against the solve's 1.1 on face s2 and face s3.
constexpr double kGridFaceWork = 72;

class GridNewtonSystem {
 public:
  GridNewtonSystem(const Patch& patch, const std::vector<FaceFrame>& frames,
                   const GridNewtonSettings& settings);

  // Lays the grid over the map's bounding box, sums the grid's gradient and damped Hessian at
  // `uv` (whose energy is `energy`) and solves for the step, carried to the vertices in
  // `direction` (u and v of vertex i at 2i and 2i + 1). Returns false when the factor fails.
  bool solve(const LocalUVs& uv, const Energy& energy, Eigen::VectorXd& direction);
  // The energy's slope along the last direction (g^T P d).
  double slope() const { return slope_; }
  // After a step of `length` times the direction was taken, `halvings` halvings after the cap.
  void adapt(double length, int halvings);
  // Work (work.h) of the last solve().
  double lastWork() const { return last_work_; }
  int nodeCount() const { return static_cast<int>(node_x_.size()); }
  int cells() const { return cells_; }
  // After a step that lowered the energy by the fraction `gain` (0 when it did not gain the
  // budget's least): the next steps take the finer grid when the step gained under
  // finer_below. True when the grid changed.
  bool refineAfter(double gain) {
    if (!(gain < settings_.finer_below) || cells_ >= settings_.finer_cells) return false;
    cells_ = settings_.finer_cells;
    return true;
  }

 private:
  // Where a vertex lies: its cell (by the lower-left node's grid number) and its place in it,
  // (s, t) in [0, 1]^2; its weights are bilinear in s and t.
  struct Place {
    int cell;
    double s, t;
  };
  // A cell's 4 corner nodes by grid number: lower-left, lower-right, upper-left, upper-right.
  std::array<int, 4> cellCorners(int cell) const {
    return {cell, cell + 1, cell + nx_, cell + nx_ + 1};
  }
  // A cell's 4 nodes by active number, in cellCorners' order.
  std::array<int, 4> cellNodes(int cell) const {
    std::array<int, 4> nodes = cellCorners(cell);
    for (int& node : nodes) node = active_[node];
    return nodes;
  }
  // A vertex's 4 nodes (active numbers) and their weights.
  std::array<int, 4> nodesOf(const Place& p) const { return cellNodes(p.cell); }
  static std::array<double, 4> weightsOf(const Place& p) {
    return {(1 - p.s) * (1 - p.t), p.s * (1 - p.t), (1 - p.s) * p.t, p.s * p.t};
  }
  // A face whose corners share a cell carries its terms to the cell's 4 nodes through 3
  // vectors (grid_newton.cpp): the cell's sums are kept in that reduced form, 33 numbers, and
  // carried to the nodes once per cell.
  static constexpr int kCellSums = 33;
  struct Partial {  // one slot's sums
    Eigen::VectorXd gradient;
    std::vector<double> band;                 // per node, kBand blocks of 4 (uu, uv, vu, vv)
    std::vector<Eigen::Triplet<double>> far;  // blocks between nodes further apart
    std::vector<double> cell;                 // per cell, kCellSums
  };
  static constexpr int kReach = 2;  // the band: nodes up to this many cells apart in x and y
  static constexpr int kBandWidth = 2 * kReach + 1;
  static constexpr int kBand = kBandWidth * kBandWidth;

  bool layOver(const LocalUVs& uv);  // false when the map has no extent
  int bandSlot(int a, int b) const;
  void sumFaces(const LocalUVs& uv, const Energy& energy);
  void sumFace(int f, const LocalUVs& uv, const Energy& energy, double stiff_value,
               Partial& out) const;
  int gatherNodes(const std::array<int, 3>& t, const FaceFrame& frame, int node[12],
                  Eigen::Vector2d G[12]) const;
  void addBandHessian(const int node[12], const Eigen::Vector2d G[12], int count,
                      const StretchModes& modes, Partial& out) const;
  void addCellSums();
  void assembleMatrix();

  const Patch& patch_;
  const std::vector<FaceFrame>& frames_;
  const GridNewtonSettings settings_;
  double damping_;
  int cells_;
  double area_ = 0;  // the patch's 3D area
  int nx_ = 0, ny_ = 0;
  std::vector<int> active_;  // per grid node: its active number, -1 when no vertex uses it
  std::vector<Place> vertex_;
  std::vector<int> node_x_, node_y_;
  std::vector<Partial> partial_;
  Eigen::VectorXd gradient_;
  Eigen::SparseMatrix<double> matrix_;
  SymmetricFactor factor_;
  double slope_ = 0;
  double last_work_ = 0;
};

}  // namespace sdp
