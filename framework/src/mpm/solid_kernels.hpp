#pragma once
// Kernels of the single-phase (dry) MUSL step, one loop each, specialised by
// dimension: points to grid, grid update, grid to points, MUSL remap, and
// the velocity gradient.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "parallel/lanes.hpp"
#include "mpm/point_supports.hpp"
#include "suffuse/grid.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse::detail {

using tensor::voigt_index;  // xx yy zz yz xz xy

// det(I + L dt) for a row-major D x D velocity gradient L: the volume ratio
// of a step. On lanes (T = Lanes<L>), of the consecutive points from l on.
template <int D, class T = double>
[[gnu::always_inline]] inline T step_jacobian(const double* l, double dt) {
  const auto c = [&](int k) { return load_at<T, D * D>(l + k); };
  if constexpr (D == 2) {
    return (1.0 + c(0) * dt) * (1.0 + c(3) * dt) - c(1) * c(2) * dt * dt;
  } else {
    const T a = 1.0 + c(0) * dt, b = c(1) * dt, d0 = c(2) * dt, d = c(3) * dt, e = 1.0 + c(4) * dt;
    const T f = c(5) * dt, g = c(6) * dt, h = c(7) * dt, i = 1.0 + c(8) * dt;
    return a * (e * i - f * h) - b * (d * i - f * g) + d0 * (d * h - e * g);
  }
}

// Local non-viscous damping (Cundall): a force opposing the motion,
// proportional to the unbalanced force.
inline double damped(double force, double velocity, double damping) {
  if (damping > 0 && velocity != 0) force -= damping * std::abs(force) * (velocity > 0 ? 1.0 : -1.0);
  return force;
}

// The force before damped(): damping < 1 keeps the sign of the force, so
// f_d = f (1 - damping sign(f) sign(v)) is inverted exactly.
inline double undamped(double damped_force, double velocity, double damping) {
  if (damping > 0 && velocity != 0)
    damped_force /= 1 - damping * (damped_force > 0 ? 1.0 : -1.0) * (velocity > 0 ? 1.0 : -1.0);
  return damped_force;
}

// The scatters copy what they read of a point into locals first: the node
// arrays could alias it for all the compiler knows, and it would reload it
// after every store.
//
// Points to grid, dry: a node's sums in one block of dry_block values,
// mass and momentum (1 + D) from its start, force (D) from dry_force.
// Every sum is linear in the node's weight N and gradient: block += a N +
// B grad N, with a and B formed once per point, so a node costs a few
// multiply-adds on one contiguous block instead of a load and a store in each
// of three arrays (unpack_dry_block spreads them). The block is padded to
// whole vectors of four, inertia in the first, forces in the second.
inline constexpr int dry_block = 8, dry_force = 4;

template <int D, int L = 2>
[[gnu::always_inline]] inline void p2g_kernel(std::size_t begin, std::size_t end, const PointSupports& s,
                const double* mass, const double* volume, const double* vel, const double* stress,
                const double* g, double scale, double* __restrict block) {
  constexpr int W = dry_block, vectors = W / L;
  for (std::size_t p = begin; p < end; ++p) {
    const double m = mass[p], V = volume[p], inertia = scale * m;
    // a: the coefficients of N; B[j]: those of dN/dx_j (-V sigma, in the
    // forces only).
    double a[W] = {}, B[D][W] = {};
    a[0] = inertia;
    for (int i = 0; i < D; ++i) {
      a[1 + i] = inertia * vel[p * D + i];
      a[dry_force + i] = m * g[i];
      for (int j = 0; j < D; ++j) B[j][dry_force + i] = -V * stress[p * 6 + voigt_index(i, j)];
    }
    Lanes<L> A[vectors], G[D][vectors];
    for (int v = 0; v < vectors; ++v) {
      A[v] = lanes_of<L>(a + v * L);
      for (int j = 0; j < D; ++j) G[j][v] = lanes_of<L>(B[j] + v * L);
    }
    for_each_node<D>(s, p, [&](std::size_t node, double N, const double* grad) {
      double* __restrict o = block + node * W;
      for (int v = 0; v < vectors; ++v) {
        const int first = v * L, last = first + L;  // the lanes [first, last)
        if (first > D && last <= dry_force) continue;  // padding only
        if (first >= dry_force + D) continue;
        Lanes<L> f = A[v] * N;
        if (last > dry_force)
          for (int j = 0; j < D; ++j) f += G[j][v] * grad[j];
        add_lanes<L>(o + first, f);
      }
    });
  }
}

template <int D>
void unpack_dry_block(std::size_t begin, std::size_t end, const double* block, double* node_mass, double* node_mom,
                      double* node_force) {
  for (std::size_t I = begin; I < end; ++I) {
    const double* b = block + I * dry_block;
    node_mass[I] = b[0];
    for (int i = 0; i < D; ++i) node_mom[I * D + i] = b[1 + i], node_force[I * D + i] = b[dry_force + i];
  }
}

template <int D>
void grid_update_kernel(std::size_t begin, std::size_t end, double dt, double damping, const double* mass,
                        const double* mom, double* force, double* vel) {
  for (std::size_t I = begin; I < end; ++I) {
    const double m = mass[I];
    if (m <= 0) {
      for (int i = 0; i < D; ++i) vel[I * D + i] = 0;
      continue;
    }
    for (int i = 0; i < D; ++i) {
      const double v_old = mom[I * D + i] / m;
      const double f = damped(force[I * D + i], v_old, damping);
      force[I * D + i] = f;
      vel[I * D + i] = v_old + f / m * dt;
    }
  }
}

// Nodal acceleration of the step after the constraints: (v - p/m) / dt.
template <int D>
void acceleration_kernel(std::size_t begin, std::size_t end, double dt, const double* mass, const double* mom,
                         const double* vel, double* acc) {
  for (std::size_t I = begin; I < end; ++I) {
    const double m = mass[I];
    for (int i = 0; i < D; ++i) acc[I * D + i] = m > 0 ? (vel[I * D + i] - mom[I * D + i] / m) / dt : 0.0;
  }
}

// Grid to points: FLIP velocity from the nodal acceleration, positions and
// displacements from the nodal velocity. WithLiquid: the pore liquid's FLIP
// velocity too, in the same pass over the points' nodes (the two-phase step).
template <int D, bool WithLiquid = false, int L = 2>
[[gnu::always_inline]] inline void g2p_kernel(std::size_t begin, std::size_t end, double dt, const PointSupports& s,
                const double* node_vel, const double* node_acc, double* x, double* u, double* vel,
                const double* node_liquid_acc = nullptr, double* liquid_vel = nullptr) {
  for (std::size_t p = begin; p < end; ++p) {
    WeightedSums<D, L> dv, vg, dvl;
    for_each_weight<D>(s, p, [&](std::size_t node, double N) {
      const std::size_t I = node * D;
      dv.add(node_acc + I, N);
      vg.add(node_vel + I, N);
      if constexpr (WithLiquid) dvl.add(node_liquid_acc + I, N);
    });
    for (int i = 0; i < D; ++i) {
      vel[p * D + i] += dt * dv[i];
      x[p * D + i] += dt * vg[i];
      u[p * D + i] += dt * vg[i];
      if constexpr (WithLiquid) liquid_vel[p * D + i] += dt * dvl[i];
    }
  }
}

template <int D, int L = 2>
[[gnu::always_inline]] inline void remap_kernel(std::size_t begin, std::size_t end, const PointSupports& s,
                  const double* mass, double scale, const double* vel, double* node_mom) {
  for (std::size_t p = begin; p < end; ++p) {
    const double m = scale * mass[p];
    const WeightedValues<D, L> velocity(vel + p * D);
    for_each_weight<D>(s, p, [&](std::size_t node, double N) { velocity.add_to(node_mom + node * D, N * m); });
  }
}

// Nodal velocities from momenta: p / m, zero at nodes without mass.
template <int D>
void velocity_from_momentum(std::size_t begin, std::size_t end, const double* mass, const double* mom, double* vel) {
  for (std::size_t I = begin; I < end; ++I) {
    const double m = mass[I];
    for (int i = 0; i < D; ++i) vel[I * D + i] = m > 0 ? mom[I * D + i] / m : 0.0;
  }
}

// The velocity gradient of each point from the nodal velocities, L =
// sum_I v_I (grad N_I)^T. Integrate: also strain += sym(L) dt and
// volume *= det(I + L dt) in the same pass (strain_volume_kernel does it
// after a change of L).
template <int D, bool Integrate = true, int L = 2>
[[gnu::always_inline]] inline void velocity_gradient_kernel(std::size_t begin, std::size_t end, double dt,
                              const PointSupports& s, const double* node_vel, double* L_field, double* strain,
                              double* volume) {
  for (std::size_t p = begin; p < end; ++p) {
    WeightedSums<D, L> column[D];  // column j: v_i dN/dx_j over i
    for_each_gradient<D>(s, p, [&](std::size_t node, const double* grad) {
      const double* v = node_vel + node * D;
      for (int j = 0; j < D; ++j) column[j].add(v, grad[j]);
    });
    double* Lp = L_field + p * D * D;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) Lp[i * D + j] = column[j][i];
    if constexpr (Integrate) {
      double* e = strain + p * 6;
      for (int i = 0; i < D; ++i)
        for (int j = i; j < D; ++j) e[voigt_index(i, j)] += 0.5 * (Lp[i * D + j] + Lp[j * D + i]) * dt;
      // Volume follows det(I + L dt) of the step.
      volume[p] *= step_jacobian<D>(Lp, dt);
    }
  }
}

template <int D>
void strain_volume_kernel(std::size_t begin, std::size_t end, double dt, const double* L, double* strain,
                          double* volume) {
  for (std::size_t p = begin; p < end; ++p) {
    const double* Lp = L + p * D * D;
    double* e = strain + p * 6;
    for (int i = 0; i < D; ++i)
      for (int j = i; j < D; ++j) e[voigt_index(i, j)] += 0.5 * (Lp[i * D + j] + Lp[j * D + i]) * dt;
    volume[p] *= step_jacobian<D>(Lp, dt);
  }
}

// Cell-averaged volumetric strain rate (anti-locking): the volume and the
// volume-weighted trace of L of the points of each cell...
template <int D>
void cell_volumetric_rate_kernel(std::size_t begin, std::size_t end, const NodeId* cell, const double* L,
                                 const double* volume, double* cell_volume, double* cell_rate) {
  for (std::size_t p = begin; p < end; ++p) {
    const double* Lp = L + p * D * D;
    double tr = 0;
    for (int i = 0; i < D; ++i) tr += Lp[i * D + i];
    cell_volume[cell[p]] += volume[p];
    cell_rate[cell[p]] += volume[p] * tr;
  }
}

// ... then each point's trace replaced by its cell's mean, the deviatoric
// part of L kept.
template <int D>
void replace_volumetric_rate_kernel(std::size_t begin, std::size_t end, const NodeId* cell,
                                    const double* cell_volume, const double* cell_rate, double* L) {
  for (std::size_t p = begin; p < end; ++p) {
    double* Lp = L + p * D * D;
    double tr = 0;
    for (int i = 0; i < D; ++i) tr += Lp[i * D + i];
    const double shift = (cell_rate[cell[p]] / cell_volume[cell[p]] - tr) / D;
    for (int i = 0; i < D; ++i) Lp[i * D + i] += shift;
  }
}

}  // namespace suffuse::detail
