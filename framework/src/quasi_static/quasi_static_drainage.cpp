// Pores that drain above a phreatic surface in a quasi-static step
// (mixture/drainage.hpp, docs/phreatic.md): a point's terms with its water
// potential psi, and the seepage faces, drained where water leaves and
// closed where it would enter (a Signorini condition, settled by solving
// the step again with the faces' nodes switched).
#include <algorithm>
#include <cmath>

#include "quasi_static/quasi_static.hpp"
#include "suffuse/liquid.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse::detail {

void QuasiStatic::add_drained_point_terms(const Drainage& drains, std::size_t p, double psi, const double* grad_psi,
                                          double div_u, double dt, std::vector<double>& f_int,
                                          std::vector<double>& r_p, std::vector<double>& water_terms) {
  const int dim = d_.dim();
  const PointSet& pts = d_.points;
  const auto& mf = mixture_->fields();
  const ExpandedSupports& s = d_.expanded_shape();
  const double V = pts.data(pts.core().volume)[p], n = pts.data(mf.porosity)[p];
  const double KL = pts.data(mf.bulk_modulus)[p], rho_w = pts.data(mf.water_density)[p];
  const double rho_l = pts.data(mf.liquid_density)[p];
  const double* sigma = pts.data(pts.core().stress) + p * 6;
  const double S = drains.saturation(psi, rho_w), k_r = drains.relative_conductivity(S);
  const double dS = drains.capacity(psi, rho_w);
  const double pressure = std::max(psi, 0.0);  // no suction on the skeleton
  const double k = pts.data(mf.conductivity)[p] * k_r / (rho_w * reference_gravity);
  // The water the pores hold against full pores at zero pressure, and what
  // the skeleton's volume change moves: only the pores' water share of it.
  const double held = n * (psi / KL + S - 1) + S * div_u;
  const auto& g = scene_.gravity;
  // The matrix's factors (Newton's exact terms of this point).
  coupling_[p] = psi >= 0 ? 1.0 : 0.0;
  saturation_[p] = S;
  capacity_[p] = n / KL + dS * (n + div_u);
  relative_[p] = k_r;
  const double dk = pts.data(mf.conductivity)[p] / (rho_w * reference_gravity) * drains.conductivity_slope(S) * dS;
  for (int i = 0; i < dim; ++i) drift_[p * 3 + i] = dk * (grad_psi[i] - rho_l * g[i]);
  for (int a = 0; a < s.npp; ++a) {
    const std::size_t q = p * s.npp + a;
    const std::int64_t I = s.ids[q];
    const double* gN = &s.gradients[q * dim];
    double flow = 0;
    for (int i = 0; i < dim; ++i) {
      double f = -V * pressure * gN[i];
      for (int j = 0; j < dim; ++j) f += V * sigma[tensor::voigt_index(i, j)] * gN[j];
      f_int[I * dim + i] += f;
      flow += gN[i] * (grad_psi[i] - rho_l * g[i]);
    }
    const double stored = s.weights[q] * V * held, flowing = dt * V * k * flow;
    r_p[I] -= stored + flowing;
    water_terms[I] += std::abs(stored) + std::abs(flowing);
  }
}

bool QuasiStatic::settle_seepage_faces() {
  // Round-off must not switch a node: a face's flux within 1e-9 of its
  // terms, or a pressure within 1e-9 of the largest, is none.
  double pressure_scale = 0;
  for (const double p : p_) pressure_scale = std::max(pressure_scale, std::abs(p));
  // A node switches at most once per step: one that would switch back
  // lies where the face's flux changes sign, and either state is within
  // the step's resolution of it (the rounds then end).
  if (seepage_rounds_ == 1) seepage_switched_.assign(seepage_node_.size(), 0);
  bool changed = false;
  for (std::size_t I = 0; I < seepage_node_.size(); ++I) {
    if (!seepage_node_[I] || seepage_switched_[I]) continue;
    const bool open = seepage_closed_[I] && p_[I] > 1e-9 * pressure_scale;  // the water presses: drained
    // A drained node's pressure equation's residual is the volume leaving
    // through it (times 1 - factor > 0 where it follows a node inside):
    // negative, the face would draw water in.
    const bool close = !seepage_closed_[I] && r_p_[I] < -1e-9 * water_terms_[I];
    if (!open && !close) continue;
    seepage_closed_[I] = close;
    seepage_switched_[I] = 1;
    changed = true;
  }
  return changed;
}

}  // namespace suffuse::detail
