// The unknowns of a quasi-static step (quasi_static.hpp), before its
// Newton iterations: the nodal masses, loads and old pressures, what the
// boundary conditions constrain, which nodes have displacement and pressure
// unknowns (tail nodes follow the points, free surfaces are drained or
// under still water), and the pressure equations' right-hand side.
#include <algorithm>
#include <cmath>
#include <limits>

#include "quasi_static/quasi_static.hpp"
#include "suffuse/grid_face.hpp"
#include "suffuse/liquid.hpp"

namespace suffuse::detail {

namespace {
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double min_cover = 1e-4;  // the cover below which a node is a tail node (quasi_static.hpp)
}  // namespace

void QuasiStatic::prepare(double time, double dt) {
  const int dim = d_.dim();
  const std::size_t nn = d_.grid.node_count();
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const ExpandedSupports& s = d_.expanded_shape();
  const double* m = pts.data(c.mass);
  const double* V = pts.data(c.volume);
  const double* x = pts.data(c.position);
  const double* n = mixture_ ? pts.data(mixture_->fields().porosity) : nullptr;
  const double* pressure = mixture_ ? pts.data(mixture_->fields().pressure) : nullptr;
  const double* moving = mixture_ ? pts.data(mixture_->fields().moving_liquid_mass) : nullptr;
  // Drained pores weigh what water they hold; their potential psi is what
  // the old pressures' storage and the first iterate start from.
  const double* saturation = phreatic_ ? pts.data(*mixture_->fields().saturation) : nullptr;
  const double* material = pts.data(c.material_id);
  if (phreatic_) {
    drains_.assign(nn, 0.0);
    const auto psi = pts.values(*mixture_->fields().potential);
    potential_.assign(psi.begin(), psi.end());
  }

  // Nodal masses (gravity), pore volumes and the old pressures projected.
  for (auto* v : {&node_mass_, &node_pore_, &node_volume_, &p_}) std::fill(v->begin(), v->end(), 0.0);
  node_cover_.assign(nn, 0.0);
  std::fill(f_ext_.begin(), f_ext_.end(), 0.0);
  std::fill(cell_count_.begin(), cell_count_.end(), 0.0);
  const auto& g = scene_.gravity;
  creep_.assign(nn * dim, 0.0);  // none until a point has no stiffness (assemble)
  const bool inertia = scene_.quasi_static.inertia && !reduction_;
  const double* v = pts.data(c.velocity);
  if (inertia) {
    inertia_.assign(nn * dim, 0.0);
    inertia_target_.assign(nn * dim, 0.0);
  } else {
    inertia_.clear();  // (a strength reduction's solves in a run with inertia)
    inertia_target_.clear();
  }
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const bool wet = n && n[p] > 0;
    const double weight = m[p] + (wet ? moving[p] : 0.0);  // n S rho_L V where pores drain
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k = p * s.npp + a;
      const std::int64_t I = s.ids[k];
      const double N = s.weights[k];
      node_mass_[I] += N * m[p];
      node_cover_[I] += N * V[p];
      for (int i = 0; i < dim; ++i) f_ext_[I * dim + i] += N * weight * g[i];
      if (inertia)  // the mixture's mass and momentum (the liquid moving with the skeleton, as in u-p)
        for (int i = 0; i < dim; ++i) {
          inertia_[I * dim + i] += N * weight;
          inertia_target_[I * dim + i] += N * weight * v[p * dim + i];
        }
      if (!wet) continue;
      if (saturation && drainage_[static_cast<std::size_t>(material[p])]) drains_[I] += N;
      node_pore_[I] += N * n[p] * V[p];
      node_volume_[I] += N * V[p];
      p_[I] += N * V[p] * (phreatic_ ? potential_[p] : pressure[p]);
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
  for (auto* sums : {&node_mass_, &node_cover_, &f_ext_, &node_pore_, &node_volume_, &p_, &cell_count_})
    sum_over_processes(*sums);
  if (phreatic_) sum_over_processes(drains_);
  // Inertia: M (du - dt v0) / dt^2 in each displacement equation, v0 the
  // nodal velocity at the start of the step (mass-weighted).
  if (inertia) {
    sum_over_processes(inertia_);
    sum_over_processes(inertia_target_);
    for (std::size_t k = 0; k < inertia_.size(); ++k) {
      const double M = inertia_[k];
      inertia_target_[k] = M > 0 ? dt * inertia_target_[k] / M : 0.0;
      inertia_[k] = M / (dt * dt);
    }
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
  apply_loads_(probe_, t1);
  held_.assign(bcs_.size(), {});
  for (std::size_t b = 0; b < bcs_.size(); ++b) {
    const bool recorded = std::any_of(scene_.reactions.begin(), scene_.reactions.end(),
                                      [&](const ReactionSpec& r) { return r.condition == b; });
    if (recorded) velocity_before_.assign(probe_.velocity.begin(), probe_.velocity.end());
    bcs_[b]->constrain_velocity(d_.grid, probe_, t1);
    if (!recorded) continue;
    for (std::size_t k = 0; k < probe_.velocity.size(); ++k) {
      const double before = velocity_before_[k], after = probe_.velocity[k];
      if (!std::isnan(after) && (std::isnan(before) || before != after)) held_[b].push_back(k);
    }
  }
  for (std::size_t k = 0; k < f_ext_.size(); ++k) f_ext_[k] += probe_.force[k];

  // Displacement unknowns: components of nodes with mass, unless constrained.
  equations_ = 0;
  tail_nodes_.clear();
  tail_mark_.assign(nn, 0);
  double cell_volume = 1;
  for (int a = 0; a < dim; ++a) cell_volume *= d_.grid.cell_size()[a];
  u_dof_.assign(nn * dim, -1);
  const bool root = d_.comm.root();  // where the terms every process knows are added (once)
  for (std::size_t I = 0; I < nn; ++I)
    for (int i = 0; i < dim; ++i) {
      const std::size_t k = I * dim + i;
      du_[k] = 0;
      if (node_mass_[I] <= 0) continue;
      if (std::isnan(probe_.velocity[k]) && node_cover_[I] < min_cover * cell_volume) {
        if (!tail_mark_[I]) tail_nodes_.push_back(static_cast<std::int64_t>(I));
        tail_mark_[I] = 1;
        continue;
      }
      if (std::isnan(probe_.velocity[k]))
        u_dof_[k] = static_cast<std::int64_t>(equations_++);
      else  // (a strength reduction's solves hold them where they are: the loads of one time)
        du_[k] = reduction_ ? 0.0 : probe_.velocity[k] * dt;
    }

  tail_points_.clear();
  if (!tail_nodes_.empty()) {
    tail_sum_.assign(nn * dim, 0.0);
    tail_weight_.assign(nn, 0.0);
    for (std::size_t p = 0; p < pts.size(); ++p)
      for (int a = 0; a < s.npp; ++a)
        if (tail_mark_[static_cast<std::size_t>(s.ids[p * s.npp + a])]) {
          tail_points_.push_back(p);
          break;
        }
  }
  follow_tail_nodes();  // the constrained increments

  // Pressure unknowns: nodes with pore volume, unless a face open to the
  // liquid or a free surface fixes their pressure.
  displacement_equations_ = equations_;
  p_dof_.assign(nn, -1);
  b_p_.assign(nn, 0.0);
  if (!mixture_) return;
  std::vector<char>& fixed = fixed_pressure_;
  fixed.assign(nn, 0);
  face_flux_.clear();
  for (const auto& bc : bcs_)
    for (const LiquidOpening& opening : bc->liquid_openings()) {
      const GridFace f = opening.face;
      for (const std::int64_t I : opening.nodes.empty() ? face_nodes(d_.grid, f) : opening.nodes) {
        if (node_pore_[I] <= 0) continue;
        const std::size_t k = static_cast<std::size_t>(I) * dim + f.axis;
        const double area = d_.periodic.face_area(d_.grid, f, I);  // (a periodic grid's seam: the whole width)
        if (!std::isnan(probe_.liquid_velocity[k]) && !std::isnan(probe_.velocity[k])) {
          // A prescribed flux: n (v_L - v_s) enters against the outward normal.
          const double nI = node_pore_[I] / node_volume_[I];
          if (root) b_p_[I] -= dt * f.outward() * nI * (probe_.liquid_velocity[k] - probe_.velocity[k]) * area;
        } else if (!fixed[I]) {
          fixed[I] = 1;  // the pressure whose traction -p n the condition applied
          p_[I] = -probe_.liquid_force[k] * f.outward() / area;
          face_flux_.push_back({I, f.axis, f.outward(), area});
        } else {  // a corner two open faces share: its residual is their sum
          std::erase_if(face_flux_, [&](const FaceFlux& ff) { return ff.node == I; });
        }
      }
    }
  find_free_surfaces();  // drained where the surface is (quasi_static_free_surface.cpp)
  for (std::size_t I = 0; I < nn; ++I)
    if (node_pore_[I] > 0 && !fixed[I]) p_dof_[I] = static_cast<std::int64_t>(equations_++);
  // Newton's first pressures: the last equilibrium's where a node had one,
  // not the points' projection of them (the old pressures' storage is the
  // points' either way). The projection differs by what the shape functions
  // smear; at a wetting front under a short step that difference is carried
  // undrained, and points over pores still drained were pushed to the apex
  // (a flood levee's step lost its equilibrium at the riverside toe).
  if (!reduction_ && equilibrium_p_.size() == nn)
    for (std::size_t I = 0; I < nn; ++I)
      if (p_dof_[I] >= 0 && !std::isnan(equilibrium_p_[I])) p_[I] = equilibrium_p_[I];
  follow_inner_nodes();
  if (reduction_) {  // the pressures held where they are: the last equilibrium's, the surfaces' own
    if (equilibrium_p_.size() == nn)
      for (std::size_t I = 0; I < nn; ++I)
        if (!fixed[I] && p_dof_[I] >= 0 && !std::isnan(equilibrium_p_[I])) p_[I] = equilibrium_p_[I];
    p_dof_.assign(nn, -1);
    extrapolated_.clear();
    equations_ = displacement_equations_;
    return;
  }

  // The rest of the pressure equations' right-hand side: the storage of the
  // old pressures and the flow gravity drives, -dt sum V k rho_L g . grad N.
  const auto& mf = mixture_->fields();
  const double* KL = pts.data(mf.bulk_modulus);
  const double* K = pts.data(mf.conductivity);
  const double* rho_w = pts.data(mf.water_density);
  const double* rho_l = pts.data(mf.liquid_density);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    if (!(n[p] > 0)) continue;
    // Pores that drain: the water they held, n (psi / K_L + S - 1) V; the
    // flow gravity drives depends on the iterate's saturation (evaluate).
    const std::optional<Drainage>* drains = phreatic_ ? &drainage_[static_cast<std::size_t>(material[p])] : nullptr;
    if (drains && *drains) {
      const double held = V[p] * n[p] * (potential_[p] / KL[p] + saturation[p] - 1);
      for (int a = 0; a < s.npp; ++a) b_p_[s.ids[p * s.npp + a]] += s.weights[p * s.npp + a] * held;
      continue;
    }
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
  sum_over_processes(b_p_);
}

void QuasiStatic::follow_tail_nodes() {
  if (tail_nodes_.empty()) return;
  const int dim = d_.dim();
  const ExpandedSupports& s = d_.expanded_shape();
  const double* m = d_.points.data(d_.points.core().mass);
  for (const std::int64_t I : tail_nodes_) {
    tail_weight_[I] = 0;
    for (int i = 0; i < dim; ++i) tail_sum_[I * dim + i] = 0;
  }
  for (const std::size_t p : tail_points_) {
    double du[3] = {0, 0, 0}, w = 0;
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t q = p * s.npp + a;
      const std::int64_t I = s.ids[q];
      if (tail_mark_[I]) continue;
      w += s.weights[q];
      for (int i = 0; i < dim; ++i) du[i] += s.weights[q] * du_[I * dim + i];
    }
    if (w <= 0) continue;  // a point only tail nodes reach: it stays
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t q = p * s.npp + a;
      const std::int64_t I = s.ids[q];
      if (!tail_mark_[I]) continue;
      const double c = s.weights[q] * m[p];
      tail_weight_[I] += c;
      for (int i = 0; i < dim; ++i) tail_sum_[I * dim + i] += c * du[i] / w;
    }
  }
  if (d_.comm.parallel()) {  // the tail nodes' sums only
    std::vector<double> sums;
    for (const std::int64_t I : tail_nodes_) {
      sums.push_back(tail_weight_[I]);
      for (int i = 0; i < dim; ++i) sums.push_back(tail_sum_[I * dim + i]);
    }
    sum_over_processes(sums);
    std::size_t at = 0;
    for (const std::int64_t I : tail_nodes_) {
      tail_weight_[I] = sums[at++];
      for (int i = 0; i < dim; ++i) tail_sum_[I * dim + i] = sums[at++];
    }
  }
  for (const std::int64_t I : tail_nodes_)
    for (int i = 0; i < dim; ++i) {
      const std::size_t k = static_cast<std::size_t>(I) * dim + i;
      if (tail_weight_[I] > 0 && std::isnan(probe_.velocity[k])) du_[k] = tail_sum_[k] / tail_weight_[I];
    }
}

}  // namespace suffuse::detail
