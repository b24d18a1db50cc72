// The matrix of a quasi-static Newton iteration: the phases' tangents and the
// u-p coupling accumulated in blocks per node pair, then one sparse matrix,
// scaled and factorised.
#include <algorithm>
#include <array>
#include <cmath>

#include "quasi_static_linear.hpp"
#include "suffuse/error.hpp"
#include "suffuse/liquid.hpp"

namespace suffuse::detail {

namespace {


// Engineering strain of the Voigt component r from the displacement of a
// node along axis i, g its shape function's gradient padded to 3 components
// (zero out of plane): B[r][i].
inline double strain_of(int r, int i, const double* g) {
  static constexpr int first[6] = {0, 1, 2, 1, 0, 0}, second[6] = {0, 1, 2, 2, 2, 1};
  const int k = first[r], l = second[r];
  if (k == l) return i == k ? g[i] : 0.0;
  if (i == k) return g[l];
  if (i == l) return g[k];
  return 0.0;
}

// Whether every point's 6x6 tangent is symmetric (to round-off of its largest entry).
bool symmetric_tangents(const std::vector<double>& tangents) {
  for (std::size_t p = 0; p + 36 <= tangents.size(); p += 36) {
    const double* D = &tangents[p];
    double largest = 0, asymmetry = 0;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) {
        largest = std::max(largest, std::abs(D[r * 6 + c]));
        asymmetry = std::max(asymmetry, std::abs(D[r * 6 + c] - D[c * 6 + r]));
      }
    if (asymmetry > 1e-12 * largest) return false;
  }
  return true;
}

inline std::array<double, 3> padded(const double* g, int dim) {
  return {g[0], dim > 1 ? g[1] : 0.0, dim > 2 ? g[2] : 0.0};
}

}  // namespace

// The nodes of a point's support, as the slots of node pairs: the matrix is
// accumulated in blocks, one per pair of nodes that share a point, (dim + 1)
// square (the displacements and the pressure), before it becomes a sparse
// matrix. A point adds to each of its npp^2 pairs; many points share a pair,
// so this is a few times fewer entries to sort than one triplet per point
// and pair.
void QuasiStatic::prepare_blocks() {
  const int dim = d_.dim();
  const ExpandedSupports& s = d_.expanded_shape();
  const std::size_t np = d_.points.size();
  // The stencil: how far apart (in nodes, along any axis) two nodes of one point lie.
  int radius = 0;
  point_nodes_ijk_.resize(np * s.npp * 3);
  for (std::size_t p = 0; p < np; ++p) {
    std::array<int, 3> lo{1 << 30, 1 << 30, 1 << 30}, hi{-1, -1, -1};
    for (int a = 0; a < s.npp; ++a) {
      const auto ijk = d_.grid.node_ijk(s.ids[p * s.npp + a]);
      for (int i = 0; i < 3; ++i) {
        point_nodes_ijk_[(p * s.npp + a) * 3 + i] = ijk[i];
        lo[i] = std::min(lo[i], ijk[i]);
        hi[i] = std::max(hi[i], ijk[i]);
      }
    }
    for (int i = 0; i < dim; ++i) radius = std::max(radius, hi[i] - lo[i]);
  }
  stencil_radius_ = radius;
  stencil_width_ = 2 * radius + 1;
  stencil_slots_ = 1;
  for (int i = 0; i < dim; ++i) stencil_slots_ *= stencil_width_;
  // Nodes with an unknown, numbered compactly.
  const std::size_t nn = d_.grid.node_count();
  block_node_.assign(nn, -1);
  block_nodes_.clear();
  for (std::size_t I = 0; I < nn; ++I) {
    bool any = p_dof_[I] >= 0;
    for (int i = 0; i < dim; ++i) any = any || u_dof_[I * dim + i] >= 0;
    if (!any) continue;
    block_node_[I] = static_cast<std::int64_t>(block_nodes_.size());
    block_nodes_.push_back(static_cast<std::int64_t>(I));
  }
  const std::size_t b = static_cast<std::size_t>(dim + 1) * (dim + 1);
  blocks_.assign(block_nodes_.size() * stencil_slots_ * b, 0.0);
  block_used_.assign(block_nodes_.size() * stencil_slots_, 0);
  linear_->ldlt_analysed = linear_->lu_analysed = linear_->distributed_started = false;
}

void QuasiStatic::assemble(double dt) {
  const int dim = d_.dim();
  PointSet& pts = d_.points;
  const ExpandedSupports& s = d_.expanded_shape();
  const double* V = pts.data(pts.core().volume);
  const double* n = mixture_ ? pts.data(mixture_->fields().porosity) : nullptr;
  const double* KL = mixture_ ? pts.data(mixture_->fields().bulk_modulus) : nullptr;
  const double* K = mixture_ ? pts.data(mixture_->fields().conductivity) : nullptr;
  const double* rho_w = mixture_ ? pts.data(mixture_->fields().water_density) : nullptr;
  linear_->symmetric = symmetric_tangents(tangent_);
  // The creep term, from the points without stiffness at this iterate (a
  // separated cohesionless point): eps V M |grad N|^2 on the diagonal of
  // their nodes' displacements. Elsewhere none: a stiffness on every node
  // would stiffen a long column's softest modes by far more than eps.
  std::fill(creep_.begin(), creep_.end(), 0.0);
  const bool distributed = linear_->distributed != nullptr;
  const double* material = pts.data(pts.core().material_id);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double* D = &tangent_[p * 36];
    if (!without_stiffness(D)) continue;
    const double creep = scene_.quasi_static.creep * V[p] * modulus_[static_cast<std::size_t>(material[p])];
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k = p * s.npp + a;
      double* creep_I = creep_.data() + static_cast<std::size_t>(s.ids[k]) * dim;
      for (int i = 0; i < dim; ++i) creep_I[i] += creep * s.gradients[k * dim + i] * s.gradients[k * dim + i];
    }
  }
  // Every process's creep_: the residual reads it (evaluate).
  if (distributed && d_.comm.any(std::any_of(creep_.begin(), creep_.end(), [](double c) { return c != 0; })))
    sum_over_processes(creep_);
  // The blocks: row and column i < dim the displacement components, dim the pressure.
  const int w = dim + 1, bsize = w * w;
  std::fill(blocks_.begin(), blocks_.end(), 0.0);
  double DB[6][3];
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double* D = &tangent_[p * 36];
    const bool wet = n && n[p] > 0;
    const double k = wet ? K[p] / (rho_w[p] * reference_gravity) : 0.0;
    const int* ijk = &point_nodes_ijk_[p * s.npp * 3];
    for (int b = 0; b < s.npp; ++b) {
      const std::size_t qb = p * s.npp + b;
      const double* gb_raw = &s.gradients[qb * dim];
      const std::array<double, 3> gb = padded(gb_raw, dim);
      for (int r = 0; r < 6; ++r)
        for (int j = 0; j < dim; ++j) {
          double v = 0;
          for (int q = 0; q < 6; ++q) v += D[r * 6 + q] * strain_of(q, j, gb.data());
          DB[r][j] = v;
        }
      for (int a = 0; a < s.npp; ++a) {
        const std::size_t qa = p * s.npp + a;
        const std::int64_t row_node = block_node_[s.ids[qa]];
        if (row_node < 0) continue;
        std::size_t slot = 0;
        for (int i = dim - 1; i >= 0; --i)
          slot = slot * stencil_width_ + (ijk[b * 3 + i] - ijk[a * 3 + i] + stencil_radius_);
        slot += static_cast<std::size_t>(row_node) * stencil_slots_;
        block_used_[slot] = 1;
        double* B = &blocks_[slot * bsize];
        const std::array<double, 3> ga = padded(&s.gradients[qa * dim], dim);
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) {
            double v = 0;
            for (int r = 0; r < 6; ++r) v += strain_of(r, i, ga.data()) * DB[r][j];
            B[i * w + j] += V[p] * v;
          }
        if (!wet) continue;
        // -Q: the pressure's force, and (transposed) the volume change; -C: storage and flow.
        for (int i = 0; i < dim; ++i) {
          B[i * w + dim] -= V[p] * ga[i] * s.weights[qb];
          B[dim * w + i] -= V[p] * gb[i] * s.weights[qa];
        }
        double flow = 0;
        for (int i = 0; i < dim; ++i) flow += ga[i] * gb_raw[i];
        B[dim * w + dim] -= V[p] * (s.weights[qa] * s.weights[qb] * n[p] / KL[p] + dt * k * flow);
      }
    }
  }
  // Blocks to the sparse matrix: every entry of a used block between two
  // unknowns, zeros included, so that the pattern stays that of the step.
  auto& t = linear_->triplets;
  t.clear();
  for (std::size_t c = 0; c < block_nodes_.size(); ++c) {
    const auto I = static_cast<std::size_t>(block_nodes_[c]);
    const auto ijk_I = d_.grid.node_ijk(block_nodes_[c]);
    for (std::size_t slot = 0; slot < stencil_slots_; ++slot) {
      if (!block_used_[c * stencil_slots_ + slot]) continue;
      std::array<int, 3> ijk_J = ijk_I;
      std::size_t rest = slot;
      for (int i = 0; i < dim; ++i) {
        ijk_J[i] += static_cast<int>(rest % stencil_width_) - stencil_radius_;
        rest /= stencil_width_;
      }
      const auto J = static_cast<std::size_t>(d_.grid.node_index(ijk_J[0], ijk_J[1], ijk_J[2]));
      const double* B = &blocks_[(c * stencil_slots_ + slot) * bsize];
      for (int i = 0; i < w; ++i) {
        const std::int64_t row = i < dim ? u_dof_[I * dim + i] : p_dof_[I];
        if (row < 0) continue;
        for (int j = 0; j < w; ++j) {
          const std::int64_t col = j < dim ? u_dof_[J * dim + j] : p_dof_[J];
          if (col < 0) continue;
          double v = B[i * w + j];
          if (i == j && I == J && i < dim && !distributed) v += creep_[I * dim + i];
          t.emplace_back(static_cast<int>(row), static_cast<int>(col), v);
        }
      }
    }
  }
  Linear& L = *linear_;
  if (distributed) {  // each process adds its points' blocks, and the first the creep term
    if (d_.comm.root())
      for (std::size_t k = 0; k < u_dof_.size(); ++k)
        if (u_dof_[k] >= 0 && creep_[k] != 0) t.emplace_back(static_cast<int>(u_dof_[k]), static_cast<int>(u_dof_[k]), creep_[k]);
    DistributedSystem& system = *L.distributed;
    if (!L.distributed_started) {
      system.start(equations_);
      system.set_fields(displacement_equations_);
      L.distributed_started = true;
    } else {
      system.restart();
    }
    system.add(t, stencil_slots_ * static_cast<std::size_t>(w));
    system.finish(true);
    return;
  }
  const auto size = static_cast<Eigen::Index>(equations_);
  L.matrix.resize(size, size);
  L.matrix.setFromTriplets(t.begin(), t.end());
  L.scale.resize(size);
  const Eigen::VectorXd diagonal = L.matrix.diagonal();
  for (Eigen::Index i = 0; i < size; ++i) L.scale[i] = diagonal[i] != 0 ? 1 / std::sqrt(std::abs(diagonal[i])) : 1.0;
  for (Eigen::Index c = 0; c < L.matrix.outerSize(); ++c)
    for (Linear::Matrix::InnerIterator it(L.matrix, c); it; ++it) it.valueRef() *= L.scale[it.row()] * L.scale[it.col()];
  if (!L.factorise())
    throw Error(std::string("the quasi-static system is singular: ") + Linear::singular);
}

}  // namespace suffuse::detail
