#pragma once
// Kernels of the explicit step where pores drain above the phreatic surface
// (docs/phreatic.md, Explicit runs). A point carries the water potential psi
// (Drainage); its pores hold the share S(psi) of water, which flows with
// K k_r(S):
//   liquid:   rho_L a_L = -grad psi - (n S gamma_w / (K k_r)) (v_L - v_s) + rho_L b
//   mixture:  (1-n) rho_s a_s + n S rho_L a_L = div(sigma' - max(psi, 0) I) + rho b
//   water:    d/dt [n (S(psi) + psi / K_L)] = -(S div v_s + div q),  q = n S (v_L - v_s)
// The liquid's -grad psi is split: the pressure, max(psi, 0), is integrated
// by parts as in saturated runs, so that a free surface where it is positive
// drains (a seepage face); the suction, min(psi, 0), is not, so that a
// drained free surface draws no water in. Its gradient at the points comes
// from its nodal projection.
#include <algorithm>
#include <cstddef>
#include <optional>

#include "mixture/drainage.hpp"
#include "mpm/solid_kernels.hpp"

namespace suffuse::detail {

// Scatter: sum N V min(psi, 0) and sum N V, two values per node, over the
// points with pores.
template <int D, int L = 2>
[[gnu::always_inline]] inline void p2g_suction(std::size_t begin, std::size_t end, const PointSupports& s,
                                               const double* volume, const double* n, const double* psi,
                                               double* __restrict block) {
  for (std::size_t p = begin; p < end; ++p) {
    if (n[p] <= 0) continue;
    const double a[2] = {volume[p] * std::min(psi[p], 0.0), volume[p]};
    const WeightedValues<2, L> sums(a);
    for_each_weight<D>(s, p, [&](std::size_t node, double N) { sums.add_to(block + node * 2, N); });
  }
}

// The nodal suction: the volume-weighted mean.
inline void nodal_suction(std::size_t begin, std::size_t end, const double* block, double* suction) {
  for (std::size_t I = begin; I < end; ++I) suction[I] = block[2 * I + 1] > 0 ? block[2 * I] / block[2 * I + 1] : 0.0;
}

// Gather: the suction's force on each point's liquid, -V grad min(psi, 0)
// (D per point; zero where the point has no pores).
template <int D>
void suction_force(std::size_t begin, std::size_t end, const PointSupports& s, const double* volume,
                   const double* n, const double* suction, double* force) {
  for (std::size_t p = begin; p < end; ++p) {
    double g[D] = {};
    if (n[p] > 0)
      for_each_gradient<D>(s, p, [&](std::size_t node, const double* grad) {
        for (int i = 0; i < D; ++i) g[i] += grad[i] * suction[node];
      });
    for (int i = 0; i < D; ++i) force[p * D + i] = -volume[p] * g[i];
  }
}

// The point fields the water's update reads and writes.
struct DrainedPoints {
  const double *porosity, *bulk_modulus, *water_density, *liquid_density, *volume, *material;
  double *rate;  // in: the rate of the water's volume per volume; out: the potential's rate
  double *potential, *pressure, *saturation, *moving_liquid_mass;
};

// Each point's rate of its potential over the step from the water its pores
// gain, through the water they hold, Drainage::content (with S = 1 and the
// liquid's compressibility in saturated pores): the potential at which they
// hold what they held plus the gain, exactly, however far the retention
// curve bends over the step. The slope at the step's start instead
// (n / K_L + n dS/dpsi) overshoots where pores start to drain, at psi = 0,
// where the curve is flat: a drained column's outflow then depended on the
// time step (by 24% between CFL 0.5 and 0.1) and strayed from the
// quasi-static step's by 14%; this way by 2% to 3%.
template <class Drains>
void potential_rate(std::size_t begin, std::size_t end, double dt, const Drains* drains, const DrainedPoints& pt) {
  for (std::size_t p = begin; p < end; ++p) {
    const double n = pt.porosity[p];
    if (n <= 0) continue;  // dry points: no pore pressure
    const auto& d = drains[static_cast<std::size_t>(pt.material[p])];
    const double psi = pt.potential[p], K = pt.bulk_modulus[p], gain = pt.rate[p] * dt / n;
    double next = psi + gain * K;
    if (d) {
      // A step takes at most half of what drained pores hold: where little
      // water is left, the explicit balance would take more than there is.
      const double held = d->content(psi, K, pt.water_density[p]);
      next = d->potential_of_content(std::max(held + gain, held < 1 ? 0.5 * held : -1.0), K, pt.water_density[p]);
    }
    pt.rate[p] = (next - psi) / dt;
  }
}

// Whether point p's pores are draining (psi < 0 where its material has a
// retention curve), or full: which of the two smoothings of the potential's
// rate it joins (split_by_drainage) and reads (g2p_potential).
template <class Drains>
bool draining(const Drains* drains, const DrainedPoints& pt, std::size_t p) {
  return drains[static_cast<std::size_t>(pt.material[p])] && pt.potential[p] < 0;
}

// Each point's porosity in the array of its kind (draining or full), zero in
// the other, for the two smoothings of the potential's rate.
template <class Drains>
void split_by_drainage(std::size_t begin, std::size_t end, const Drains* drains, const DrainedPoints& pt,
                       double* full, double* draining_pores) {
  for (std::size_t p = begin; p < end; ++p) {
    const bool drains_here = draining(drains, pt, p);
    full[p] = drains_here ? 0.0 : pt.porosity[p];
    draining_pores[p] = drains_here ? pt.porosity[p] : 0.0;
  }
}

// Gather, after the rates are smoothed over the nodes as the saturated
// pressure's are (SaturatedMixture::update_pore_pressure): each point's
// potential grows by the interpolated nodal rate; then its pressure,
// saturation and the liquid the momentum balance moves, n S rho_L V.
// Smoothing the potential's rate keeps the increments of a cell's points
// alike where the phreatic surface crosses it. Smoothing the water's
// instead, each point turning it into potential through its own storage, a
// saturated point (n / K_L) beside a drained one (n dS/dpsi, up to five
// orders more) took a pressure rise for water the other stores: a
// checkerboard of pressures below the phreatic surface that the nodes do
// not see and nothing damps (680 Pa in a column at rest 1 m high).
// The rates are smoothed apart among full pores (`node_rate`) and draining
// ones (`node_draining_rate`, psi < 0 at the step's start): together, a
// full point's rate, K_L / n times its volume change, reached the draining
// points beside it, whose potential then rose for water no one gave them.
// With water at 2.2 GPa the drained clay of a levee gained 2.6 times the
// water its pores held in a second, weight its skeleton carried (0.21.9).
// `drains` per material (null: saturated pores).
template <int D, class Drains>
void g2p_potential(std::size_t begin, std::size_t end, double dt, const PointSupports& s, const double* node_rate,
                   const double* node_draining_rate, const Drains* drains, const DrainedPoints& pt) {
  for (std::size_t p = begin; p < end; ++p) {
    const double n = pt.porosity[p];
    if (n <= 0) continue;
    const auto& d = drains[static_cast<std::size_t>(pt.material[p])];
    const double* smoothed = draining(drains, pt, p) ? node_draining_rate : node_rate;
    double rate = 0;
    for_each_weight<D>(s, p, [&](std::size_t node, double N) { rate += N * smoothed[node]; });
    const double next = pt.potential[p] + rate * dt, S = d ? d->saturation(next, pt.water_density[p]) : 1.0;
    pt.potential[p] = next;
    pt.pressure[p] = std::max(next, 0.0);
    pt.saturation[p] = S;
    pt.moving_liquid_mass[p] = n * S * pt.volume[p] * pt.liquid_density[p];
  }
}

}  // namespace suffuse::detail
