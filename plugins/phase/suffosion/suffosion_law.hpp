// phase/suffosion: the DEM study's relations (seed 001; docs/suffosion.md),
// parameters parsed once, and the strain they give as a tensor.
//
// d eps_s = A beta eta (1 - x^xi) / (M_c^2 (1 - x^2)) d f_er with x = eta/M_c:
// both factors change sign at x = 1, where D = 0, so the ratio is taken in
// that form, with its limit xi/2 where |1 - x^2| < 1e-8: no division by
// zero, and d eps_s is finite and positive on both sides of M_c.
#pragma once

#include <algorithm>
#include <cmath>
#include <suffuse/tensor.hpp>

namespace suffosion {

namespace t = suffuse::tensor;

// The study's relations, parameters parsed once.
struct SuffosionLaw {
  double M_so, f_so0, M_c, A, xi, beta, eta_max;

  // Eroded fraction at which erosion starts to deform the skeleton.
  double onset(double eta) const {
    const double r = eta / M_so;
    return r < 1 ? f_so0 * std::sqrt(1 - r * r) : 0.0;
  }
  // d eps_v / d f_er (compression positive) and d eps_s / d f_er after
  // onset: d eps_s = d eps_v / D, finite at D = 0. Both from (eta/M_c)^xi
  // - 1: one exp and one log, the most of a root solve's evaluation.
  struct Rates {
    double volumetric, shear;
  };
  Rates rates(double eta) const {
    const double x = eta / M_c, power = std::expm1(xi * std::log(x));
    if (eta <= 0) return {-A * power, 0.0};
    const double one_minus_x2 = (1 - x) * (1 + x);
    const double ratio = std::abs(one_minus_x2) < 1e-8 ? xi / 2 : -power / one_minus_x2;
    return {-A * power, A * beta * eta * ratio / (M_c * M_c)};
  }
  // The erosion-induced strain of a step at stress ratio eta that takes the
  // eroded fraction from f - df to f: only the part beyond the onset
  // (deposition deforms nothing).
  struct Strain {
    double volumetric = 0, shear = 0;  // d eps_v (compression positive), d eps_s
  };
  Strain of_step(double eta, double f, double df) const {
    const double active = std::max(0.0, f - std::max(f - df, onset(eta)));
    if (active <= 0) return {};
    const Rates r = rates(eta);
    return {r.volumetric * active, r.shear * active};
  }
};

// A strain of volume d_ev (compression positive) and shear d_es along the
// deviator `dev` of deviatoric stress q, as a tension-positive tensor
// (Voigt): -d_ev/3 I + 3/2 d_es dev/q (3/2 s/q has eps_s 1).
inline t::Voigt strain_tensor(const SuffosionLaw::Strain& e, const t::Voigt& dev, double q) {
  t::Voigt out{};
  for (int c = 0; c < 6; ++c) out[c] = (c < 3 ? -e.volumetric / 3 : 0.0) + (q > 0 ? 1.5 * e.shear * dev[c] / q : 0.0);
  return out;
}

}  // namespace suffosion
