// phase/suffosion's "implicit" integration: a point's erosion-induced
// strain of a step, at the stress ratio of the step's end (backward Euler),
// from its strain increment. phase/suffosion calls erode() in its stress
// update, once at the increment and, where a tangent may follow (a
// quasi-static iterate), twelve times more for it.
#pragma once

#include <algorithm>
#include <suffuse/tensor.hpp>

#include "suffosion_law.hpp"

namespace suffosion {

// D e, e a tensor (engineering shear for D).
inline t::Voigt stress_of(const double* D, const t::Voigt& e) {
  t::Voigt out{};
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) out[r] += D[r * 6 + c] * e[c] * (c < 3 ? 1.0 : 2.0);
  return out;
}
// a + factor b.
inline t::Voigt add(const double* a, const t::Voigt& b, double factor) {
  t::Voigt out;
  for (int c = 0; c < 6; ++c) out[c] = a[c] + factor * b[c];
  return out;
}

// "implicit": backward Euler. The step's erosion-induced strain is the
// law's at the stress ratio eta of the step's end, e(eta) (onset
// included), and that end is the elastic trial stress (the step's start
// plus the base's elastic stiffness D times the strain increment) less
// D e(eta): eta solves eta = ratio(trial - D e(eta)) (end_ratio()). q and
// the shear strain are along the deviator of the step's start, fixed over
// the iterations. A point whose end would fall below a thousandth of its
// p' (slack) takes the share of the strain that leaves it there. The
// base then updates its stress with that strain imposed. Where the base
// yields in the step, eta is the elastic trial's, which its return then
// moves (docs/time-integration.md, Limits).
struct Direction {  // of q and of the erosion's shear strain
  t::Voigt dev;
  double q;
  double along(const t::Voigt& v) const {  // q = (3/2) s : dev / q
    return q > 0 ? 1.5 * t::double_contraction(t::deviator(v.data()).data(), dev.data()) / q : 0.0;
  }
};
// The root of eta = ratio(end(eta)) on [0, eta_max]: the zero of
// r(eta) = q - eta max(p', 0) of the end. r falls as eta rises wherever
// p' > 0, the onset included: a larger ratio compacts less and shears
// more, and though it also erodes more past a lower onset, the shear of
// that erosion lowers q more than its compaction lowers p' (by 3 G beta /
// (M_c^2 - eta^2) against K eta, for nu = 0.3 and beta = 1.5 at least 6.1 G
// against 2.2 G). Where the strain takes p' past zero it is q, which
// falls too. So the root is unique, and moves continuously with the
// trial (a division by p', or the cap where p' <= 0, made roots where a
// large step's strain takes p' past zero, and the point slack).
// Found by the Illinois method (false position, halving the weight of an
// end that stays), which keeps the bracket as bisection does but converges
// superlinearly where bisection halved it fifty times: an eroding point's
// update in a quasi-static iterate is thirteen of these solves, and was
// most of a flood levee's run (an eroding column ran six times as fast).
// `near` (the root at a neighbouring strain, for the tangent's
// differences) brackets it first within 1e-6 of it.
template <class EndAt>
double end_ratio(const SuffosionLaw& law, const Direction& along, const EndAt& end_at, double near = -1) {
  auto residual = [&](double eta) {
    const t::Voigt v = end_at(eta);
    return along.along(v) - eta * std::max(t::mean_stress(v.data()), 0.0);
  };
  double lo = 0, hi = law.eta_max, r_lo = 0, r_hi = 0;
  bool bracketed = false;
  if (near > 0 && near < law.eta_max) {
    lo = std::max(0.0, near - 1e-6), hi = std::min(law.eta_max, near + 1e-6);
    r_lo = residual(lo), r_hi = residual(hi);
    bracketed = r_lo > 0 && !(r_hi > 0);
  }
  if (!bracketed) {
    lo = 0, hi = law.eta_max;
    r_lo = residual(lo);
    if (!(r_lo > 0)) return lo;
    r_hi = residual(hi);
    if (r_hi > 0) return hi;
  }
  int kept = 0;  // +1: lo stayed in the last iteration, -1: hi did
  for (int k = 0; k < 100 && hi - lo > 1e-15; ++k) {
    double mid = (lo * r_hi - hi * r_lo) / (r_hi - r_lo);
    if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);  // round-off at a bracket this narrow
    const double r = residual(mid);
    if (r > 0) {
      lo = mid, r_lo = r;
      if (kept == -1) r_hi *= 0.5;
      kept = -1;
    } else {
      hi = mid, r_hi = r;
      if (kept == 1) r_lo *= 0.5;
      kept = 1;
    }
    if (r == 0) return mid;
  }
  return 0.5 * (lo + hi);
}

// `eta` returns the step's end ratio; `near`, where given, is the root at
// a neighbouring strain.
inline SuffosionLaw::Strain erode(const SuffosionLaw& law, const double* start, const t::Voigt& strain, const double* D,
                                  const Direction& along, double f, double df, double& eta, double near = -1) {
  constexpr double slack = 1e-3;
  const t::Voigt trial = add(start, stress_of(D, strain), 1.0);
  const double p_start = t::mean_stress(start), p_trial = t::mean_stress(trial.data());
  const double p_ref = std::max(p_start, p_trial);
  auto end_at = [&](double ratio) {
    return add(trial.data(), stress_of(D, strain_tensor(law.of_step(ratio, f, df), along.dev, along.q)), -1.0);
  };
  eta = end_ratio(law, along, end_at, near);
  SuffosionLaw::Strain d = law.of_step(eta, f, df);
  const double p_end = t::mean_stress(end_at(eta).data());
  if (p_end < slack * p_ref) {
    const double relief = p_trial - p_end;
    const double share = relief > 0 ? std::clamp((p_trial - slack * p_ref) / relief, 0.0, 1.0) : 0.0;
    d = {share * d.volumetric, share * d.shear};
  }
  return d;
}

}  // namespace suffosion
