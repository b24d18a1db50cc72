#pragma once
// Pores that drain above the phreatic surface (docs/phreatic.md): the water
// is described by one potential per point, psi, the pore pressure where the
// pores are full (psi >= 0) and below zero where they drain. The skeleton
// feels max(psi, 0): no suction holds it. The pores hold the water
//   S(psi) = 1                                   psi >= 0
//          = 1 / (1 + (psi / (gamma_w h_d))^2)  psi <  0
// (van Genuchten's curve with n = 2, m = 1; h_d the drainage head), whose
// slope is zero at psi = 0 from both sides: Newton's iterations cross the
// phreatic surface without the jump of storage an exponential curve has
// there (from n / (gamma_w h_d) to n / K_L, seven orders). The water flows
// with the conductivity's relative factor k_r = r + (1 - r) S^3, r the
// residual. Drained pores (S near 0) still pass r K, and the fringe above
// the phreatic surface, where S falls from 1 over a few h_d, passes about
// 0.59 h_d K (the integral of S^3): the method's known errors.
#include <algorithm>
#include <cmath>

#include "suffuse/liquid.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

struct Drainage {
  double head = 0.05, residual = 1e-3;  // h_d [m]; r [-]

  explicit Drainage(const DrainageSpec& d) : head(d.drainage_head), residual(d.residual_conductivity) {}

  // gamma_w h_d [Pa] for clean water of density rho_w.
  double pressure_scale(double rho_w) const { return rho_w * reference_gravity * head; }
  double saturation(double psi, double rho_w) const {
    if (psi >= 0) return 1.0;
    const double x = psi / pressure_scale(rho_w);
    return 1 / (1 + x * x);
  }
  // dS / dpsi [1/Pa].
  double capacity(double psi, double rho_w) const {
    if (psi >= 0) return 0.0;
    const double s = pressure_scale(rho_w), x = psi / s, d = 1 + x * x;
    return -2 * x / (s * d * d);
  }
  double relative_conductivity(double saturation) const {
    return residual + (1 - residual) * saturation * saturation * saturation;
  }
  // dk_r / dS.
  double conductivity_slope(double saturation) const { return 3 * (1 - residual) * saturation * saturation; }
  // The integral of S over the heights lo to hi (lo <= hi) where the water
  // is at rest, psi = -rho_w g (y - y0), y0 the height where psi is zero
  // (S = 1 below it): the height of full pores it equals [m], for the
  // weight of a drained body (its initial geostatic stress). Without
  // gravity psi is zero: the pores are full.
  double saturated_height(double lo, double hi, double y0, double g) const {
    const double a = g / (reference_gravity * head);
    if (!(a > 0)) return hi - lo;
    const double full = std::clamp(y0, lo, hi) - lo, from = std::max(lo, y0), to = std::max(hi, y0);
    return full + (std::atan(a * (to - y0)) - std::atan(a * (from - y0))) / a;
  }
  // psi of a point from its pore pressure and saturation (the fields it keeps).
  double potential(double pressure, double saturation, double rho_w) const {
    return saturation < 1 ? -pressure_scale(rho_w) * std::sqrt(1 / std::max(saturation, 1e-300) - 1) : pressure;
  }
};

}  // namespace suffuse::detail
