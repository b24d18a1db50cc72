#pragma once
// Kernels of the saturated (two-phase, single-point) MPM step, one loop each.
// Formulation: Jassim, Stolle & Vermeer (2013); see docs/two-phase.md.
//   liquid:  rho_L a_L = -grad p - (n rho_L g_ref / K)(v_L - v_s) + rho_L b
//   mixture: (1-n) rho_s a_s + n rho_L a_L = div(sigma' - p I) + rho_sat b
//   pressure: dp/dt = -(K_L / n) [div v_s + div q],  q = n (v_L - v_s)
//             (= (1-n) div v_s + n div v_L where n is uniform)
#include <cstddef>
#include <cstdint>

#include "parallel/lanes.hpp"
#include "mpm/solid_kernels.hpp"
#include "suffuse/grid.hpp"
#include "suffuse/liquid.hpp"

namespace suffuse::detail {

// Nodal sums of the saturated points-to-grid scatter.
struct SaturatedNodes {
  double* solid_mass;       // sum N (1-n) rho_s V
  double* solid_momentum;   // D per node
  double* force;            // D per node, mixture
  double* liquid_mass;      // sum N n rho_L V
  double* liquid_momentum;  // D per node
  double* liquid_force;     // D per node
  double* liquid_inertia;   // sum N rho_L V
  double* drag;             // sum N n rho_w g_ref V / K
};

// Where pores drain (drained_pores.hpp), `porosity` is the water's share n S,
// `conductivity` K k_r, and `liquid_force` (D per point, else null) the
// suction's force on the liquid.
struct SaturatedPoints {
  const double *mass, *volume, *velocity, *stress, *porosity, *pressure, *liquid_velocity, *liquid_mass,
      *conductivity, *water_density, *liquid_force;
};

// Points to grid, saturated: a node's sums in one block of
// saturated_block<D> values, in the order of SaturatedNodes. As in the dry
// scatter (p2g_kernel), each is linear in the node's N and grad N:
// block += a N + B grad N, where only the forces have a B.
template <int D>
inline constexpr int saturated_block = 4 + 4 * D;

// Suction: the points carry a liquid force (pt.liquid_force), chosen once
// per scatter so that saturated runs keep the loop without it.
template <int D, int L = 2, bool Suction = false>
[[gnu::always_inline]] inline void p2g_saturated(std::size_t begin, std::size_t end, const PointSupports& s,
                   const SaturatedPoints& pt, const double* g, double scale,
                   double* __restrict block) {
  constexpr int W = saturated_block<D>, inertial = 4 + 2 * D;  // the sums without a gradient term
  constexpr int vectors = W / L, first_force_vector = inertial / L;
  static_assert(W % L == 0);
  for (std::size_t p = begin; p < end; ++p) {
    const double ms = pt.mass[p], V = pt.volume[p], n = pt.porosity[p], pr = pt.pressure[p];
    // n rho_L V; its intrinsic density times the volume is m_L / n.
    const double ml = n > 0 ? pt.liquid_mass[p] : 0.0;
    const double rho_l_V = n > 0 ? ml / n : 0.0;
    // Drag n gamma_w V / K: K is measured with clean water, whatever the
    // liquid carries. A dry point (n = 0) adds no liquid mass, drag or force.
    const double drag = n > 0 ? n * pt.water_density[p] * reference_gravity * V / pt.conductivity[p] : 0.0;
    const double Vp = V * pr, Vp_liquid = n > 0 ? Vp : 0.0, mixture = ms + ml;
    // Inertia (masses, momenta) carries the mass scaling; forces do not.
    // a: the coefficients of N; B[j]: those of dN/dx_j, zero but in the
    // forces (the mixture's V (p I - sigma'), then the liquid's V p I). In
    // 3D on four lanes one vector holds two momenta and two forces; its
    // momenta get zero products, which leave a sum as it was (a nodal sum
    // starts at +0 and never becomes -0), so the lanes round as the scalar
    // sums did. That needs finite gradients, as every shape function of a
    // finite point gives (a non-finite one would make those momenta NaN
    // where the forces are NaN already).
    double a[W], B[D][W] = {};
    a[0] = scale * ms, a[1] = scale * ml, a[2] = scale * rho_l_V, a[3] = drag;
    for (int i = 0; i < D; ++i) {
      a[4 + i] = scale * ms * pt.velocity[p * D + i];
      a[4 + D + i] = scale * ml * pt.liquid_velocity[p * D + i];
      a[inertial + i] = mixture * g[i];
      if constexpr (Suction)
        a[inertial + D + i] = rho_l_V * g[i] + pt.liquid_force[p * D + i];
      else
        a[inertial + D + i] = rho_l_V * g[i];
      for (int j = 0; j < D; ++j) {
        B[j][inertial + i] = (i == j ? Vp : 0.0) - V * pt.stress[p * 6 + voigt_index(i, j)];
        B[j][inertial + D + i] = i == j ? Vp_liquid : 0.0;
      }
    }
    Lanes<L> A[vectors], G[D][vectors];
    for (int v = 0; v < vectors; ++v) {
      A[v] = lanes_of<L>(a + v * L);
      for (int j = 0; j < D; ++j) G[j][v] = lanes_of<L>(B[j] + v * L);
    }
    for_each_node<D>(s, p, [&](std::size_t node, double N, const double* grad) {
      double* __restrict o = block + node * W;
      for (int v = 0; v < vectors; ++v) {
        Lanes<L> f = A[v] * N;
        if (v >= first_force_vector)
          for (int j = 0; j < D; ++j) f += G[j][v] * grad[j];
        add_lanes<L>(o + v * L, f);
      }
    });
  }
}

template <int D>
void unpack_saturated_block(std::size_t begin, std::size_t end, const double* block, const SaturatedNodes& out) {
  constexpr int W = saturated_block<D>;
  for (std::size_t I = begin; I < end; ++I) {
    const double* b = block + I * W;
    out.solid_mass[I] = b[0], out.liquid_mass[I] = b[1], out.liquid_inertia[I] = b[2], out.drag[I] = b[3];
    for (int i = 0; i < D; ++i) {
      out.solid_momentum[I * D + i] = b[4 + i];
      out.liquid_momentum[I * D + i] = b[4 + D + i];
      out.force[I * D + i] = b[4 + 2 * D + i];
      out.liquid_force[I * D + i] = b[4 + 3 * D + i];
    }
  }
}

// The MUSL remap of both phases' momenta in one pass, into one block of 2D
// values per node: the solid's momentum, then the liquid's.
template <int D, int L = 2>
[[gnu::always_inline]] inline void remap_two_phase(std::size_t begin, std::size_t end, const PointSupports& s,
                     const double* mass, const double* liquid_mass, double scale, const double* vel,
                     const double* liquid_vel, double* __restrict block) {
  for (std::size_t p = begin; p < end; ++p) {
    double a[2 * D];
    for (int i = 0; i < D; ++i)
      a[i] = scale * mass[p] * vel[p * D + i], a[D + i] = scale * liquid_mass[p] * liquid_vel[p * D + i];
    const WeightedValues<2 * D, L> momenta(a);
    for_each_weight<D>(s, p, [&](std::size_t node, double N) { momenta.add_to(block + node * 2 * D, N); });
  }
}

template <int D>
void unpack_remap_block(std::size_t begin, std::size_t end, const double* block, double* mom, double* liquid_mom) {
  for (std::size_t I = begin; I < end; ++I)
    for (int i = 0; i < D; ++i) mom[I * D + i] = block[I * 2 * D + i], liquid_mom[I * D + i] = block[I * 2 * D + D + i];
}

// Liquid acceleration from its own forces and the drag, then the solid's from
// the mixture balance. Writes the new (unconstrained) velocities.
// The drag relaxes the relative velocity w at the rate
// lambda = drag (1 + m_L / m_s) / inertia. Where the step is shorter than
// 1 / lambda the drag is explicit, on w at the step's start (as the
// verification cases were tuned with). Where it is longer (a clay's
// K = 1e-8 m/s gives 1 / lambda near 1e-11 s) it acts on w at the step's
// end, w + dt (a_L - a_s) with a_s from the mixture balance
// m_s a_s + m_L a_L = f: semi-implicit, so that no conductivity bounds the
// step, and w falls to zero in a step where the drag dominates (the
// undrained limit) instead of overshooting. It predicts a_s undamped: local
// damping (explicit runs only; a collapse has none) then acts on the solid's
// force as everywhere.
template <int D>
void grid_update_saturated(std::size_t begin, std::size_t end, double dt, double damping, const double* ms,
                           const double* ps, const double* f, const double* ml, const double* pl, const double* fl,
                           const double* inertia, const double* drag, double* vs, double* vl) {
  for (std::size_t I = begin; I < end; ++I) {
    if (ms[I] <= 0) {
      for (int i = 0; i < D; ++i) vs[I * D + i] = vl[I * D + i] = 0;
      continue;
    }
    const bool implicit = drag[I] * dt * (1 + ml[I] / ms[I]) > inertia[I];
    for (int i = 0; i < D; ++i) {
      const double vs_old = ps[I * D + i] / ms[I];
      const double vl_old = ml[I] > 0 ? pl[I * D + i] / ml[I] : vs_old;
      const double al =
          inertia[I] <= 0 ? 0.0
          : !implicit     ? (fl[I * D + i] - drag[I] * (vl_old - vs_old)) / inertia[I]
                          : (fl[I * D + i] - drag[I] * (vl_old - vs_old - dt * f[I * D + i] / ms[I])) /
                                (inertia[I] + drag[I] * dt * (1 + ml[I] / ms[I]));
      const double fs = damped(f[I * D + i] - ml[I] * al, vs_old, damping);
      vs[I * D + i] = vs_old + fs / ms[I] * dt;
      vl[I * D + i] = vl_old + al * dt;
    }
  }
}

// After the velocity constraints, where the drag is semi-implicit and a
// condition held a component of the skeleton's velocity (vs differs from
// integrate_grid's vs_free) but left the liquid's free (vl is vl_free): the
// liquid's step again with the skeleton's end velocity known,
//   inertia (vl - vl_old) / dt = fl - drag (vl - vs).
// grid_update_saturated dragged the liquid along the skeleton's free
// acceleration, which carries the wall's unbalanced push: where the drag
// dominates, a held wall's liquid then moved as the unheld skeleton would
// have, and drained through a face open to it (the gravel under a levee
// lost water through its river bed against the river's pressure, its
// pressure there falling from 47 to 15 kPa in half a second with K = 1e-4
// m/s; with K = 1e-2 m/s, explicit drag, it held).
template <int D>
void drag_against_held_solid_kernel(std::size_t begin, std::size_t end, double dt, const double* ms,
                                    const double* ml, const double* pl, const double* fl, const double* inertia,
                                    const double* drag, const double* vs_free, const double* vl_free,
                                    const double* vs, double* vl) {
  for (std::size_t I = begin; I < end; ++I) {
    if (ms[I] <= 0 || ml[I] <= 0 || inertia[I] <= 0) continue;
    if (!(drag[I] * dt * (1 + ml[I] / ms[I]) > inertia[I])) continue;  // explicit drag: on the step's start
    for (int i = 0; i < D; ++i) {
      const std::size_t k = I * D + i;
      if (vs[k] == vs_free[k] || vl[k] != vl_free[k]) continue;
      vl[k] = (inertia[I] * pl[k] / ml[I] + dt * (fl[k] + drag[I] * vs[k])) / (inertia[I] + drag[I] * dt);
    }
  }
}

// The point fields of the porous update.
struct PorousPoints {
  const double* velocity_gradient;  // D x D per point, row-major
  const double* bulk_modulus;       // the pore liquid's
  const double* solid_velocity;     // D per point
  const double* liquid_velocity;    // D per point
  double* porosity;
  double* porosity_increment;
  double* pressure_rate;
  double* darcy;                    // D per point
  const double* saturation;         // S where pores drain (drained_pores.hpp), else null
};

// After the skeleton's velocity gradient L (field) and volume are updated:
// pore pressure rate, porosity and Darcy flux. Returns the first point whose
// porosity fell to zero or below (grains are incompressible), or `end`.
// Starts the step's porosity increment. A dry point (porosity 0) keeps its
// porosity and Darcy flux, with no pressure rate. A gather, then a pass over
// the points on lanes (two divisions per point).
template <int D, int L = 2>
[[gnu::always_inline]] inline std::size_t porous_update(std::size_t begin, std::size_t end, double dt,
                                                        const PointSupports& s, const double* node_q,
                                                        const PorousPoints& pt) {
  // div q with the nodal Darcy flux: the porosity gradient counts (erosion
  // makes porosity vary), as in the transport. Held in the pressure rate.
  for (std::size_t p = begin; p < end; ++p) {
    double div_q = 0;
    for_each_gradient<D>(s, p, [&](std::size_t node, const double* grad) {
      const double* qI = node_q + node * D;
      for (int i = 0; i < D; ++i) div_q += qI[i] * grad[i];
    });
    pt.pressure_rate[p] = div_q;
  }
  bool failed = false;
  for_points_in_lanes<L>(begin, end, [&]<class T>(std::size_t p) {
    const double* l = pt.velocity_gradient + p * D * D;
    T div_s{};
    for (int i = 0; i < D; ++i) div_s += load_at<T, D * D>(l + i * D + i);
    const T J = step_jacobian<D, T>(l, dt);
    const T n0 = load_at<T>(pt.porosity + p), div_q = load_at<T>(pt.pressure_rate + p);
    const auto dry = n0 <= T{};  // a NaN porosity is not dry: it fails below
    const T n = 1.0 - (1.0 - n0) / J;  // incompressible grains: solid volume is conserved
    // Where pores drain, the rate of the water's volume, -(S div v_s + div q):
    // potential_rate (drained_pores.hpp) turns it into the potential's.
    const T S = pt.saturation ? load_at<T>(pt.saturation + p) : splat<T>(1.0);
    const T rate = pt.saturation ? -(S * div_s + div_q) : -load_at<T>(pt.bulk_modulus + p) / n0 * (div_s + div_q);
    store_at(pt.pressure_rate + p, pick(dry, T{}, rate));
    store_at(pt.porosity + p, pick(dry, n0, n));
    store_at(pt.porosity_increment + p, pick(dry, T{}, n - n0));  // erosion adds its share later in the step
    for (int i = 0; i < D; ++i) {
      double* q = pt.darcy + p * D + i;
      const T relative = load_at<T, D>(pt.liquid_velocity + p * D + i) - load_at<T, D>(pt.solid_velocity + p * D + i);
      store_at<T, D>(q, pick(dry, load_at<T, D>(q), n * S * relative));
    }
    const T checked = pick(dry, splat<T>(1.0), n);  // fails !(n > 0), NaN too
    failed = any_lane(checked <= T{}) || any_lane(checked != checked) || failed;
  });
  if (failed)
    for (std::size_t p = begin; p < end; ++p)
      if (pt.porosity_increment[p] != 0 && !(pt.porosity[p] > 0)) return p;  // a wet point: a dry one has no increment
  return end;
}

// Pressure smoothing, scatter half: volume-weighted nodal pressure rates,
// into one block of two values per node (sum N V rate, sum N V).
template <int D, int L = 2>
[[gnu::always_inline]] inline void p2g_pressure_rate(std::size_t begin, std::size_t end, const PointSupports& s,
                       const double* volume, const double* n, const double* rate, double* __restrict block) {
  for (std::size_t p = begin; p < end; ++p) {
    if (n[p] <= 0) continue;  // dry points neither give nor take pore pressure
    const double a[2] = {volume[p] * rate[p], volume[p]};
    const WeightedValues<2, L> rates(a);
    for_each_weight<D>(s, p, [&](std::size_t node, double N) { rates.add_to(block + node * 2, N); });
  }
}

// The nodal rate: the volume-weighted mean (zero at nodes without volume).
inline void nodal_pressure_rate(std::size_t begin, std::size_t end, const double* block, double* node_rate) {
  for (std::size_t I = begin; I < end; ++I)
    node_rate[I] = block[2 * I + 1] > 0 ? block[2 * I] / block[2 * I + 1] : 0.0;
}

// Gather half: each point's pressure grows by the interpolated nodal rate.
template <int D>
void g2p_pressure(std::size_t begin, std::size_t end, double dt, const PointSupports& s, const double* node_rate, const double* n, double* pressure) {
  for (std::size_t p = begin; p < end; ++p) {
    if (n[p] <= 0) continue;  // dry points keep p = 0
    double rate = 0;
    for_each_weight<D>(s, p, [&](std::size_t node, double N) { rate += N * node_rate[node]; });
    pressure[p] += rate * dt;
  }
}

}  // namespace suffuse::detail
