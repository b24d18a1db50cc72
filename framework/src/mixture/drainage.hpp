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
  // The water a pore volume holds, relative to its volume at psi = 0 and
  // with the liquid's compressibility 1 / K_L: S(psi) + psi / K_L. Its slope,
  // the storage per pore volume, is at least 1 / K_L: no stiffer than the
  // water, also where the retention curve is flat (psi = 0).
  double content(double psi, double bulk_modulus, double rho_w) const {
    return saturation(psi, rho_w) + psi / bulk_modulus;
  }
  // Its inverse: the potential at which the pores hold `theta` (Newton's
  // iterations kept in a bracket; the content increases with psi).
  double potential_of_content(double theta, double bulk_modulus, double rho_w) const {
    if (theta >= 1) return (theta - 1) * bulk_modulus;
    // Below: psi < 0, above both the curve's own inverse (the water taken
    // as incompressible) and the water's compression alone: each of those
    // takes all of the deficit, which the two share.
    const double drained = potential(0.0, std::clamp(theta, 1e-300, 1.0), rho_w);
    const double compressed = (theta - 1) * bulk_modulus;
    double lo = std::max(drained, compressed), hi = 0, psi = lo;
    for (int i = 0; i < 60; ++i) {
      const double f = content(psi, bulk_modulus, rho_w) - theta;
      if (f > 0) hi = psi; else lo = psi;
      const double next = psi - f / (capacity(psi, rho_w) + 1 / bulk_modulus);
      const double step = next > lo && next < hi ? next : 0.5 * (lo + hi);
      if (std::abs(step - psi) <= 1e-14 * std::abs(psi)) return step;
      psi = step;
    }
    return psi;
  }
  // psi of a point from its pore pressure and saturation (the fields it keeps).
  double potential(double pressure, double saturation, double rho_w) const {
    return saturation < 1 ? -pressure_scale(rho_w) * std::sqrt(1 / std::max(saturation, 1e-300) - 1) : pressure;
  }
};

}  // namespace suffuse::detail
