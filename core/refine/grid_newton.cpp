#include "grid_newton.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "core/common/parallel.h"

namespace sdp {

GridNewtonSystem::GridNewtonSystem(const Patch& patch, const std::vector<FaceFrame>& frames,
                                   const GridNewtonSettings& settings)
    : patch_(patch),
      frames_(frames),
      settings_(settings),
      damping_(settings.damping),
      cells_(settings.cells) {
  for (const FaceFrame& frame : frames) area_ += frame.area;
}

bool GridNewtonSystem::layOver(const LocalUVs& uv) {
  const int n = patch_.real_vertex_count;
  Eigen::Vector2d lo = uv[0], hi = uv[0];
  for (int v = 1; v < n; ++v) {
    lo = lo.cwiseMin(uv[v]);
    hi = hi.cwiseMax(uv[v]);
  }
  const double side = std::max(hi.x() - lo.x(), hi.y() - lo.y()) / cells_;
  if (!(side > 0) || !std::isfinite(side)) return false;  // no extent to lay a grid over
  nx_ = std::max(2, static_cast<int>(std::ceil((hi.x() - lo.x()) / side)) + 1);
  ny_ = std::max(2, static_cast<int>(std::ceil((hi.y() - lo.y()) / side)) + 1);
  active_.assign(static_cast<size_t>(nx_) * ny_, -1);
  vertex_.resize(n);
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector2d p = (uv[v] - lo) / side;
    const int ix = std::clamp(static_cast<int>(p.x()), 0, nx_ - 2);
    const int iy = std::clamp(static_cast<int>(p.y()), 0, ny_ - 2);
    const double s = std::clamp(p.x() - ix, 0.0, 1.0), t = std::clamp(p.y() - iy, 0.0, 1.0);
    const int base = iy * nx_ + ix;
    vertex_[v] = {base, s, t};
    for (int node : cellCorners(base)) active_[node] = 0;
  }
  // The nodes some vertex uses, numbered in grid order.
  node_x_.clear();
  node_y_.clear();
  for (int k = 0; k < nx_ * ny_; ++k)
    if (active_[k] == 0) {
      active_[k] = static_cast<int>(node_x_.size());
      node_x_.push_back(k % nx_);
      node_y_.push_back(k / nx_);
    }
  return true;
}

// A face's corners at (s, t) in one cell's coordinates (inside it, or beyond its edges for the
// extrapolated weights of a face across them): E = [A B C] (2 x 3), the sums of s g, t g and
// s t g over the corners, through which the face reaches the cell's 4 nodes (addCellSums()).
static Eigen::Matrix<double, 2, 3> cellFrame(const FaceFrame& frame, const double s[3],
                                             const double t[3]) {
  Eigen::Matrix<double, 2, 3> E = Eigen::Matrix<double, 2, 3>::Zero();
  for (int c = 0; c < 3; ++c) {
    E.col(0) += s[c] * frame.g[c];
    E.col(1) += t[c] * frame.g[c];
    E.col(2) += s[c] * t[c] * frame.g[c];
  }
  return E;
}

// The face's gradient dJ in the cell's reduced form: E^T dJ per coordinate.
static void addCellGradient(const Eigen::Matrix<double, 2, 3>& E, const Eigen::Vector4d& dJ,
                            double* sums) {
  Eigen::Map<Eigen::Vector3d>(sums) += E.transpose() * dJ.head<2>();
  Eigen::Map<Eigen::Vector3d>(sums + 3) += E.transpose() * dJ.tail<2>();
}

// `share` of the face's Hessian h in the cell's reduced form, E^T h E per pair of coordinates,
// from its eigen-pairs (value, w): E^T h_xy E = sum value (E^T w_x)(E^T w_y)^T.
static void addCellHessian(const Eigen::Matrix<double, 2, 3>& E, const StretchModes& h,
                           double share, double* sums) {
  // Row-major 3 x 3 blocks: u-u, u-v, v-v.
  using Block = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>;
  Eigen::Matrix3d uu = Eigen::Matrix3d::Zero(), uv = Eigen::Matrix3d::Zero(),
                  vv = Eigen::Matrix3d::Zero();
  for (int m = 0; m < 4; ++m) {
    const Eigen::Vector3d a = E.transpose() * h.vector[m].head<2>();
    const Eigen::Vector3d b = E.transpose() * h.vector[m].tail<2>();
    const double value = share * h.value[m];
    const Eigen::Vector3d weighted = value * a;
    uu.noalias() += weighted * a.transpose();
    uv.noalias() += weighted * b.transpose();
    vv.noalias() += (value * b) * b.transpose();
  }
  Block(sums + 6) += uu;
  Block(sums + 15) += uv;
  Block(sums + 24) += vv;
}

int GridNewtonSystem::bandSlot(int a, int b) const {
  const int dx = node_x_[b] - node_x_[a], dy = node_y_[b] - node_y_[a];
  if (std::abs(dx) > kReach || std::abs(dy) > kReach) return -1;
  return (dy + kReach) * kBandWidth + dx + kReach;
}

// Face f's share of the gradient and the Hessian (see sumFaces).
void GridNewtonSystem::sumFace(int f, const LocalUVs& uv, const Energy& energy, double stiff_value,
                               Partial& out) const {
  const FaceFrame& frame = frames_[f];
  if (frame.area == 0) return;
  const auto& t = patch_.face[f];
  Eigen::Vector4d dJ;
  StretchModes modes;
  faceNewtonTerms(frame, jacobian(frame, t, uv), energy, dJ, modes);
  const Place &w0 = vertex_[t[0]], &w1 = vertex_[t[1]], &w2 = vertex_[t[2]];
  if (w0.cell == w1.cell && w0.cell == w2.cell) {
    const double cs[3] = {w0.s, w1.s, w2.s}, ct[3] = {w0.t, w1.t, w2.t};
    const Eigen::Matrix<double, 2, 3> E = cellFrame(frame, cs, ct);
    double* sums = &out.cell[static_cast<size_t>(w0.cell) * kCellSums];
    addCellGradient(E, dJ, sums);
    addCellHessian(E, modes, 1.0, sums);
    return;
  }
  int node[12];
  Eigen::Vector2d G[12];
  const int count = gatherNodes(t, frame, node, G);
  for (int l = 0; l < count; ++l) {
    out.gradient[2 * node[l]] += G[l].dot(dJ.head<2>());
    out.gradient[2 * node[l] + 1] += G[l].dot(dJ.tail<2>());
  }
  if (!(*std::max_element(modes.value.begin(), modes.value.end()) > stiff_value * frame.area)) {
    const Place* corner[3] = {&w0, &w1, &w2};
    for (const Place* home : corner) {
      const int hx = home->cell % nx_, hy = home->cell / nx_;
      double cs[3], ct[3];
      for (int c = 0; c < 3; ++c) {
        cs[c] = corner[c]->s + (corner[c]->cell % nx_ - hx);
        ct[c] = corner[c]->t + (corner[c]->cell / nx_ - hy);
      }
      addCellHessian(cellFrame(frame, cs, ct), modes, 1.0 / 3,
                     &out.cell[static_cast<size_t>(home->cell) * kCellSums]);
    }
    return;
  }
  addBandHessian(node, G, count, modes, out);
}

// The grid nodes that carry the corners of face t (each once) and their G_k.
int GridNewtonSystem::gatherNodes(const std::array<int, 3>& t, const FaceFrame& frame, int node[12],
                                  Eigen::Vector2d G[12]) const {
  int count = 0;
  for (int c = 0; c < 3; ++c) {
    const std::array<int, 4> nodes = nodesOf(vertex_[t[c]]);
    const std::array<double, 4> weights = weightsOf(vertex_[t[c]]);
    for (int q = 0; q < 4; ++q) {
      if (weights[q] == 0) continue;
      int k = 0;
      while (k < count && node[k] != nodes[q]) ++k;
      if (k == count) {
        node[count] = nodes[q];
        G[count++].setZero();
      }
      G[k] += weights[q] * frame.g[c];
    }
  }
  return count;
}

// A stiff face's exact Hessian G_k^T h G_l, in the band or, beyond its reach, in `far`.
void GridNewtonSystem::addBandHessian(const int node[12], const Eigen::Vector2d G[12], int count,
                                      const StretchModes& modes, Partial& out) const {
  const Eigen::Matrix4d h = modes.matrix();
  const Eigen::Matrix2d huu = h.topLeftCorner<2, 2>(), huv = h.topRightCorner<2, 2>();
  const Eigen::Matrix2d hvu = h.bottomLeftCorner<2, 2>(), hvv = h.bottomRightCorner<2, 2>();
  for (int l = 0; l < count; ++l) {
    const Eigen::Vector2d uu = huu * G[l], uv_l = huv * G[l], vu = hvu * G[l], vv = hvv * G[l];
    for (int k = 0; k < count; ++k) {
      const double block[4] = {G[k].dot(uu), G[k].dot(uv_l), G[k].dot(vu), G[k].dot(vv)};
      const int slot_k = bandSlot(node[k], node[l]);
      if (slot_k >= 0) {
        double* to = &out.band[(static_cast<size_t>(node[k]) * kBand + slot_k) * 4];
        for (int e = 0; e < 4; ++e) to[e] += block[e];
      } else {
        for (int e = 0; e < 4; ++e)
          out.far.emplace_back(2 * node[k] + e / 2, 2 * node[l] + e % 2, block[e]);
      }
    }
  }
}

// Per face, J's change under the grid's displacements d_k is sum_k (G_k . d_k^u, G_k . d_k^v)
// with G_k = sum over the corners of the corner's weight for node k times its gradient g: the
// face's gradient dJ and Hessian h carried to its nodes. A face inside one cell goes through its
// cell's sums (cellFrame); one across cell edges computes its G_k here for the gradient, and
// carries its Hessian exactly only when it is stiff (GridNewtonSettings::exact_below): else a
// third to each corner's cell, as if the face lay in it. The faces are split into fixed slots
// summed in slot order: the same bits on any number of cores.
void GridNewtonSystem::sumFaces(const LocalUVs& uv, const Energy& energy) {
  const int m = nodeCount();
  const int faces = patch_.real_face_count;
  const int slots = std::clamp(faces / 65536, 1, 4);
  partial_.resize(slots);
  for (Partial& p : partial_) {
    p.gradient.setZero(2 * m);
    p.band.assign(static_cast<size_t>(m) * kBand * 4, 0.0);
    p.far.clear();
    p.cell.assign(static_cast<size_t>(nx_) * ny_ * kCellSums, 0.0);
  }
  // A face's Hessian is stiff when its largest eigenvalue passes that of a face squeezed to
  // exact_below of its size along one direction, in the map scaled to the patch's area: the
  // scaling's 6 / s^4 (stretchHessian) times S and the face's area (faceNewtonTerms), with
  // s = exact_below sqrt(S / A).
  const double scale = energy.S / area_;
  const double stiff_value = energy.S * 6 / std::pow(settings_.exact_below, 4) / (scale * scale);
  parallelForSlots(faces, slots, [&](int begin, int end, int slot) {
    for (int f = begin; f < end; ++f) sumFace(f, uv, energy, stiff_value, partial_[slot]);
  });
  gradient_ = partial_[0].gradient;
  for (size_t s = 1; s < partial_.size(); ++s) {
    gradient_ += partial_[s].gradient;
    for (size_t i = 0; i < partial_[0].band.size(); ++i) partial_[0].band[i] += partial_[s].band[i];
    for (size_t i = 0; i < partial_[0].cell.size(); ++i) partial_[0].cell[i] += partial_[s].cell[i];
  }
  addCellSums();
}

// The bilinear weight of a cell's node k (lower-left, lower-right, upper-left, upper-right) is
// a + b s + c t + d s t; as the corners' gradients sum to zero, a face inside the cell carries
// G_k = b A + c B + d C to node k, with A, B, C the sums of s g, t g and s t g over its corners.
constexpr double kNodeCoefficients[4][3] = {{-1, -1, 1}, {1, 0, -1}, {0, 1, -1}, {0, 0, 1}};

void GridNewtonSystem::addCellSums() {
  const double* sums = partial_[0].cell.data();
  double* band = partial_[0].band.data();
  for (int cell = 0; cell < nx_ * ny_; ++cell, sums += kCellSums) {
    if (std::all_of(sums, sums + kCellSums, [](double x) { return x == 0; })) continue;
    const std::array<int, 4> node = cellNodes(cell);
    // sums: the gradient's u and v parts (3 each), then the u-u, u-v, v-v blocks (3 x 3 each,
    // row-major).
    for (int k = 0; k < 4; ++k) {
      const double* phi_k = kNodeCoefficients[k];
      double gu = 0, gv = 0;
      for (int a = 0; a < 3; ++a) {
        gu += phi_k[a] * sums[a];
        gv += phi_k[a] * sums[3 + a];
      }
      gradient_[2 * node[k]] += gu;
      gradient_[2 * node[k] + 1] += gv;
      for (int l = 0; l < 4; ++l) {
        const double* phi_l = kNodeCoefficients[l];
        double block[4] = {0, 0, 0, 0};  // uu, uv, vu, vv
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            const double weight = phi_k[a] * phi_l[b];
            block[0] += weight * sums[6 + 3 * a + b];
            block[1] += weight * sums[15 + 3 * a + b];
            block[2] += weight * sums[15 + 3 * b + a];
            block[3] += weight * sums[24 + 3 * a + b];
          }
        double* to = &band[(static_cast<size_t>(node[k]) * kBand + bandSlot(node[k], node[l])) * 4];
        for (int e = 0; e < 4; ++e) to[e] += block[e];
      }
    }
  }
}

void GridNewtonSystem::assembleMatrix() {
  const int m = nodeCount();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(m) * (kBand * 4 + 8));
  double trace = 0;
  for (int a = 0; a < m; ++a)
    for (int dy = -kReach; dy <= kReach; ++dy)
      for (int dx = -kReach; dx <= kReach; ++dx) {
        const int x = node_x_[a] + dx, y = node_y_[a] + dy;
        if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
        const int b = active_[static_cast<size_t>(y) * nx_ + x];
        if (b < 0) continue;
        const int slot = (dy + kReach) * kBandWidth + dx + kReach;  // bandSlot(a, b)
        const double* block = &partial_[0].band[(static_cast<size_t>(a) * kBand + slot) * 4];
        if (block[0] == 0 && block[1] == 0 && block[2] == 0 && block[3] == 0) continue;
        for (int e = 0; e < 4; ++e) entries.emplace_back(2 * a + e / 2, 2 * b + e % 2, block[e]);
        if (a == b) trace += block[0] + block[3];
      }
  for (const Partial& p : partial_) entries.insert(entries.end(), p.far.begin(), p.far.end());
  const double mean_diagonal = trace / (2 * m);
  // A small multiple of the identity fixes the translation the energy does not see.
  for (int i = 0; i < 2 * m; ++i) entries.emplace_back(i, i, 1e-8 * mean_diagonal);
  const double smooth = damping_ * mean_diagonal;
  for (int a = 0; a < m; ++a)
    for (const auto& [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
      const int x = node_x_[a] + dx, y = node_y_[a] + dy;
      if (x >= nx_ || y >= ny_) continue;
      const int b = active_[static_cast<size_t>(y) * nx_ + x];
      if (b < 0) continue;
      for (int e = 0; e < 2; ++e) {
        entries.emplace_back(2 * a + e, 2 * a + e, smooth);
        entries.emplace_back(2 * b + e, 2 * b + e, smooth);
        entries.emplace_back(2 * a + e, 2 * b + e, -smooth);
        entries.emplace_back(2 * b + e, 2 * a + e, -smooth);
      }
    }
  matrix_.resize(2 * m, 2 * m);
  matrix_.setFromTriplets(entries.begin(), entries.end());
}

bool GridNewtonSystem::solve(const LocalUVs& uv, const Energy& energy, Eigen::VectorXd& direction) {
  const int n = patch_.real_vertex_count;
  last_work_ = n * 8 * WorkCosts::kVectorEntry;  // the bounds, weights and the step's values
  if (!layOver(uv)) return false;
  sumFaces(uv, energy);
  assembleMatrix();
  last_work_ += patch_.real_face_count * kGridFaceWork;
  // The pattern's analysis, about ten visits of each entry.
  last_work_ += static_cast<double>(matrix_.nonZeros()) * 10 * WorkCosts::kNonzero;
  factor_.forgetPattern();
  if (!factor_.factorize(matrix_)) return false;
  last_work_ += factor_.lastWork();
  Eigen::VectorXd coarse;
  const bool solved = factor_.solve(-gradient_, coarse);
  last_work_ += factor_.lastWork();
  if (!solved) return false;
  for (int v = 0; v < n; ++v) {
    const std::array<int, 4> nodes = nodesOf(vertex_[v]);
    const std::array<double, 4> weights = weightsOf(vertex_[v]);
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    for (int q = 0; q < 4; ++q) d += weights[q] * coarse.segment<2>(2 * nodes[q]);
    direction.segment<2>(2 * v) = d;
  }
  slope_ = gradient_.dot(coarse);
  return true;
}

void GridNewtonSystem::adapt(double length, int halvings) {
  if (length >= 1 && halvings == 0)
    damping_ = std::max(damping_ * settings_.damping_fall, settings_.least_damping);
  else if (length < 0.5 || halvings > 0)
    damping_ = std::min(damping_ * settings_.damping_rise, settings_.most_damping);
}

}  // namespace sdp
