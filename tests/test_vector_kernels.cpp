// The kernels written on lanes (lanes.hpp) against the scalar forms they
// replaced, on random data, bit for bit: the scatters (dry and saturated
// points to grid, both remaps, species, pressure rates), and the gathers
// (grid to points, velocity gradient, the transport's shares), the porous
// update (a gather, then a pass over points on lanes), in 2D and 3D,
// with two lanes, with four lanes on the baseline (the AVX2 path's logic on
// any machine) and on AVX2 where this machine has it (kernel_isa.hpp), with
// some factors zero, as outside a support. Then the
// transport's exchange from per-node shares against the per-face form it
// replaced (each face from both of its nodes).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "parallel/kernel_isa.hpp"
#include "mpm/point_supports.hpp"
#include "test_support.hpp"
#include "mpm/solid_kernels.hpp"
#include "transport/species_kernels.hpp"
#include "suffuse/liquid.hpp"
#include "mixture/two_phase_kernels.hpp"

namespace {

using namespace suffuse::detail;
using suffuse::NodeId;

constexpr std::size_t points = 300, nodes = 48;

// How a kernel runs: two lanes (the portable kernels), four lanes compiled
// for the baseline, or the AVX2 copy.
enum class Variant { two_lanes, four_lanes_baseline, avx2 };

std::string name(Variant v) {
  return v == Variant::two_lanes ? "two lanes" : v == Variant::avx2 ? "avx2" : "four lanes on the baseline";
}

// Every variant, but AVX2 only where the processor has it and the user did
// not choose the portable kernels (as under valgrind).
std::vector<Variant> variants() {
  std::vector<Variant> all{Variant::two_lanes, Variant::four_lanes_baseline};
  const char* chosen = std::getenv("SUFFUSE_KERNELS");
  if (chosen && std::string(chosen) == "portable") return all;
  const suffuse::test::KernelChoice automatic("auto");
  if (kernel_isa_for_this_machine() == KernelIsa::avx2) all.push_back(Variant::avx2);
  return all;
}

template <int D, class Kernel>
void run(Variant v, const Kernel& kernel) {
  if (v == Variant::four_lanes_baseline)
    kernel.template operator()<D, 4>();
  else
    run_vector_kernel(v == Variant::avx2 ? KernelIsa::avx2 : KernelIsa::portable, D, kernel);
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Random point and node data for dimension D: supports of three nodes per
// axis on a grid of `nodes` nodes (6 x 8 in 2D, 4 x 4 x 3 in 3D), the
// kernels' input, and the same written out node by node (ids, w, dw) for
// the scalar forms.
template <int D>
struct Data {
  std::array<int, 3> m;  // support nodes per axis
  int npp = m[0] * m[1] * m[2], per_point = m[0] + m[1] + m[2] - (D == 2 ? 1 : 0);
  std::array<int, 3> grid_nodes = D == 2 ? std::array<int, 3>{6, 8, 1} : std::array<int, 3>{4, 4, 3};
  std::vector<NodeId> first, ids;
  std::vector<double> weights1d, derivatives1d, w, dw, mass, volume, vel, stress, n, pressure, liquid_vel, liquid_mass, conductivity, rho_w,
      fines, carrying, rate, node_a, node_b, node_c, node_scalar;
  Data(unsigned seed, std::array<int, 3> support) : m(support) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-1, 1), pos(0.1, 2);
    auto fill = [&](std::vector<double>& v, std::size_t size, bool positive) {
      v.resize(size);
      for (double& x : v) x = positive ? pos(gen) : u(gen);
    };
    first.resize(points);
    for (auto& f : first) {
      int ijk[3] = {0, 0, 0};
      for (int a = 0; a < D; ++a) ijk[a] = std::uniform_int_distribution<int>(0, grid_nodes[a] - m[a])(gen);
      f = ijk[0] + grid_nodes[0] * (ijk[1] + grid_nodes[1] * ijk[2]);
    }
    weights1d.resize(points * per_point), derivatives1d.resize(points * per_point);
    for (std::size_t p = 0; p < points; ++p)
      for (int k = 0; k < per_point; ++k) {
        weights1d[p * per_point + k] = (p + k) % 7 == 0 ? 0.0 : pos(gen);  // zero, as outside a support
        derivatives1d[p * per_point + k] = (p + k) % 7 == 0 ? 0.0 : u(gen);
      }
    // Node by node for the scalar forms, in the order and with the
    // products the shape function interface documents (written out here,
    // not through point_supports.hpp, so that a change there is seen).
    for (std::size_t p = 0; p < points; ++p) {
      const double* s[3] = {&weights1d[p * per_point], &weights1d[p * per_point + m[0]],
                            &weights1d[p * per_point + m[0] + m[1]]};
      const double* ds[3] = {&derivatives1d[p * per_point], &derivatives1d[p * per_point + m[0]],
                             &derivatives1d[p * per_point + m[0] + m[1]]};
      for (int l = 0; l < (D == 3 ? m[2] : 1); ++l)
        for (int j = 0; j < m[1]; ++j)
          for (int i = 0; i < m[0]; ++i) {
            ids.push_back(first[p] + i + grid_nodes[0] * (j + grid_nodes[1] * l));
            if (D == 2) {
              w.push_back(s[0][i] * s[1][j]);
              dw.push_back(ds[0][i] * s[1][j]), dw.push_back(ds[1][j] * s[0][i]);
            } else {
              w.push_back(s[0][i] * s[1][j] * s[2][l]);
              dw.push_back(ds[0][i] * s[1][j] * s[2][l]), dw.push_back(ds[1][j] * s[0][i] * s[2][l]);
              dw.push_back(ds[2][l] * s[0][i] * s[1][j]);
            }
          }
    }
    fill(mass, points, true), fill(volume, points, true), fill(vel, points * D, false);
    fill(stress, points * 6, false), fill(n, points, true), fill(pressure, points, false);
    for (std::size_t p = 0; p < points; p += 11) n[p] = 0;  // dry points
    fill(liquid_vel, points * D, false), fill(liquid_mass, points, true), fill(conductivity, points, true);
    fill(rho_w, points, true), fill(fines, points, true), fill(carrying, points, true), fill(rate, points, false);
    fill(node_a, nodes * D, false), fill(node_b, nodes * D, false), fill(node_c, nodes * D, false);
    fill(node_scalar, nodes, true);
  }
  PointSupports supports() const {
    return {first.data(), weights1d.data(), derivatives1d.data(), per_point, m,
            {1, grid_nodes[0], D == 3 ? grid_nodes[0] * grid_nodes[1] : 0}};
  }
  SaturatedPoints saturated() const {
    return {mass.data(),       volume.data(), vel.data(),         stress.data(),       n.data(),
            pressure.data(),   liquid_vel.data(), liquid_mass.data(), conductivity.data(), rho_w.data(), nullptr};
  }
};

// The scalar forms, as they were before the lanes.
template <int D>
void p2g_saturated_scalar(const Data<D>& d, const double* g, double scale, double* block) {
  constexpr int W = saturated_block<D>, inertial = 4 + 2 * D;
  const SaturatedPoints pt = d.saturated();
  for (std::size_t p = 0; p < points; ++p) {
    const double ms = pt.mass[p], V = pt.volume[p], n = pt.porosity[p], pr = pt.pressure[p];
    const double ml = n > 0 ? pt.liquid_mass[p] : 0.0;
    const double rho_l_V = n > 0 ? ml / n : 0.0;
    const double drag = n > 0 ? n * pt.water_density[p] * suffuse::reference_gravity * V / pt.conductivity[p] : 0.0;
    const double Vp = V * pr, Vp_liquid = n > 0 ? Vp : 0.0, mixture = ms + ml;
    double a[W], B[2 * D][D];
    a[0] = scale * ms, a[1] = scale * ml, a[2] = scale * rho_l_V, a[3] = drag;
    for (int i = 0; i < D; ++i) {
      a[4 + i] = scale * ms * pt.velocity[p * D + i];
      a[4 + D + i] = scale * ml * pt.liquid_velocity[p * D + i];
      a[inertial + i] = mixture * g[i];
      a[inertial + D + i] = rho_l_V * g[i];
      for (int j = 0; j < D; ++j) {
        B[i][j] = (i == j ? Vp : 0.0) - V * pt.stress[p * 6 + voigt_index(i, j)];
        B[D + i][j] = i == j ? Vp_liquid : 0.0;
      }
    }
    for (int k = 0; k < d.npp; ++k) {
      const std::size_t q = p * d.npp + k;
      double* o = block + static_cast<std::size_t>(d.ids[q]) * W;
      const double N = d.w[q];
      const double* grad = d.dw.data() + q * D;
      for (int c = 0; c < inertial; ++c) o[c] += a[c] * N;
      for (int i = 0; i < 2 * D; ++i) {
        double f = a[inertial + i] * N;
        for (int j = 0; j < D; ++j) f += B[i][j] * grad[j];
        o[inertial + i] += f;
      }
    }
  }
}

template <int D>
void p2g_dry_scalar(const Data<D>& d, const double* g, double scale, double* block) {
  for (std::size_t p = 0; p < points; ++p) {
    const double m = d.mass[p], V = d.volume[p], inertia = scale * m;
    for (int k = 0; k < d.npp; ++k) {
      const std::size_t q = p * d.npp + k;
      double* o = block + static_cast<std::size_t>(d.ids[q]) * dry_block;
      const double N = d.w[q];
      o[0] += inertia * N;
      for (int i = 0; i < D; ++i) {
        o[1 + i] += inertia * d.vel[p * D + i] * N;
        double f = m * g[i] * N;
        for (int j = 0; j < D; ++j) f += -V * d.stress[p * 6 + voigt_index(i, j)] * d.dw[q * D + j];
        o[dry_force + i] += f;
      }
    }
  }
}

template <int D>
void g2p_scalar(const Data<D>& d, double dt, double* x, double* u, double* vel, double* liquid_vel) {
  for (std::size_t p = 0; p < points; ++p) {
    double dv[D] = {}, vg[D] = {}, dvl[D] = {};
    for (int a = 0; a < d.npp; ++a) {
      const std::size_t k = p * d.npp + a, I = static_cast<std::size_t>(d.ids[k]);
      for (int i = 0; i < D; ++i) {
        dv[i] += d.w[k] * d.node_b[I * D + i];
        vg[i] += d.w[k] * d.node_a[I * D + i];
        dvl[i] += d.w[k] * d.node_c[I * D + i];
      }
    }
    for (int i = 0; i < D; ++i) {
      vel[p * D + i] += dt * dv[i];
      x[p * D + i] += dt * vg[i];
      u[p * D + i] += dt * vg[i];
      liquid_vel[p * D + i] += dt * dvl[i];
    }
  }
}

template <int D>
void velocity_gradient_scalar(const Data<D>& d, double* L) {
  for (std::size_t p = 0; p < points; ++p) {
    double l[D][D] = {};
    for (int a = 0; a < d.npp; ++a) {
      const std::size_t k = p * d.npp + a, I = static_cast<std::size_t>(d.ids[k]);
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) l[i][j] += d.node_a[I * D + i] * d.dw[k * D + j];
    }
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) L[p * D * D + i * D + j] = l[i][j];
  }
}

// block[id * width + c] += N * a(p, c) for every point's nodes.
template <int D, class Amount>
void weighted_scalar(const Data<D>& d, int width, Amount a, double* block) {
  for (std::size_t p = 0; p < points; ++p)
    for (int k = 0; k < d.npp; ++k) {
      const std::size_t q = p * d.npp + k;
      for (int c = 0; c < width; ++c) block[static_cast<std::size_t>(d.ids[q]) * width + c] += d.w[q] * a(p, c);
    }
}

// The fields the porous update writes, from a Data's points.
struct PorousFields {
  std::vector<double> L, n, dn, rate, q;
  template <int D>
  PorousFields(const Data<D>& d, const std::vector<double>& gradient)
      : L(gradient), n(d.n), dn(points, -1.0), rate(points, -1.0), q(d.liquid_vel) {
    for (std::size_t p = 0; p < points; ++p) n[p] = d.n[p] > 0 ? 0.2 + 0.2 * d.n[p] : 0.0;  // dry where d's are
  }
  template <int D>
  PorousPoints points_of(const Data<D>& d) {
    return {L.data(), d.mass.data(), d.vel.data(), d.liquid_vel.data(), n.data(), dn.data(), rate.data(), q.data(),
            nullptr};
  }
};

// The porous update as it was before it ran on lanes (the bulk modulus:
// d.mass; the nodal Darcy flux: d.node_a).
template <int D>
std::size_t porous_update_scalar(const Data<D>& d, std::size_t begin, std::size_t end, double dt, PorousFields& f) {
  for (std::size_t p = begin; p < end; ++p) {
    double div_q = 0;
    for (int k = 0; k < d.npp; ++k) {
      const std::size_t a = p * d.npp + k;
      for (int i = 0; i < D; ++i) div_q += d.node_a[static_cast<std::size_t>(d.ids[a]) * D + i] * d.dw[a * D + i];
    }
    const double* l = f.L.data() + p * D * D;
    double div_s = 0;
    for (int i = 0; i < D; ++i) div_s += l[i * D + i];
    double J;
    if constexpr (D == 2) {
      J = (1 + l[0] * dt) * (1 + l[3] * dt) - l[1] * l[2] * dt * dt;
    } else {
      const double a = 1 + l[0] * dt, b = l[1] * dt, c = l[2] * dt, e0 = l[3] * dt, e = 1 + l[4] * dt;
      const double g0 = l[5] * dt, g = l[6] * dt, h = l[7] * dt, i = 1 + l[8] * dt;
      J = a * (e * i - g0 * h) - b * (e0 * i - g0 * g) + c * (e0 * h - e * g);
    }
    const double n0 = f.n[p];
    if (n0 <= 0) {
      f.rate[p] = 0;
      f.dn[p] = 0;
      continue;
    }
    f.rate[p] = -d.mass[p] / n0 * (div_s + div_q);
    f.n[p] = 1 - (1 - n0) / J;
    f.dn[p] = f.n[p] - n0;
    if (!(f.n[p] > 0)) return p;
    for (int i = 0; i < D; ++i) f.q[p * D + i] = f.n[p] * (d.liquid_vel[p * D + i] - d.vel[p * D + i]);
  }
  return end;
}

// support: nodes per axis (2 x 2 (x 2) and 3 x 3 (x 3) run unrolled loops,
// others the general one).
template <int D>
void expect_each_kernel_is_its_scalar_form(std::array<int, 3> support) {
  const Data<D> d(D == 2 ? 17u : 29u, support);
  const double g[3] = {0.3, -9.81, 0.7}, scale = 1.7, dt = 1e-3;
  for (const Variant isa : variants()) {
    const std::string on = " in " + std::to_string(D) + "D, support " + std::to_string(support[0]) + " x " +
                           std::to_string(support[1]) + " x " + std::to_string(support[2]) + ", " + name(isa);
    // Points to grid, saturated and dry.
    std::vector<double> want(nodes * saturated_block<D>, 0.0), got = want;
    p2g_saturated_scalar(d, g, scale, want.data());
    run<D>(isa, [&]<int, int L>() {
      p2g_saturated<D, L>(0, points, d.supports(), d.saturated(), g, scale,
                          got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "p2g_saturated" << on;
    want.assign(nodes * dry_block, 0.0), got = want;
    p2g_dry_scalar(d, g, scale, want.data());
    run<D>(isa, [&]<int, int L>() {
      p2g_kernel<D, L>(0, points, d.supports(), d.mass.data(), d.volume.data(),
                       d.vel.data(), d.stress.data(), g, scale, got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "p2g_kernel" << on;
    // Remaps.
    want.assign(nodes * 2 * D, 0.0), got = want;
    for (std::size_t p = 0; p < points; ++p)
      for (int k = 0; k < d.npp; ++k) {
        const std::size_t q = p * d.npp + k;
        for (int i = 0; i < D; ++i) {
          want[d.ids[q] * 2 * D + i] += d.w[q] * (scale * d.mass[p] * d.vel[p * D + i]);
          want[d.ids[q] * 2 * D + D + i] += d.w[q] * (scale * d.liquid_mass[p] * d.liquid_vel[p * D + i]);
        }
      }
    run<D>(isa, [&]<int, int L>() {
      remap_two_phase<D, L>(0, points, d.supports(), d.mass.data(), d.liquid_mass.data(), scale,
                            d.vel.data(), d.liquid_vel.data(), got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "remap_two_phase" << on;
    want.assign(nodes * D, 0.0), got = want;
    for (std::size_t p = 0; p < points; ++p)
      for (int k = 0; k < d.npp; ++k) {
        const std::size_t q = p * d.npp + k;
        for (int i = 0; i < D; ++i) want[d.ids[q] * D + i] += d.w[q] * (scale * d.mass[p]) * d.vel[p * D + i];
      }
    run<D>(isa, [&]<int, int L>() {
      remap_kernel<D, L>(0, points, d.supports(), d.mass.data(), scale, d.vel.data(), got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "remap_kernel" << on;
    // Species and pressure rates. Dry points add nothing; here they add
    // products with zero, which leave a sum as it was.
    want.assign(nodes * species_block, 0.0), got = want;
    weighted_scalar(d, species_block, [&](std::size_t p, int c) {
      if (d.n[p] <= 0) return 0.0;
      const double a[4] = {d.n[p] * d.volume[p], d.liquid_mass[p], d.fines[p], d.carrying[p]};
      return a[c];
    }, want.data());
    run<D>(isa, [&]<int, int L>() {
      p2g_species<D, L>(0, points, d.supports(), d.volume.data(), d.n.data(),
                     d.liquid_mass.data(), d.fines.data(), d.carrying.data(), got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "p2g_species" << on;
    want.assign(nodes * 2, 0.0), got = want;
    weighted_scalar(d, 2, [&](std::size_t p, int c) {
      return d.n[p] <= 0 ? 0.0 : c == 0 ? d.volume[p] * d.rate[p] : d.volume[p];
    }, want.data());
    run<D>(isa, [&]<int, int L>() {
      p2g_pressure_rate<D, L>(0, points, d.supports(), d.volume.data(), d.n.data(), d.rate.data(),
                           got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "p2g_pressure_rate" << on;
    // Grid to points, both phases.
    std::vector<double> x(points * D, 0.5), u(points * D, 0.1), v(points * D, -0.2), vl(points * D, 0.3);
    std::vector<double> x2 = x, u2 = u, v2 = v, vl2 = vl;
    g2p_scalar(d, dt, x.data(), u.data(), v.data(), vl.data());
    run<D>(isa, [&]<int, int L>() {
      g2p_kernel<D, true, L>(0, points, dt, d.supports(), d.node_a.data(), d.node_b.data(),
                             x2.data(), u2.data(), v2.data(), d.node_c.data(), vl2.data());
    });
    EXPECT_TRUE(same_bits(x, x2) && same_bits(u, u2) && same_bits(v, v2) && same_bits(vl, vl2)) << "g2p" << on;
    run<D>(isa, [&]<int, int L>() {  // the solid alone, as the dry step calls it
      g2p_kernel<D, false, L>(0, points, dt, d.supports(), d.node_a.data(), d.node_b.data(),
                              x2.data(), u2.data(), v2.data());
    });
    std::vector<double> vl_unused(points * D, 0.3);
    g2p_scalar(d, dt, x.data(), u.data(), v.data(), vl_unused.data());
    EXPECT_TRUE(same_bits(x, x2) && same_bits(u, u2) && same_bits(v, v2)) << "g2p without liquid" << on;
    // Velocity gradient.
    std::vector<double> L1(points * D * D), L2 = L1;
    velocity_gradient_scalar(d, L1.data());
    run<D>(isa, [&]<int, int L>() {
      velocity_gradient_kernel<D, false, L>(0, points, dt, d.supports(), d.node_a.data(),
                                            L2.data(), nullptr, nullptr);
    });
    EXPECT_TRUE(same_bits(L1, L2)) << "velocity_gradient" << on;
    // Integrated: the strain increment and the volume from L.
    std::vector<double> e1(points * 6, 0.01), e2 = e1, V1 = d.volume, V2 = d.volume;
    for (std::size_t p = 0; p < points; ++p) {
      const double* Lp = L1.data() + p * D * D;
      for (int i = 0; i < D; ++i)
        for (int j = i; j < D; ++j) e1[p * 6 + voigt_index(i, j)] += 0.5 * (Lp[i * D + j] + Lp[j * D + i]) * dt;
      V1[p] *= step_jacobian<D>(Lp, dt);
    }
    run<D>(isa, [&]<int, int L>() {
      velocity_gradient_kernel<D, true, L>(0, points, dt, d.supports(), d.node_a.data(),
                                           L2.data(), e2.data(), V2.data());
    });
    EXPECT_TRUE(same_bits(L1, L2) && same_bits(e1, e2) && same_bits(V1, V2)) << "velocity_gradient, integrated" << on;
    // The transport's shares: rates per amount held and per pore volume.
    std::vector<double> block(nodes * share_block, 0.0);
    for (int s = 0; s < 3; ++s)
      share_rates(0, nodes, s, d.node_scalar.data(), d.node_scalar.data(), d.node_a.data() + s, block.data());
    std::vector<double> held[3] = {d.liquid_mass, d.fines, d.carrying}, held2[3] = {d.liquid_mass, d.fines, d.carrying};
    for (std::size_t p = 0; p < points; ++p) {
      if (d.n[p] <= 0) continue;
      const double pore = d.n[p] * d.volume[p];
      double change[3] = {};
      for (int k = 0; k < d.npp; ++k) {
        const std::size_t q = p * d.npp + k;
        const double* b = block.data() + static_cast<std::size_t>(d.ids[q]) * share_block;
        for (int s = 0; s < 3; ++s) change[s] += d.w[q] * (held[s][p] * b[s] + pore * b[share_per_pore + s]);
      }
      for (int s = 0; s < 3; ++s) held[s][p] += change[s];
    }
    double* const amounts[3] = {held2[0].data(), held2[1].data(), held2[2].data()};
    run<D>(isa, [&]<int, int L>() {
      g2p_share<D, L>(0, points, d.supports(), d.volume.data(), d.n.data(), block.data(), amounts);
    });
    for (int s = 0; s < 3; ++s) EXPECT_TRUE(same_bits(held[s], held2[s])) << "g2p_share, species " << s << on;
    // The porous update (pressure rate, porosity, Darcy flux), on a range
    // that leaves a group of lanes short, then with points compressed to a
    // porosity of zero or below and one of NaN porosity, of which the first
    // must be named.
    std::vector<double> gradient(points * D * D);
    for (std::size_t k = 0; k < gradient.size(); ++k) gradient[k] = 30 * d.vel[k % (points * D)] * (k % 3 ? 1 : -1);
    for (const bool compressed : {false, true}) {
      PorousFields want(d, gradient), got = want;
      if (compressed) {
        for (std::size_t p : {std::size_t{13}, std::size_t{14}, std::size_t{40}}) {
          want.n[p] = got.n[p] = 0.3;
          for (int i = 0; i < D; ++i) want.L[p * D * D + i * D + i] = got.L[p * D * D + i * D + i] = -500;
        }
        want.n[9] = got.n[9] = std::numeric_limits<double>::quiet_NaN();  // not dry: a failure
      }
      const std::size_t first_want = porous_update_scalar(d, 1, points - 1, dt, want);
      std::size_t first_got = 0;
      run<D>(isa, [&]<int, int L>() {
        first_got = porous_update<D, L>(1, points - 1, dt, d.supports(), d.node_a.data(), got.points_of(d));
      });
      EXPECT_EQ(first_got, first_want) << "porous_update" << on;
      EXPECT_EQ(first_got, compressed ? 9u : points - 1) << "porous_update" << on;
      if (!compressed) {
        EXPECT_TRUE(same_bits(want.n, got.n) && same_bits(want.dn, got.dn) && same_bits(want.rate, got.rate) &&
                    same_bits(want.q, got.q))
            << "porous_update" << on;
      }
    }
  }
}

// The transport's exchange as it was: each face computed from both of its
// nodes, dividing where it reads (species_kernels.hpp had this form).
template <int D>
void face_from_both_nodes(const Transport<D>& t, std::int64_t I, int a, const std::array<int, 3>& c,
                          const double* out, double& liquid, double& fines, double& carrying) {
  const TransportGrid& g = t.g;
  const auto ratio = [&](const double* amount, std::int64_t J) { return g.liquid[J] > 0 ? amount[J] / g.liquid[J] : 0.0; };
  liquid = fines = carrying = 0;
  const double vol = t.face_volume(I, a, c);
  if (vol == 0) return;
  const bool forward = vol > 0;
  const std::int64_t up = forward ? I : I + t.stride(a), down = forward ? I + t.stride(a) : I;
  const int up_index = forward ? c[a] : c[a] + 1;
  const bool has_far = forward ? up_index > 0 : up_index < g.nodes[a] - 1;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double far_liquid = nan, far_ratio = nan, far_carrying = nan;
  if (has_far) {
    const std::int64_t far = forward ? up - t.stride(a) : up + t.stride(a);
    if (g.pore[far] > 0) {
      far_liquid = g.liquid[far] / g.pore[far];
      if (g.fines) far_ratio = ratio(g.fines, far), far_carrying = ratio(g.carrying, far);
    }
  } else if (!std::isnan(g.inflow_liquid[up * D + a])) {
    far_liquid = g.inflow_liquid[up * D + a];
    far_ratio = g.inflow_fines[up * D + a] / far_liquid;
    far_carrying = g.inflow_carrying[up * D + a] / far_liquid;
  }
  const double value = Transport<D>::limited(g.liquid[up] / g.pore[up], g.liquid[down] / g.pore[down], far_liquid);
  liquid = t.scale(up, out) * vol * value;
  if (g.fines) {
    fines = liquid * Transport<D>::limited(ratio(g.fines, up), ratio(g.fines, down), far_ratio);
    carrying = liquid * Transport<D>::limited(ratio(g.carrying, up), ratio(g.carrying, down), far_carrying);
  }
}

template <int D>
void exchange_from_both_nodes(const Transport<D>& t, std::size_t nn, const double* out, std::vector<double> (&r)[6]) {
  const TransportGrid& g = t.g;
  for (std::size_t n = 0; n < nn; ++n) {
    const auto I = static_cast<std::int64_t>(n);
    const auto c = t.ijk(I);
    double dl = 0, df = 0, dc = 0, liquid, fines, carrying;
    for (int a = 0; a < D; ++a) {
      if (c[a] < g.nodes[a] - 1) {
        face_from_both_nodes(t, I, a, c, out, liquid, fines, carrying);
        dl -= liquid, df -= fines, dc -= carrying;
      }
      if (c[a] > 0) {
        auto below = c;
        --below[a];
        face_from_both_nodes(t, I - t.stride(a), a, below, out, liquid, fines, carrying);
        dl += liquid, df += fines, dc += carrying;
      }
    }
    const double free = t.free_surface_volume(I, c);
    r[3][n] = r[4][n] = r[5][n] = 0;
    if (free > 0) {
      const double share = t.scale(I, out) * free / g.pore[I];
      r[3][n] = share * g.liquid[I];
      r[4][n] = g.fines ? share * g.fines[I] : 0.0;
      r[5][n] = g.fines ? share * g.carrying[I] : 0.0;
      dl -= r[3][n], df -= r[4][n], dc -= r[5][n];
    }
    r[0][n] = dl, r[1][n] = df, r[2][n] = dc;
  }
}

// A small grid with dry nodes (free surfaces), inlets on a third of the
// boundary faces, Darcy fluxes large enough that nodes send less than all
// they hold, with and without fines; the shares, flows and exchange run in
// three chunks, as threads would.
template <int D>
void expect_the_exchange_of_the_per_face_form(unsigned seed, bool with_fines) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1, 1), pos(0.1, 2);
  std::uniform_int_distribution<int> pick(0, 9);
  const std::array<int, 3> grid_nodes{7, 6, D == 3 ? 5 : 1};
  const std::size_t nn = static_cast<std::size_t>(grid_nodes[0]) * grid_nodes[1] * grid_nodes[2];
  std::vector<double> pore(nn), liquid(nn), fines(nn), carrying(nn), darcy(nn * D), face(nn * D, 0.0);
  std::vector<double> in_liquid(nn * D, std::numeric_limits<double>::quiet_NaN()), in_fines = in_liquid,
                                                                                   in_carrying = in_liquid;
  for (std::size_t I = 0; I < nn; ++I) {
    const int k = pick(gen);
    pore[I] = k < 2 ? 0.0 : pos(gen);
    liquid[I] = k < 2 ? 0.0 : pos(gen) * pore[I];
    fines[I] = 0.15 * liquid[I] * pos(gen);
    carrying[I] = std::min(liquid[I], 2 * fines[I]);
    for (int a = 0; a < D; ++a) darcy[I * D + a] = 5 * u(gen);
    for (int a = 0; a < D; ++a)
      if (pick(gen) < 3) in_liquid[I * D + a] = pos(gen), in_fines[I * D + a] = 0.1 * pos(gen), in_carrying[I * D + a] = 0.2;
  }
  const TransportGrid g{grid_nodes, {0.1, 0.12, 0.09}, 2.0, pore.data(), liquid.data(),
                        with_fines ? fines.data() : nullptr, with_fines ? carrying.data() : nullptr, darcy.data(),
                        face.data(), in_liquid.data(), in_fines.data(), in_carrying.data()};
  const Transport<D> t{g};
  std::vector<double> out(nn);
  t.faces(0, nn);
  t.outflow(0, nn, out.data());
  std::vector<double> want[6], got[6];
  for (auto& r : want) r.assign(nn, -7.0);
  for (auto& r : got) r.assign(nn, -7.0);
  exchange_from_both_nodes(t, nn, out.data(), want);
  std::vector<double> per_pore(nn), fines_ratio(nn), carrying_ratio(nn), send(nn), flow(nn * D * 3, 0.0);
  const NodeShares shares{per_pore.data(), fines_ratio.data(), carrying_ratio.data(), send.data(), flow.data()};
  const auto chunk = [&](int c) { return nn * static_cast<std::size_t>(c) / 3; };
  for (int c = 0; c < 3; ++c) t.shares(chunk(c), chunk(c + 1), out.data(), shares);
  for (int c = 0; c < 3; ++c) t.flows(chunk(c), chunk(c + 1), shares);
  for (int c = 0; c < 3; ++c)
    t.exchange(chunk(c), chunk(c + 1), shares, got[0].data(), got[1].data(), got[2].data(), got[3].data(),
               got[4].data(), got[5].data());
  const char* what[6] = {"liquid", "fines", "carrying liquid", "free liquid", "free fines", "free carrying"};
  for (int k = 0; k < 6; ++k) EXPECT_TRUE(same_bits(want[k], got[k])) << what[k] << " in " << D << "D, seed " << seed;
  std::size_t moving = 0, sending_less = 0;
  for (std::size_t I = 0; I < nn; ++I) moving += want[0][I] != 0, sending_less += pore[I] > 0 && send[I] < 1;
  EXPECT_GT(moving, nn / 2) << "most nodes must exchange liquid";
  EXPECT_GT(sending_less, 0u) << "some nodes must send less than they could";
}

TEST(VectorKernels, TransportExchangeIsThePerFaceFormBitForBit) {
  for (unsigned seed = 1; seed <= 5; ++seed)
    for (const bool with_fines : {true, false}) {
      expect_the_exchange_of_the_per_face_form<2>(seed, with_fines);
      expect_the_exchange_of_the_per_face_form<3>(seed + 100, with_fines);
    }
}

TEST(VectorKernels, EachIsItsScalarFormBitForBitIn2D) {
  for (const std::array<int, 3> m : {std::array<int, 3>{3, 3, 1}, {2, 2, 1}, {3, 2, 1}})
    expect_each_kernel_is_its_scalar_form<2>(m);
}
TEST(VectorKernels, EachIsItsScalarFormBitForBitIn3D) {
  for (const std::array<int, 3> m : {std::array<int, 3>{3, 3, 3}, {2, 2, 2}, {3, 3, 2}})
    expect_each_kernel_is_its_scalar_form<3>(m);
}

// The erosion's per-point passes as they were before they ran on lanes
// (species_kernels.hpp and SpeciesTransport::erode had these forms).
namespace before {
double suspended_concentration(double fines, double liquid, double rho_s, double rho_w) {
  const double v_fines = fines / rho_s, v_water = std::max(0.0, liquid - fines) / rho_w;
  return v_fines > 0 ? v_fines / (v_fines + v_water) : 0.0;
}
std::pair<double, double> carrier_state(double fines, double carrying, double liquid, double rho_s, double rho_w) {
  const double v_fines = fines / rho_s;
  const double v_carrying = v_fines + std::max(0.0, carrying - fines) / rho_w;
  const double v_liquid = v_fines + std::max(0.0, liquid - fines) / rho_w;
  if (carrying >= liquid) return {1.0, suspended_concentration(fines, liquid, rho_s, rho_w)};
  return {v_liquid > 0 ? std::min(1.0, v_carrying / v_liquid) : 0.0,
          suspended_concentration(fines, carrying, rho_s, rho_w)};
}
void apply_erosion(std::size_t begin, std::size_t end, double dt, const SpeciesPoints& pt,
                   const double* ultimate_fines, double* rate) {
  for (std::size_t p = begin; p < end; ++p) {
    const double rho_s = pt.grain_density[p], V = pt.volume[p];
    const double ms = pt.solid_mass[p], fines = pt.skeleton_fines[p], f_inf = ultimate_fines[p];
    double moved = rho_s * rate[p] * V * dt;
    if (moved > 0)
      moved = std::min(moved, std::max(0.0, (fines - f_inf * ms) / (1 - f_inf)));
    else
      moved = std::max(moved, -pt.suspended_fines[p]);
    pt.solid_mass[p] = ms - moved;
    pt.skeleton_fines[p] = fines - moved;
    pt.suspended_fines[p] += moved;
    pt.liquid_mass[p] += moved;
    if (pt.carrying_liquid) pt.carrying_liquid[p] = std::max(0.0, pt.carrying_liquid[p] + moved);
    pt.eroded_mass[p] += moved;
    pt.porosity[p] += moved / (rho_s * V);
    rate[p] = moved / (rho_s * V * dt);
  }
}
}  // namespace before

// The species of random points, with the cases the passes select between:
// all liquid carrying or only part of it, more suspended fines than liquid,
// no suspended fines, rates that erode, deposit or do nothing, points
// already below f_c_inf, dry points.
struct ErosionData {
  std::vector<double> solid, skeleton, suspended, liquid, eroded, volume, n, rho_s, carrying, q, K, rho_w, f_inf,
      rate, fc, fer, dn, dfc, dfer, magnitude, gradient, c, share, carrier_c, density, moving;
  explicit ErosionData(unsigned seed, int dim) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(0, 1);
    auto fill = [&](std::vector<double>& v, std::size_t size, double lo, double hi) {
      v.resize(size);
      for (double& x : v) x = lo + (hi - lo) * u(gen);
    };
    fill(solid, points, 1, 2), fill(skeleton, points, 0, 0.5), fill(suspended, points, 0, 0.1);
    fill(liquid, points, 0.05, 1), fill(eroded, points, 0, 0.1), fill(volume, points, 1e-4, 1e-3);
    fill(n, points, 0.2, 0.5), fill(rho_s, points, 2500, 2700), fill(carrying, points, 0, 1.2);
    fill(q, points * dim, -1e-3, 1e-3), fill(K, points, 1e-5, 1e-3), fill(rho_w, points, 990, 1010);
    fill(f_inf, points, 0, 0.3), fill(rate, points, -2, 2), fill(dn, points, -1e-3, 1e-3);
    fill(fer, points, 0, 0.1), fill(density, points, 1000, 1100), fill(moving, points, 0, 1);
    for (std::size_t p = 0; p < points; ++p) {
      fc.push_back(skeleton[p] / solid[p]);
      if (p % 5 == 0) carrying[p] = liquid[p];   // all of the liquid carries
      if (p % 7 == 0) suspended[p] = 0;           // clean water
      if (p % 13 == 0) suspended[p] = 2 * liquid[p];
      if (p % 3 == 0) rate[p] = 0;
      if (p % 17 == 0) n[p] = 0;                  // dry
    }
    dfc = dfer = magnitude = gradient = c = share = carrier_c = std::vector<double>(points, -1.0);
  }
  SpeciesPoints species() {
    return {solid.data(), skeleton.data(), suspended.data(), liquid.data(), eroded.data(),
            volume.data(), n.data(),       rho_s.data(),     carrying.data()};
  }
};

bool same_erosion_state(ErosionData& a, ErosionData& b) {
  const auto fields = [](ErosionData& d) {
    return std::vector<std::vector<double>*>{
        &d.solid, &d.skeleton, &d.suspended, &d.liquid, &d.eroded, &d.n,         &d.carrying, &d.rate, &d.fc,
        &d.fer,   &d.dn,       &d.dfc,       &d.dfer,   &d.magnitude, &d.gradient, &d.c,      &d.share, &d.carrier_c,
        &d.density, &d.moving};
  };
  const auto x = fields(a), y = fields(b);
  for (std::size_t k = 0; k < x.size(); ++k)
    if (!same_bits(*x[k], *y[k])) return false;
  return true;
}

// The erosion's inputs, its update and the pore liquid's density after the
// transport, on lanes, against the scalar code they replaced. The range
// leaves a point at each end out and a group of lanes short at its end.
template <int D>
void expect_the_erosion_passes_of_their_scalar_form() {
  const std::size_t begin = 1, end = points - 1;
  const double dt = 0.05;
  for (const Variant isa : variants()) {
    const std::string on = " in " + std::to_string(D) + "D, " + name(isa);
    ErosionData want(D == 2 ? 41u : 43u, D), got = want;
    bool mixed_want = false, moved_want = false;
    {
      const SpeciesPoints pt = want.species();
      for (std::size_t p = begin; p < end; ++p) {
        double q2 = 0;
        for (int i = 0; i < D; ++i) q2 += want.q[p * D + i] * want.q[p * D + i];
        want.magnitude[p] = std::sqrt(q2);
        want.gradient[p] = want.magnitude[p] / want.K[p];
        want.fc[p] = pt.skeleton_fines[p] / pt.solid_mass[p];
        want.c[p] = before::suspended_concentration(pt.suspended_fines[p], pt.liquid_mass[p], pt.grain_density[p],
                                                    want.rho_w[p]);
        const auto [share, conc] = before::carrier_state(pt.suspended_fines[p], want.carrying[p], pt.liquid_mass[p],
                                                         pt.grain_density[p], want.rho_w[p]);
        want.share[p] = share, want.carrier_c[p] = conc;
        mixed_want = mixed_want || share < 1;
      }
      for (std::size_t p = begin; p < end; ++p)
        want.dn[p] -= want.n[p], want.dfc[p] = want.fc[p], want.dfer[p] = want.fer[p];
      before::apply_erosion(begin, end, dt, pt, want.f_inf.data(), want.rate.data());
      for (std::size_t p = begin; p < end; ++p) moved_want = moved_want || want.rate[p] != 0;
      for (std::size_t p = begin; p < end; ++p) {
        want.fc[p] = pt.skeleton_fines[p] / pt.solid_mass[p];
        want.fer[p] = pt.eroded_mass[p] / (pt.solid_mass[p] + pt.eroded_mass[p]);
        want.dn[p] += want.n[p];
        want.dfc[p] = want.fc[p] - want.dfc[p];
        want.dfer[p] = want.fer[p] - want.dfer[p];
      }
      for (std::size_t p = begin; p < end; ++p) {
        if (want.n[p] <= 0) continue;
        const double conc = before::suspended_concentration(want.suspended[p], want.liquid[p], want.rho_s[p],
                                                            want.rho_w[p]);
        want.c[p] = conc;
        want.density[p] = suffuse::suspension_density(conc, want.rho_s[p], want.rho_w[p]);
        want.moving[p] = want.n[p] * want.volume[p] * want.density[p];
      }
    }
    bool mixed = false, moved = false;
    const SpeciesPoints pt = got.species();
    // The block's scratch (magnitude, share, carrier_c) is indexed from `begin`.
    const ErosionInputs in{got.q.data(),  got.K.data(),        got.rho_w.data(), got.magnitude.data() + begin,
                           got.gradient.data(), got.fc.data(), got.c.data(),     got.share.data() + begin,
                           got.carrier_c.data() + begin};
    const ErosionState st{got.fc.data(), got.fer.data(), got.dn.data(), got.dfc.data(), got.dfer.data()};
    const PoreLiquidPoints liquid{got.volume.data(), got.n.data(),    got.rho_s.data(),   got.rho_w.data(),
                                  got.suspended.data(), got.liquid.data(), got.c.data(), got.density.data(),
                                  got.moving.data()};
    run<D>(isa, [&]<int, int L>() {
      mixed = erosion_inputs<D, L>(begin, end, pt, in);
      moved = erode_points<L>(begin, end, dt, pt, got.f_inf.data(), got.rate.data(), st);
      pore_liquid_density<L>(begin, end, liquid);
    });
    EXPECT_TRUE(same_erosion_state(want, got)) << "erosion passes" << on;
    EXPECT_EQ(mixed, mixed_want) << on;
    EXPECT_EQ(moved, moved_want) << on;
    EXPECT_TRUE(mixed && moved) << "the data must hold mixed points and erode";
  }
}

TEST(VectorKernels, ErosionPassesAreTheirScalarFormBitForBit) {
  expect_the_erosion_passes_of_their_scalar_form<2>();
  expect_the_erosion_passes_of_their_scalar_form<3>();
}

}  // namespace
