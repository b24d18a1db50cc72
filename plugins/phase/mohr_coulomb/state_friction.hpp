#pragma once
// A friction angle that follows the soil's state (phase/mohr_coulomb's
// "state_friction_slope"): the strength of a sand depends on how far its void
// ratio lies from the critical state line, through the state parameter
// (Been and Jefferies 1985)
//   psi = e - e_cs(p'),  e_cs = e_Gamma - lambda ln(p' / p_ref),
// and the stress ratio it can carry in triaxial compression falls linearly
// with it (Wood, Belkheir and Liu 1994; Muir Wood, Maeda and Nukudani 2010
// used it for the weakening of an eroded soil):
//   M(psi) = M_cs (1 - k psi),  M_cs = 6 sin(phi_cs) / (3 - sin(phi_cs)),
// and the Mohr-Coulomb friction angle with that ratio in triaxial
// compression, sin(phi) = 3 M / (6 + M). Erosion raises e at a constant
// skeleton volume (phase/suffosion's void-ratio identity), so psi rises and
// the strength falls; a denser state (psi < 0) is stronger.
#include <algorithm>
#include <cmath>

namespace suffuse_mohr_coulomb {

struct StateFriction {
  double M_cs;     // the critical-state stress ratio in triaxial compression
  double k;        // the slope of M / M_cs against psi
  double e_gamma;  // e on the critical state line at p_ref
  double lambda;   // the line's slope in e - ln p'
  double p_ref;    // [Pa]
  // Below it p' counts as it: the line's ln p' has no limit at a free surface.
  static constexpr double lowest_pressure = 1e3;  // [Pa]
  // M stays within these factors of M_cs, and below 2.9 (sin(phi) < 1).
  static constexpr double weakest = 0.1, strongest = 2.0;

  static double ratio_of(double phi) { return 6 * std::sin(phi) / (3 - std::sin(phi)); }

  // p' compression positive [Pa].
  double state_parameter(double e, double p) const {
    return e - (e_gamma - lambda * std::log(std::max(p, lowest_pressure) / p_ref));
  }
  // The friction angle [rad] at void ratio e and mean effective stress p'.
  double friction(double e, double p) const {
    const double M = std::min(M_cs * std::clamp(1 - k * state_parameter(e, p), weakest, strongest), 2.9);
    return std::asin(3 * M / (6 + M));
  }
};

}  // namespace suffuse_mohr_coulomb
