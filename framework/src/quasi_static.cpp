#include "quasi_static.hpp"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "solid_kernels.hpp"
#include "suffuse/error.hpp"
#include "suffuse/grid_face.hpp"
#include "suffuse/liquid.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse::detail {

struct QuasiStatic::Linear {
  using Matrix = Eigen::SparseMatrix<double>;
  std::vector<Eigen::Triplet<double>> triplets;
  Matrix matrix;
  Eigen::VectorXd scale;  // symmetric diagonal scaling: the blocks differ by many orders of magnitude
  // Symmetric tangents: LDL' (half the work and memory of LU). A tangent
  // that is not symmetric (Mohr-Coulomb's with psi < phi): LU.
  bool symmetric = true;
  Eigen::SimplicialLDLT<Matrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  Eigen::SparseLU<Matrix, Eigen::COLAMDOrdering<int>> lu;
  // The pattern is that of the step (QuasiStatic::prepare_blocks): its
  // ordering and symbolic analysis are done once per step and solver.
  bool ldlt_analysed = false, lu_analysed = false;

  bool factorise() {
    if (symmetric && !ldlt_analysed) ldlt.analyzePattern(matrix), ldlt_analysed = true;
    if (!symmetric && !lu_analysed) lu.analyzePattern(matrix), lu_analysed = true;
    if (symmetric) {
      ldlt.factorize(matrix);
      return ldlt.info() == Eigen::Success;
    }
    lu.factorize(matrix);
    return lu.info() == Eigen::Success;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    const Eigen::VectorXd scaled = scale.asDiagonal() * rhs;
    return scale.asDiagonal() * (symmetric ? Eigen::VectorXd(ldlt.solve(scaled)) : Eigen::VectorXd(lu.solve(scaled)));
  }
};

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

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

QuasiStatic::QuasiStatic(const Scene& scene, Domain& domain, const Materials& materials, SaturatedMixture* mixture,
                         const std::vector<std::unique_ptr<BoundaryCondition>>& bcs)
    : scene_(scene), d_(domain), materials_(materials), mixture_(mixture), bcs_(bcs),
      linear_(std::make_unique<Linear>()) {
  const std::size_t nn = d_.grid.node_count();
  const int dim = d_.dim();
  probe_.resize(nn, dim, mixture_ != nullptr);
  for (auto* v : {&node_mass_, &node_pore_, &node_volume_, &p_}) v->assign(nn, 0.0);
  du_.assign(nn * dim, 0.0);
  f_ext_.assign(nn * dim, 0.0);
  for (std::size_t m = 0; m < scene.materials.size(); ++m) modulus_.push_back(materials.phase(m).p_wave_modulus());
  std::size_t cells = 1;
  for (int a = 0; a < dim; ++a) cells *= static_cast<std::size_t>(d_.grid.cells()[a]);
  cell_count_.assign(cells, 0);
}

QuasiStatic::~QuasiStatic() = default;

void QuasiStatic::save_state() {
  const auto& ids = materials_.stress_state_fields();
  saved_.resize(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const auto v = d_.points.values(ids[k]);
    saved_[k].assign(v.begin(), v.end());
  }
}

void QuasiStatic::restore_state() {
  const auto& ids = materials_.stress_state_fields();
  for (std::size_t k = 0; k < ids.size(); ++k) std::copy(saved_[k].begin(), saved_[k].end(), d_.points.data(ids[k]));
}

void QuasiStatic::prepare(double time, double dt) {
  const int dim = d_.dim();
  const std::size_t nn = d_.grid.node_count();
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const Interpolation& s = d_.shape;
  const double* m = pts.data(c.mass);
  const double* V = pts.data(c.volume);
  const double* x = pts.data(c.position);
  const double* n = mixture_ ? pts.data(mixture_->fields().porosity) : nullptr;
  const double* pressure = mixture_ ? pts.data(mixture_->fields().pressure) : nullptr;
  const double* moving = mixture_ ? pts.data(mixture_->fields().moving_liquid_mass) : nullptr;

  // Nodal masses (gravity), pore volumes and the old pressures projected.
  for (auto* v : {&node_mass_, &node_pore_, &node_volume_, &p_}) std::fill(v->begin(), v->end(), 0.0);
  std::fill(f_ext_.begin(), f_ext_.end(), 0.0);
  std::fill(cell_count_.begin(), cell_count_.end(), 0);
  const auto& g = scene_.gravity;
  creep_.assign(nn * dim, 0.0);  // none until a point has no stiffness (assemble)
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const bool wet = n && n[p] > 0;
    const double weight = m[p] + (wet ? moving[p] : 0.0);
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k = p * s.npp + a;
      const std::int64_t I = s.ids[k];
      const double N = s.weights[k];
      node_mass_[I] += N * m[p];
      for (int i = 0; i < dim; ++i) f_ext_[I * dim + i] += N * weight * g[i];
      if (!wet) continue;
      node_pore_[I] += N * n[p] * V[p];
      node_volume_[I] += N * V[p];
      p_[I] += N * V[p] * pressure[p];
    }
    if (!wet) continue;
    std::int64_t cell = 0, stride = 1;
    for (int a = 0; a < dim; ++a) {
      const int i = static_cast<int>(std::floor((x[p * dim + a] - d_.grid.origin()[a]) / d_.grid.cell_size()[a]));
      cell += stride * std::clamp(i, 0, d_.grid.cells()[a] - 1);
      stride *= d_.grid.cells()[a];
    }
    ++cell_count_[cell];
  }
  for (std::size_t I = 0; I < nn; ++I)
    if (node_volume_[I] > 0) p_[I] /= node_volume_[I];

  // What the boundary conditions do: loads at the end of the step, and the
  // components they constrain (left NaN where they do not).
  const double t1 = time + dt;
  for (auto* v : {&probe_.force, &probe_.liquid_force}) std::fill(v->begin(), v->end(), 0.0);
  std::fill(probe_.velocity.begin(), probe_.velocity.end(), nan);
  if (mixture_) {
    std::fill(probe_.liquid_velocity.begin(), probe_.liquid_velocity.end(), nan);
    probe_.liquid_mass = node_pore_;  // their ratio is the nodal porosity
    probe_.liquid_inertia = node_volume_;
  }
  for (const auto& bc : bcs_) {
    bc->apply_forces(d_.grid, probe_, t1);
    bc->apply_point_forces(d_.grid, pts, probe_, t1);
  }
  for (const auto& bc : bcs_) bc->constrain_velocity(d_.grid, probe_, t1);
  for (std::size_t k = 0; k < f_ext_.size(); ++k) f_ext_[k] += probe_.force[k];

  // Displacement unknowns: components of nodes with mass, unless constrained.
  equations_ = 0;
  u_dof_.assign(nn * dim, -1);
  for (std::size_t I = 0; I < nn; ++I)
    for (int i = 0; i < dim; ++i) {
      const std::size_t k = I * dim + i;
      du_[k] = 0;
      if (node_mass_[I] <= 0) continue;
      if (std::isnan(probe_.velocity[k]))
        u_dof_[k] = static_cast<std::int64_t>(equations_++);
      else
        du_[k] = probe_.velocity[k] * dt;
    }

  // Pressure unknowns: nodes with pore volume, unless a face open to the
  // liquid or a free surface fixes their pressure.
  p_dof_.assign(nn, -1);
  b_p_.assign(nn, 0.0);
  if (!mixture_) return;
  std::vector<char>& fixed = fixed_pressure_;
  fixed.assign(nn, 0);
  face_flux_.clear();
  for (const auto& bc : bcs_)
    for (const LiquidOpening& opening : bc->liquid_openings()) {
      const GridFace f = opening.face;
      for (const std::int64_t I : face_nodes(d_.grid, f)) {
        if (node_pore_[I] <= 0) continue;
        const std::size_t k = static_cast<std::size_t>(I) * dim + f.axis;
        const double area = face_node_area(d_.grid, f, I);
        if (!std::isnan(probe_.liquid_velocity[k]) && !std::isnan(probe_.velocity[k])) {
          // A prescribed flux: n (v_L - v_s) enters against the outward normal.
          const double nI = node_pore_[I] / node_volume_[I];
          b_p_[I] -= dt * f.outward() * nI * (probe_.liquid_velocity[k] - probe_.velocity[k]) * area;
        } else if (!fixed[I]) {
          fixed[I] = 1;  // the pressure whose traction -p n the condition applied
          p_[I] = -probe_.liquid_force[k] * f.outward() / area;
          face_flux_.push_back({I, f.axis, f.outward(), area});
        } else {  // a corner two open faces share: its residual is their sum
          std::erase_if(face_flux_, [&](const FaceFlux& ff) { return ff.node == I; });
        }
      }
    }
  // Free surfaces: next to a cell inside the grid that holds no saturated point.
  const auto& cells = d_.grid.cells();
  for (std::size_t I = 0; I < nn; ++I) {
    if (node_pore_[I] <= 0 || fixed[I]) continue;
    const auto ijk = d_.grid.node_ijk(static_cast<std::int64_t>(I));
    bool surface = false;
    for (int corner = 0; corner < (1 << dim) && !surface; ++corner) {
      std::int64_t cell = 0, stride = 1;
      bool inside = true;
      for (int a = 0; a < dim; ++a) {
        const int ci = ijk[a] - ((corner >> a) & 1);
        inside = inside && ci >= 0 && ci < cells[a];
        cell += stride * ci;
        stride *= cells[a];
      }
      surface = inside && cell_count_[cell] == 0;
    }
    if (surface) {
      fixed[I] = 1;
      p_[I] = 0;
    }
  }
  for (std::size_t I = 0; I < nn; ++I)
    if (node_pore_[I] > 0 && !fixed[I]) p_dof_[I] = static_cast<std::int64_t>(equations_++);

  // The rest of the pressure equations' right-hand side: the storage of the
  // old pressures and the flow gravity drives, -dt sum V k rho_L g . grad N.
  const auto& mf = mixture_->fields();
  const double* KL = pts.data(mf.bulk_modulus);
  const double* K = pts.data(mf.conductivity);
  const double* rho_w = pts.data(mf.water_density);
  const double* rho_l = pts.data(mf.liquid_density);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    if (!(n[p] > 0)) continue;
    const double storage = V[p] * n[p] / KL[p] * pressure[p];
    const double k = K[p] / (rho_w[p] * reference_gravity);
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t q = p * s.npp + a;
      const std::int64_t I = s.ids[q];
      double g_dot = 0;
      for (int i = 0; i < dim; ++i) g_dot += g[i] * s.gradients[q * dim + i];
      b_p_[I] += s.weights[q] * storage + dt * V[p] * k * rho_l[p] * g_dot;
    }
  }
}

// The stresses of the current increments (each phase's own update from the
// state at the start of the step) and the out-of-balance forces and
// volumes; returns the norm of the forces at the free components.
double QuasiStatic::evaluate(double dt) {
  const int dim = d_.dim();
  const std::size_t nn = d_.grid.node_count();
  for (std::size_t k = 0; k < du_.size(); ++k) d_.nodes.velocity[k] = du_[k] / dt;
  d_.update_velocity_gradient(dt);
  materials_.update_stress(d_, dt);

  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const Interpolation& s = d_.shape;
  const double* V = pts.data(c.volume);
  const double* sigma = pts.data(c.stress);
  const double* n = mixture_ ? pts.data(mixture_->fields().porosity) : nullptr;
  const double* KL = mixture_ ? pts.data(mixture_->fields().bulk_modulus) : nullptr;
  const double* K = mixture_ ? pts.data(mixture_->fields().conductivity) : nullptr;
  const double* rho_w = mixture_ ? pts.data(mixture_->fields().water_density) : nullptr;
  std::vector<double>& f_int = f_int_;
  f_int.assign(nn * dim, 0.0);
  std::vector<double>& r_p = r_p_;
  r_p = b_p_;
  point_pressure_.assign(pts.size(), 0.0);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const bool wet = n && n[p] > 0;
    double pp = 0, grad_p[3] = {0, 0, 0}, div_u = 0;
    if (wet)
      for (int a = 0; a < s.npp; ++a) {
        const std::size_t q = p * s.npp + a;
        const std::int64_t I = s.ids[q];
        pp += s.weights[q] * p_[I];
        for (int i = 0; i < dim; ++i) {
          grad_p[i] += s.gradients[q * dim + i] * p_[I];
          div_u += s.gradients[q * dim + i] * du_[I * dim + i];
        }
      }
    point_pressure_[p] = pp;
    const double* sp = sigma + p * 6;
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t q = p * s.npp + a;
      const std::int64_t I = s.ids[q];
      const double* gN = &s.gradients[q * dim];
      for (int i = 0; i < dim; ++i) {
        double f = -V[p] * pp * gN[i];  // total stress sigma' - p I
        for (int j = 0; j < dim; ++j) f += V[p] * sp[tensor::voigt_index(i, j)] * gN[j];
        f_int[I * dim + i] += f;
      }
      if (!wet) continue;
      const double k = K[p] / (rho_w[p] * reference_gravity);
      double flow = 0;
      for (int i = 0; i < dim; ++i) flow += gN[i] * grad_p[i];
      r_p[I] -= s.weights[q] * V[p] * (n[p] / KL[p] * pp + div_u) + dt * V[p] * k * flow;
    }
  }
  double r2 = 0, f2 = 0, i2 = 0;
  for (std::size_t I = 0; I < nn; ++I)
    for (int i = 0; i < dim; ++i) {
      const std::size_t k = I * dim + i;
      if (node_mass_[I] <= 0) continue;
      f2 += f_ext_[k] * f_ext_[k];
      i2 += f_int[k] * f_int[k];
      if (u_dof_[k] < 0) continue;
      const double r = f_ext_[k] - f_int[k] - creep_[k] * du_[k];
      residual_[static_cast<std::size_t>(u_dof_[k])] = r;
      r2 += r * r;
    }
  for (std::size_t I = 0; I < nn; ++I)
    if (p_dof_[I] >= 0) residual_[static_cast<std::size_t>(p_dof_[I])] = -r_p[I];
  force_scale_ = std::sqrt(std::max(f2, i2));
  return std::sqrt(r2);
}

// The nodes of a point's support, as the slots of node pairs: the matrix is
// accumulated in blocks, one per pair of nodes that share a point, (dim + 1)
// square (the displacements and the pressure), before it becomes a sparse
// matrix. A point adds to each of its npp^2 pairs; many points share a pair,
// so this is a few times fewer entries to sort than one triplet per point
// and pair.
void QuasiStatic::prepare_blocks() {
  const int dim = d_.dim();
  const Interpolation& s = d_.shape;
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
  linear_->ldlt_analysed = linear_->lu_analysed = false;
}

void QuasiStatic::assemble(double dt) {
  const int dim = d_.dim();
  PointSet& pts = d_.points;
  const Interpolation& s = d_.shape;
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
  const double* material = pts.data(pts.core().material_id);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double* D = &tangent_[p * 36];
    if (D[0] != 0 || D[7] != 0 || D[14] != 0 || D[35] != 0) continue;
    const double creep = scene_.quasi_static.creep * V[p] * modulus_[static_cast<std::size_t>(material[p])];
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k = p * s.npp + a;
      for (int i = 0; i < dim; ++i) creep_[s.ids[k] * dim + i] += creep * s.gradients[k * dim + i] * s.gradients[k * dim + i];
    }
  }
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
          if (i == j && I == J && i < dim) v += creep_[I * dim + i];
          t.emplace_back(static_cast<int>(row), static_cast<int>(col), v);
        }
      }
    }
  }
  const auto size = static_cast<Eigen::Index>(equations_);
  Linear& L = *linear_;
  L.matrix.resize(size, size);
  L.matrix.setFromTriplets(t.begin(), t.end());
  L.scale.resize(size);
  const Eigen::VectorXd diagonal = L.matrix.diagonal();
  for (Eigen::Index i = 0; i < size; ++i) L.scale[i] = diagonal[i] != 0 ? 1 / std::sqrt(std::abs(diagonal[i])) : 1.0;
  for (Eigen::Index c = 0; c < L.matrix.outerSize(); ++c)
    for (Linear::Matrix::InnerIterator it(L.matrix, c); it; ++it) it.valueRef() *= L.scale[it.row()] * L.scale[it.col()];
  if (!L.factorise())
    throw Error("the quasi-static system is singular: a body that nothing holds (check the velocity "
                "conditions), or pore pressure with no face to drain to and no storage");
}

// Newton iterations on the true stresses, the matrix from the phases'
// tangents at each iterate (a cohesionless point that separates has none).
std::optional<int> QuasiStatic::solve(double time, double dt) {
  prepare(time, dt);
  prepare_blocks();
  residual_.assign(equations_, 0.0);
  save_state();
  int iterations = 0;
  if (newton(dt, iterations)) return iterations;
  return std::nullopt;
}

bool QuasiStatic::newton(double dt, int& iterations) {
  const QuasiStaticControls& control = scene_.quasi_static;
  Linear& L = *linear_;
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(equations_));
  // The size of the residual a line search compares: scaled as the system,
  // so that forces and liquid volumes count alike.
  auto merit = [&] {
    double sum = 0;
    for (std::size_t e = 0; e < equations_; ++e) sum += std::pow(L.scale[static_cast<Eigen::Index>(e)] * residual_[e], 2);
    return std::sqrt(sum);
  };
  std::vector<double>& du0 = du_previous_;
  std::vector<double>& p0 = p_previous_;
  restore_state();
  double norm = evaluate(dt);
  for (int iteration = 0;; ++iteration) {
    if (!std::isfinite(norm)) break;
    // The first evaluation has the old pressures: at least one solve.
    if (iteration > 0 && norm <= control.newton_tolerance * force_scale_) return true;
    if (iteration == control.max_iterations) break;
    ++iterations;
    materials_.tangent(d_, dt, tangent_);
    assemble(dt);
    for (std::size_t e = 0; e < equations_; ++e) rhs[static_cast<Eigen::Index>(e)] = residual_[e];
    const Eigen::VectorXd delta = L.solve(rhs);
    // Backtracking: far from equilibrium a full Newton step on a perfectly
    // plastic skeleton can overshoot onto the wrong side of many returns;
    // halve it until the residual falls (Armijo), at most six times.
    const double before = merit();
    du0 = du_, p0 = p_;
    double alpha = 1;
    for (int halving = 0;; ++halving) {
      for (std::size_t k = 0; k < u_dof_.size(); ++k)
        if (u_dof_[k] >= 0) du_[k] = du0[k] + alpha * delta[u_dof_[k]];
      for (std::size_t I = 0; I < p_dof_.size(); ++I)
        if (p_dof_[I] >= 0) p_[I] = p0[I] + alpha * delta[p_dof_[I]];
      restore_state();
      norm = evaluate(dt);
      if (halving == 6 || (std::isfinite(norm) && merit() <= (1 - 1e-4 * alpha) * before)) break;
      alpha /= 2;
    }
  }
  restore_state();
  return false;
}

void QuasiStatic::update_points(double dt) {
  const int dim = d_.dim();
  d_.update_kinematics(dt);  // strain and volume; L as the last iteration had it
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const Interpolation& s = d_.shape;
  double* x = pts.data(c.position);
  double* u = pts.data(c.displacement);
  double* v = pts.data(c.velocity);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    double du[3] = {0, 0, 0};
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t q = p * s.npp + a;
      for (int i = 0; i < dim; ++i) du[i] += s.weights[q] * du_[s.ids[q] * dim + i];
    }
    for (int i = 0; i < dim; ++i) {
      x[p * dim + i] += du[i];
      u[p * dim + i] += du[i];
      v[p * dim + i] = du[i] / dt;
    }
  }
  if (!mixture_) return;

  // Pore pressure, porosity (incompressible grains), Darcy flux and the
  // liquid's velocity at the points; the nodal Darcy flux of the transport.
  const auto& mf = mixture_->fields();
  double* n = pts.data(mf.porosity);
  double* dn = pts.data(mf.porosity_increment);
  double* pressure = pts.data(mf.pressure);
  double* rate = pts.data(mf.pressure_rate);
  double* q = pts.data(mf.darcy_flux);
  double* vl = pts.data(mf.liquid_velocity);
  const double* K = pts.data(mf.conductivity);
  const double* rho_w = pts.data(mf.water_density);
  const double* rho_l = pts.data(mf.liquid_density);
  const double* L = pts.data(c.velocity_gradient);
  const double* V = pts.data(c.volume);
  const auto& g = scene_.gravity;
  std::vector<double>& node_q = mixture_->nodal_darcy_flux();
  std::fill(node_q.begin(), node_q.end(), 0.0);
  std::fill(node_volume_.begin(), node_volume_.end(), 0.0);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    if (!(n[p] > 0)) continue;
    double pp = 0, grad_p[3] = {0, 0, 0};
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k = p * s.npp + a;
      pp += s.weights[k] * p_[s.ids[k]];
      for (int i = 0; i < dim; ++i) grad_p[i] += s.gradients[k * dim + i] * p_[s.ids[k]];
    }
    rate[p] = (pp - pressure[p]) / dt;
    pressure[p] = pp;
    const double n0 = n[p];
    const double J = dim == 2 ? step_jacobian<2>(L + p * 4, dt) : step_jacobian<3>(L + p * 9, dt);
    n[p] = 1 - (1 - n0) / J;
    dn[p] = n[p] - n0;  // erosion adds its share later in the step
    if (!(n[p] > 0))
      throw Error("material point " + std::to_string(p) + " was compressed to porosity " + std::to_string(n[p]) +
                  ": its grains cannot be compressed; shorten /time/dt or check the loads");
    const double k = K[p] / (rho_w[p] * reference_gravity);
    for (int i = 0; i < dim; ++i) {
      q[p * dim + i] = -k * (grad_p[i] - rho_l[p] * g[i]);
      vl[p * dim + i] = v[p * dim + i] + q[p * dim + i] / n[p];
    }
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k2 = p * s.npp + a;
      const std::int64_t I = s.ids[k2];
      node_volume_[I] += s.weights[k2] * V[p];
      for (int i = 0; i < dim; ++i) node_q[I * dim + i] += s.weights[k2] * V[p] * q[p * dim + i];
    }
  }
  for (std::size_t I = 0; I < node_volume_.size(); ++I)
    for (int i = 0; i < dim; ++i) node_q[I * dim + i] = node_volume_[I] > 0 ? node_q[I * dim + i] / node_volume_[I] : 0.0;
  // Through a face whose pressure is prescribed, the flux is what the
  // pressure equation of its node leaves unbalanced (the weak form's
  // boundary term: the volume leaving there over the step), not the mean of
  // the points near it. That mean takes one side of the face only, and where
  // the conductivity varies across the last cell (a washed-out top) it
  // misses the flow by up to 40%; the transport would then pile the liquid
  // up at the face's nodes until their outflow balanced the inflow.
  for (const FaceFlux& f : face_flux_)
    node_q[static_cast<std::size_t>(f.node) * dim + f.axis] = f.outward * r_p_[f.node] / (dt * f.area);
}

double QuasiStatic::transport_rate() const {
  if (!mixture_) return 0;
  const int dim = d_.dim();
  const PointSet& pts = d_.points;
  const double* n = pts.data(mixture_->fields().porosity);
  const double* q = pts.data(mixture_->fields().darcy_flux);
  double worst = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    if (!(n[p] > 0)) continue;
    double rate = 0;
    for (int i = 0; i < dim; ++i) rate += std::abs(q[p * dim + i]) / (n[p] * d_.grid.cell_size()[i]);
    worst = std::max(worst, rate);
  }
  return worst;
}

}  // namespace suffuse::detail
