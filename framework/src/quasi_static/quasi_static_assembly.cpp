// The matrix of a quasi-static Newton iteration: the phases' tangents and the
// u-p coupling accumulated in blocks per node pair, then one sparse matrix,
// scaled (QuasiStatic::newton factorises it or reuses earlier factors).
#include <algorithm>
#include <array>
#include <cmath>
#include <span>

#include "quasi_static/quasi_static_linear.hpp"
#include "suffuse/error.hpp"
#include "suffuse/liquid.hpp"

namespace suffuse::detail {

namespace {


// The Voigt components (xx, yy, zz, yz, xz, xy) a displacement strains:
// in plane strain only xx, yy and xy.
template <int dim>
constexpr std::array<int, 6> strained_components =
    dim == 2 ? std::array<int, 6>{0, 1, 5, 0, 0, 0} : std::array<int, 6>{0, 1, 2, 3, 4, 5};
template <int dim>
constexpr int strained_count = dim == 2 ? 3 : 6;

// Engineering strain of the Voigt component r from the displacement of a
// node along axis i, g its shape function's gradient (dim components): B[r][i].
// r must be one of strained_components<dim>: in 2D the others would read g[2].
template <int dim>
inline double strain_of(int r, int i, const double* g) {
  constexpr int first[6] = {0, 1, 2, 1, 0, 0}, second[6] = {0, 1, 2, 2, 2, 1};
  const int k = first[r], l = second[r];
  if (k == l) return i == k ? g[i] : 0.0;
  if (i == k) return g[l];
  if (i == l) return g[k];
  return 0.0;
}

// What one point adds to the blocks of its node pairs (QuasiStatic::assemble).
struct BlockTerms {
  const ExpandedSupports& s;
  const double* tangents;  // 36 per point
  const double *V, *n, *KL, *K, *rho_w;  // n and the rest null in dry runs
  // Phreatic scenes (mixture/drainage.hpp), per point at the iterate (null
  // in others): the pressure's push on the skeleton (1 where psi >= 0, else
  // 0), the saturation S, the water stored per unit volume and pressure,
  // k_r, and the flow's change with psi through k_r (3 per point).
  const double *coupling, *saturation, *capacity, *relative, *drift;
  const int* point_nodes_ijk;
  const std::int64_t* block_node;
  int stencil_radius, stencil_width;
  std::size_t stencil_slots;
  double dt;
  double* blocks;
  char* block_used;
};

// Templated on the dimension so that the strain-displacement products,
// with their zeros, unroll to the few multiplications that are not.
template <int dim>
void add_point_blocks(const BlockTerms& t, std::size_t p) {
  constexpr int w = dim + 1, bsize = w * w, rows = strained_count<dim>;
  constexpr auto component = strained_components<dim>;
  const int npp = t.s.npp;
  double D[rows][rows];
  for (int r = 0; r < rows; ++r)
    for (int q = 0; q < rows; ++q) D[r][q] = t.tangents[p * 36 + component[r] * 6 + component[q]];
  const double V = t.V[p];
  const bool wet = t.n && t.n[p] > 0;
  double storage = wet ? V * t.n[p] / t.KL[p] : 0.0;
  double flow = wet ? V * t.dt * t.K[p] / (t.rho_w[p] * reference_gravity) : 0.0;
  // Where the pores drain (Newton's exact terms, which are not symmetric):
  // the retention curve stores water, the flow has k_r and changes with psi
  // through it, the pressure pushes on the skeleton only where psi >= 0,
  // and the skeleton's volume change moves the water the pores hold, S.
  double coupling = 1, volume = 1;
  const double* drift = nullptr;
  if (wet && t.coupling) {
    storage = V * t.capacity[p];
    flow *= t.relative[p];
    coupling = t.coupling[p], volume = t.saturation[p];
    drift = t.drift + p * 3;
  }
  const int* ijk = &t.point_nodes_ijk[p * npp * 3];
  for (int b = 0; b < npp; ++b) {
    const std::size_t qb = p * npp + b;
    const double* gb = &t.s.gradients[qb * dim];
    const double Nb = t.s.weights[qb];
    double DB[rows][dim];
    for (int r = 0; r < rows; ++r)
      for (int j = 0; j < dim; ++j) {
        double v = 0;
        for (int q = 0; q < rows; ++q) v += D[r][q] * strain_of<dim>(component[q], j, gb);
        DB[r][j] = V * v;
      }
    for (int a = 0; a < npp; ++a) {
      const std::size_t qa = p * npp + a;
      const std::int64_t row_node = t.block_node[t.s.ids[qa]];
      if (row_node < 0) continue;
      std::size_t slot = 0;
      for (int i = dim - 1; i >= 0; --i)
        slot = slot * t.stencil_width + (ijk[b * 3 + i] - ijk[a * 3 + i] + t.stencil_radius);
      slot += static_cast<std::size_t>(row_node) * t.stencil_slots;
      t.block_used[slot] = 1;
      double* B = &t.blocks[slot * bsize];
      const double* ga = &t.s.gradients[qa * dim];
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < dim; ++j) {
          double v = 0;
          for (int r = 0; r < rows; ++r) v += strain_of<dim>(component[r], i, ga) * DB[r][j];
          B[i * w + j] += v;
        }
      if (!wet) continue;
      // -Q: the pressure's force, and (transposed) the volume change; -C: storage and flow.
      const double Na = t.s.weights[qa];
      double grad_dot = 0;
      for (int i = 0; i < dim; ++i) {
        B[i * w + dim] -= coupling * V * ga[i] * Nb;
        B[dim * w + i] -= volume * V * gb[i] * Na;
        grad_dot += ga[i] * gb[i];
      }
      B[dim * w + dim] -= storage * Na * Nb + flow * grad_dot;
      if (drift) {
        double along = 0;
        for (int i = 0; i < dim; ++i) along += ga[i] * drift[i];
        B[dim * w + dim] -= t.dt * V * along * Nb;
      }
    }
  }
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
  linear_->distributed_started = false;
  linear_->value_at.clear();  // the next assembly builds the step's matrix
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
  linear_->symmetric = !phreatic_ && symmetric_tangents(tangent_);
  // The creep term, from the points without stiffness at this iterate, or
  // without it in some direction (a cohesionless point separated across a
  // plane: coupling::separated_directions): eps V M |grad N|^2 on the
  // diagonal of their nodes' displacements. Elsewhere none: a stiffness on
  // every node would stiffen a long column's softest modes by far more than
  // eps.
  std::fill(creep_.begin(), creep_.end(), 0.0);
  const bool distributed = linear_->distributed != nullptr;
  const double* material = pts.data(pts.core().material_id);
  const auto separated_field = pts.find(coupling::separated_directions);
  const double* separated = separated_field ? pts.data(*separated_field) : nullptr;
  double held = 0;  // points that give the creep term
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double* D = &tangent_[p * 36];
    if (!without_stiffness(D) && !(separated && separated[p] > 0)) continue;
    held += 1;
    const double creep = scene_.quasi_static.creep * V[p] * modulus_[static_cast<std::size_t>(material[p])];
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k = p * s.npp + a;
      double* creep_I = creep_.data() + static_cast<std::size_t>(s.ids[k]) * dim;
      for (int i = 0; i < dim; ++i) creep_I[i] += creep * s.gradients[k * dim + i] * s.gradients[k * dim + i];
    }
  }
  d_.comm.sum(std::span<double>(&held, 1));
  creep_held_points_ = static_cast<std::size_t>(held);
  // Every process's creep_: the residual reads it (evaluate).
  if (distributed && creep_held_points_ > 0) sum_over_processes(creep_);
  // What the nodes' own terms add to a displacement equation's diagonal: the
  // creep term, and the inertia (M / dt^2) with /time/inertia.
  const auto own_diagonal = [&](std::size_t k) { return creep_[k] + (inertia_.empty() ? 0.0 : inertia_[k]); };
  // The blocks: row and column i < dim the displacement components, dim the pressure.
  const int w = dim + 1, bsize = w * w;
  std::fill(blocks_.begin(), blocks_.end(), 0.0);
  const bool drains = phreatic_ && !coupling_.empty();
  const BlockTerms terms{s, tangent_.data(), V, n, KL, K, rho_w,
                         drains ? coupling_.data() : nullptr, drains ? saturation_.data() : nullptr,
                         drains ? capacity_.data() : nullptr, drains ? relative_.data() : nullptr,
                         drains ? drift_.data() : nullptr, point_nodes_ijk_.data(), block_node_.data(),
                         stencil_radius_, stencil_width_, stencil_slots_, dt, blocks_.data(), block_used_.data()};
  for (std::size_t p = 0; p < pts.size(); ++p) dim == 2 ? add_point_blocks<2>(terms, p) : add_point_blocks<3>(terms, p);
  // Blocks to the sparse matrix: every entry of a used block between two
  // unknowns, zeros included, so that the pattern stays that of the step.
  // The step's first assembly builds the matrix from triplets; later ones
  // write the same entries, in the same order, into its values.
  Linear& L = *linear_;
  const bool in_place = L.value_at.size() > 0 && !distributed;
  auto& t = L.triplets;
  t.clear();
  double* values = in_place ? L.matrix.valuePtr() : nullptr;
  if (in_place) std::fill(values, values + L.matrix.nonZeros(), 0.0);  // entries extrapolated nodes share add up
  std::size_t entry = 0;
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
          if (i == dim) v *= p_weight_[I];  // an extrapolated node's equation joins its inner node's
          if (j == dim) v *= p_weight_[J];
          if (i == j && I == J && i < dim && !distributed) v += own_diagonal(I * dim + i);
          if (in_place) {
            if (entry < L.value_at.size()) values[L.value_at[entry]] += v;
            ++entry;  // more than the step's first assembly had: a defect, reported below
          } else
            t.emplace_back(static_cast<int>(row), static_cast<int>(col), v);
        }
      }
    }
  }
  // The pattern is the step's (prepare_blocks): entries that changed within
  // a step would be a defect of this code, not of the scene.
  if (in_place && entry != L.value_at.size())
    throw Error("internal error: the quasi-static matrix changed its pattern within a step; please report the scene");
  if (distributed) {  // each process adds its points' blocks, and the nodes' own terms of the rows it holds
    DistributedSystem& system = *L.distributed;
    if (!L.distributed_started) {
      system.start(equations_);
      system.set_fields(displacement_equations_);
      L.distributed_started = true;
    } else {
      system.restart();
    }
    const auto [first, last] = system.rows();
    for (std::size_t k = 0; k < u_dof_.size(); ++k) {
      const std::int64_t row = u_dof_[k];
      if (row >= 0 && static_cast<std::size_t>(row) >= first && static_cast<std::size_t>(row) < last &&
          own_diagonal(k) != 0)
        t.emplace_back(static_cast<int>(row), static_cast<int>(row), own_diagonal(k));
    }
    // An inner node that surface nodes follow has a few entries more: PETSc lets them grow.
    system.add(t, stencil_slots_ * static_cast<std::size_t>(w));
    system.finish(true);
    return;
  }
  const auto size = static_cast<Eigen::Index>(equations_);
  if (!in_place) {
    L.matrix.resize(size, size);
    L.matrix.setFromTriplets(t.begin(), t.end());
    // Where each triplet's value lies (some share one: an extrapolated node's with its inner node's).
    const int* outer = L.matrix.outerIndexPtr();
    const int* inner = L.matrix.innerIndexPtr();
    L.value_at.resize(t.size());
    for (std::size_t e = 0; e < t.size(); ++e)
      L.value_at[e] = static_cast<std::size_t>(
          std::lower_bound(inner + outer[t[e].col()], inner + outer[t[e].col() + 1], t[e].row()) - inner);
    L.new_step_pattern(u_dof_, p_dof_);
  }
  L.scale.resize(size);
  const Eigen::VectorXd diagonal = L.matrix.diagonal();
  for (Eigen::Index i = 0; i < size; ++i) L.scale[i] = diagonal[i] != 0 ? 1 / std::sqrt(std::abs(diagonal[i])) : 1.0;
  for (Eigen::Index c = 0; c < L.matrix.outerSize(); ++c)
    for (Linear::Matrix::InnerIterator it(L.matrix, c); it; ++it) it.valueRef() *= L.scale[it.row()] * L.scale[it.col()];
}

bool QuasiStatic::factorise_or_throw() {
  ++factorisations_;
  if (linear_->factorise()) return true;
  // A strength reduction's, or a run's under /failure: no equilibrium there.
  if (reduction_ || singular_fails_attempt_) return singular_ = true, false;
  throw Error(std::string("the quasi-static system is singular: ") + Linear::singular + Linear::failing);
}

}  // namespace suffuse::detail
