// Beyond the paper: Newton steps on the L2 stretch itself, with the boundary free. The
// as-rigid-as-possible steps of free_boundary.h stop where their optimum folds (face.off,
// camelhead.off: a fold-free map exists, but ARAP's target is not it). This minimizes Sander's
// L2 directly: L2^2 = Q * S / (2 A^2) with Q = sum_f A_f |J_f^-1|^2 (J_f the map from the flat
// 3D triangle to its UV triangle, A_f its 3D area, A their sum) and S = sum_f A_f det J_f (the
// UV area).
// |J^-1|^2 = |J|^2 / det(J)^2 grows without bound as a face collapses, so the energy is its own
// barrier against folds; each step is also capped below the first collapse along it, and
// checked like the ARAP steps (no flipped face, no boundary crossing), so the map stays
// one-to-one.
//
// The step: per face, the 4x4 Hessian of |J|^2 / det^2 made positive semi-definite (eigenvalues
// clamped), mapped to the face's 6 UV coordinates: one sparse system over u and v together. Up
// to StretchNewtonSettings::direct_up_to vertices it is assembled and solved by a sparse Cholesky
// (LDLT) factor, the pattern's analysis kept across steps. Above, where the factor's memory and
// time grow too fast, it is applied face by face without being assembled and solved by
// conjugate gradients, preconditioned by the project's multigrid on a scalar Laplacian proxy of
// it (u and v are coupled, the multigrid takes scalar M-matrices: the proxy drops the coupling).
#pragma once

#include <vector>

#include "core/common/metrics.h"
#include "core/common/options.h"
#include "core/common/patch.h"
#include "core/common/progress.h"
#include "core/linear/solve_path.h"
#include "core/paper/solve.h"
#include "grid_newton.h"
#include "refine_budget.h"

namespace sdp {

struct StretchNewtonSettings {
  // The sparse factor up to this many vertices, conjugate gradients above (linear/solve_path.h).
  int direct_up_to = DirectUpTo::kNewtonStep;
  // Relative residual of the conjugate gradients: a truncated Newton step (any iterate
  // descends; the line search makes it safe).
  double cg_tolerance = 1e-2;
  // The tolerance is rarely met in a few iterations: this cap decides (3, 5, 8 and 10 measured:
  // docs/measurements.md).
  int cg_max_iterations = 5;
  // Above direct_up_to, up to this many steps in the coarse grid's space first (grid_newton.h;
  // 0: none), then the fine ones. A grid step that fails or gains under the budget's least
  // gain hands over to the fine steps early.
  int grid_max_steps = 30;
  GridNewtonSettings grid;
  // The expected work of the first fine step after grid steps, which costs several times a
  // grid step (firstFineNewtonStepWork): a budget without room for it does not start it. 0: the
  // last grid step's.
  double first_fine_step_work = 0;
};

// The expected work (work.h) of one grid step, and of the first fine step without the sparse
// factor (its set-up, one update, the conjugate gradients), on a patch of `faces` faces.
double gridNewtonStepWork(int faces, int cells = GridNewtonSettings().cells);
double firstFineNewtonStepWork(int faces);

// True when a patch of `vertices` real vertices takes the conjugate-gradient path.
bool stretchNewtonIsMatrixFree(int vertices, const StretchNewtonSettings& settings = {});

struct StretchNewtonCounts {
  int steps_taken = 0;
  int cg_iterations = 0;  // summed over the steps (0 on the direct path)
  int grid_steps = 0;     // directions found in the grid's coarse space
  bool skipped = false;   // the system did not fit in memory
  bool stopped = false;   // a step could not be taken, or the energy stopped decreasing
};

// Up to `steps` Newton steps from `uv` (one-to-one, with its metrics in `metrics`). Returns the
// map with the lowest L2 stretch seen (each step's from its energy, the returned map's measured)
// and its metrics in `metrics`; the start, with steps_taken 0, when none is lower.
// Virtual hole-fill vertices keep their positions. `progress` as in relaxWithFreeBoundary
// (Stage::Newton).
LocalUVs minimizeStretchWithFreeBoundary(const Patch& patch, const LocalUVs& uv, int steps,
                                         StretchMetrics& metrics, StretchNewtonCounts& counts,
                                         const Progress& progress = Progress(),
                                         const RefineBudget& budget = {},
                                         const StretchNewtonSettings& settings = {});

}  // namespace sdp
