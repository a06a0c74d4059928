#include "grid_newton.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "parallel.h"

namespace sdp {

GridNewtonSystem::GridNewtonSystem(const Patch& patch, const std::vector<FaceFrame>& frames,
                                   const GridNewtonSettings& settings)
    : patch_(patch), frames_(frames), settings_(settings), damping_(settings.damping) {}

bool GridNewtonSystem::layOver(const LocalUVs& uv) {
  const int n = patch_.real_vertex_count;
  Eigen::Vector2d lo = uv[0], hi = uv[0];
  for (int v = 1; v < n; ++v) {
    lo = lo.cwiseMin(uv[v]);
    hi = hi.cwiseMax(uv[v]);
  }
  const double side = std::max(hi.x() - lo.x(), hi.y() - lo.y()) / settings_.cells;
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
    Weights& w = vertex_[v];
    const int base = iy * nx_ + ix;
    w.node = {base, base + 1, base + nx_, base + nx_ + 1};
    w.weight = {(1 - s) * (1 - t), s * (1 - t), (1 - s) * t, s * t};
    for (int node : w.node) active_[node] = 0;
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
  for (Weights& w : vertex_)
    for (int& node : w.node) node = active_[node];
  return true;
}

int GridNewtonSystem::bandSlot(int a, int b) const {
  const int dx = node_x_[b] - node_x_[a], dy = node_y_[b] - node_y_[a];
  if (std::abs(dx) > kReach || std::abs(dy) > kReach) return -1;
  return (dy + kReach) * kBandWidth + dx + kReach;
}

// Per face, J's change under the grid's displacements d_k is sum_k (G_k . d_k^u, G_k . d_k^v)
// with G_k = sum over the corners of the corner's weight for node k times its gradient g: the
// face's gradient dJ and Hessian h carried to its nodes. The faces are split into fixed slots
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
  }
  parallelForSlots(faces, slots, [&](int begin, int end, int slot) {
    Partial& out = partial_[slot];
    for (int f = begin; f < end; ++f) {
      const FaceFrame& frame = frames_[f];
      if (frame.area == 0) continue;
      const auto& t = patch_.face[f];
      Eigen::Vector4d dJ;
      Eigen::Matrix4d h;
      faceNewtonTerms(frame, jacobian(frame, t, uv), energy, dJ, h);
      int node[12];
      Eigen::Vector2d G[12];
      int count = 0;
      for (int c = 0; c < 3; ++c) {
        const Weights& w = vertex_[t[c]];
        for (int q = 0; q < 4; ++q) {
          if (w.weight[q] == 0) continue;
          int k = 0;
          while (k < count && node[k] != w.node[q]) ++k;
          if (k == count) {
            node[count] = w.node[q];
            G[count++].setZero();
          }
          G[k] += w.weight[q] * frame.g[c];
        }
      }
      const Eigen::Matrix2d huu = h.topLeftCorner<2, 2>(), huv = h.topRightCorner<2, 2>();
      const Eigen::Matrix2d hvu = h.bottomLeftCorner<2, 2>(), hvv = h.bottomRightCorner<2, 2>();
      for (int l = 0; l < count; ++l) {
        out.gradient[2 * node[l]] += G[l].dot(dJ.head<2>());
        out.gradient[2 * node[l] + 1] += G[l].dot(dJ.tail<2>());
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
  });
  gradient_ = partial_[0].gradient;
  for (size_t s = 1; s < partial_.size(); ++s) {
    gradient_ += partial_[s].gradient;
    for (size_t i = 0; i < partial_[0].band.size(); ++i) partial_[0].band[i] += partial_[s].band[i];
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
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    for (int q = 0; q < 4; ++q)
      d += vertex_[v].weight[q] * coarse.segment<2>(2 * vertex_[v].node[q]);
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
