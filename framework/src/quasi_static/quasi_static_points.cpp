// Stage "g2p" of a quasi-static step (quasi_static.hpp): once the step's
// equilibrium converged, the points follow its solution (positions, strain,
// volume, porosity, pore pressure, Darcy flux), and the transport gets the
// nodal Darcy flux and the rate that bounds its substeps.
#include <algorithm>
#include <cmath>
#include <string>

#include "quasi_static/quasi_static.hpp"
#include "mpm/solid_kernels.hpp"
#include "suffuse/error.hpp"
#include "suffuse/liquid.hpp"

namespace suffuse::detail {

void QuasiStatic::update_points(double dt) {
  const int dim = d_.dim();
  d_.update_kinematics(dt);  // strain and volume; L as the last iteration had it
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const ExpandedSupports& s = d_.expanded_shape();
  double* x = pts.data(c.position);
  double* u = pts.data(c.displacement);
  double* v = pts.data(c.velocity);
  // Velocities: without inertia the step's mean, du / dt; with it FLIP, as
  // in explicit runs: the points' own velocity changes by the nodes' change
  // (du / dt - v0), which carries no averaging over the support from step to
  // step (the mean would damp a collapse more, the more steps it takes).
  const bool flip = !inertia_.empty();
  for (std::size_t p = 0; p < pts.size(); ++p) {
    double du[3] = {0, 0, 0}, dv[3] = {0, 0, 0};
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t q = p * s.npp + a;
      const std::size_t I = static_cast<std::size_t>(s.ids[q]);
      for (int i = 0; i < dim; ++i) du[i] += s.weights[q] * du_[I * dim + i];
      if (flip)
        for (int i = 0; i < dim; ++i) dv[i] += s.weights[q] * (du_[I * dim + i] - inertia_target_[I * dim + i]);
    }
    for (int i = 0; i < dim; ++i) {
      x[p * dim + i] += du[i];
      u[p * dim + i] += du[i];
      v[p * dim + i] = flip ? v[p * dim + i] + dv[i] / dt : du[i] / dt;
    }
  }
  d_.periodic.wrap(x, pts.size());
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
  double* saturation = phreatic_ ? pts.data(*mf.saturation) : nullptr;
  double* potential = phreatic_ ? pts.data(*mf.potential) : nullptr;
  const double* material = pts.data(c.material_id);
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
    // Where the pores drain, pp is the potential psi: the pressure is its
    // positive part, and the saturation and conductivity follow it.
    double k_r = 1;
    if (potential) potential[p] = pp;
    if (const std::optional<Drainage>* drains = phreatic_ ? &drainage_[static_cast<std::size_t>(material[p])] : nullptr;
        drains && *drains) {
      saturation[p] = (*drains)->saturation(pp, rho_w[p]);
      k_r = (*drains)->relative_conductivity(saturation[p]);
      pp = std::max(pp, 0.0);
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
    const double k = K[p] / (rho_w[p] * reference_gravity) * k_r;
    for (int i = 0; i < dim; ++i) q[p * dim + i] = -k * (grad_p[i] - rho_l[p] * g[i]);  // projected below
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k2 = p * s.npp + a;
      const std::int64_t I = s.ids[k2];
      node_volume_[I] += s.weights[k2] * V[p];
      for (int i = 0; i < dim; ++i) node_q[I * dim + i] += s.weights[k2] * V[p] * q[p * dim + i];
    }
  }
  sum_over_processes(node_volume_);  // every node's flux on every process: the transport's nodes follow the points
  sum_over_processes(node_q);
  for (std::size_t I = 0; I < node_volume_.size(); ++I)
    for (int i = 0; i < dim; ++i) node_q[I * dim + i] = node_volume_[I] > 0 ? node_q[I * dim + i] / node_volume_[I] : 0.0;
  d_.periodic.copy_to_images(node_q, dim);  // (the transport reads it with the compact supports)
  // Through a face whose pressure is prescribed, the flux is what the
  // pressure equation of its node leaves unbalanced (the weak form's
  // boundary term: the volume leaving there over the step), not the mean of
  // the points near it. That mean takes one side of the face only, and where
  // the conductivity varies across the last cell (a washed-out top) it
  // misses the flow by up to 40%; the transport would then pile the liquid
  // up at the face's nodes until their outflow balanced the inflow.
  for (const FaceFlux& f : face_flux_)
    node_q[static_cast<std::size_t>(f.node) * dim + f.axis] = f.outward * r_p_[f.node] / (dt * f.area);
  // The points' flux and liquid velocity: the nodal flux interpolated, as
  // in explicit runs. -K grad p at a point swings by up to 10% from point
  // to point where the permeability changes within a support (an erosion
  // front), and the liquid the transport carries is the nodal flux anyway.
  for (std::size_t p = 0; p < pts.size(); ++p) {
    if (!(n[p] > 0)) continue;
    double qp[3] = {0, 0, 0};
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t k = p * s.npp + a;
      for (int i = 0; i < dim; ++i) qp[i] += s.weights[k] * node_q[static_cast<std::size_t>(s.ids[k]) * dim + i];
    }
    for (int i = 0; i < dim; ++i) {
      q[p * dim + i] = qp[i];
      vl[p * dim + i] = v[p * dim + i] + qp[i] / (saturation ? n[p] * saturation[p] : n[p]);  // the water's pores
    }
  }
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
  return d_.comm.max(worst);
}

}  // namespace suffuse::detail
