// The kernels written on lanes (lanes.hpp) against the scalar forms they
// replaced, on random data, bit for bit, on each instruction set this
// machine has (kernel_isa.hpp): the scatters (dry and saturated points to
// grid, both remaps, species, pressure rates), and the gathers (grid to
// points, velocity gradient, the transport's shares), in 2D and 3D. Node ids
// repeat within a point's support, as they do at a grid edge.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "kernel_isa.hpp"
#include "solid_kernels.hpp"
#include "species_kernels.hpp"
#include "two_phase_kernels.hpp"

namespace {

using namespace suffuse::detail;
using suffuse::NodeId;

constexpr std::size_t points = 300, nodes = 40;

std::vector<KernelIsa> instruction_sets() {
  std::vector<KernelIsa> sets{KernelIsa::portable};
  setenv("SUFFUSE_KERNELS", "auto", 1);
  if (kernel_isa_for_this_machine() == KernelIsa::avx2) sets.push_back(KernelIsa::avx2);
  unsetenv("SUFFUSE_KERNELS");
  return sets;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Random point and node data for dimension D (npp nodes per point).
template <int D>
struct Data {
  int npp = D == 2 ? 9 : 27;
  std::vector<NodeId> ids;
  std::vector<double> w, dw, mass, volume, vel, stress, n, pressure, liquid_vel, liquid_mass, conductivity, rho_w,
      fines, carrying, rate, node_a, node_b, node_c, node_scalar;
  explicit Data(unsigned seed) {
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> u(-1, 1), pos(0.1, 2);
    std::uniform_int_distribution<NodeId> id(0, nodes - 1);
    auto fill = [&](std::vector<double>& v, std::size_t size, bool positive) {
      v.resize(size);
      for (double& x : v) x = positive ? pos(gen) : u(gen);
    };
    ids.resize(points * npp);
    for (auto& i : ids) i = id(gen);
    fill(w, points * npp, true);
    fill(dw, points * npp * D, false);
    for (std::size_t q = 0; q < w.size(); q += 7) w[q] = 0, dw[q * D] = 0;  // zero weights, as outside a support
    fill(mass, points, true), fill(volume, points, true), fill(vel, points * D, false);
    fill(stress, points * 6, false), fill(n, points, true), fill(pressure, points, false);
    for (std::size_t p = 0; p < points; p += 11) n[p] = 0;  // dry points
    fill(liquid_vel, points * D, false), fill(liquid_mass, points, true), fill(conductivity, points, true);
    fill(rho_w, points, true), fill(fines, points, true), fill(carrying, points, true), fill(rate, points, false);
    fill(node_a, nodes * D, false), fill(node_b, nodes * D, false), fill(node_c, nodes * D, false);
    fill(node_scalar, nodes, true);
  }
  SaturatedPoints saturated() const {
    return {mass.data(),       volume.data(), vel.data(),         stress.data(),       n.data(),
            pressure.data(),   liquid_vel.data(), liquid_mass.data(), conductivity.data(), rho_w.data()};
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

template <int D>
void expect_each_kernel_is_its_scalar_form() {
  const Data<D> d(D == 2 ? 17u : 29u);
  const double g[3] = {0.3, -9.81, 0.7}, scale = 1.7, dt = 1e-3;
  for (const KernelIsa isa : instruction_sets()) {
    const std::string on = " in " + std::to_string(D) + "D on " + kernel_isa_name(isa);
    // Points to grid, saturated and dry.
    std::vector<double> want(nodes * saturated_block<D>, 0.0), got = want;
    p2g_saturated_scalar(d, g, scale, want.data());
    run_vector_kernel(isa, D, [&]<int, int L>() {
      p2g_saturated<D, L>(0, points, d.npp, d.ids.data(), d.w.data(), d.dw.data(), d.saturated(), g, scale,
                          got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "p2g_saturated" << on;
    want.assign(nodes * dry_block, 0.0), got = want;
    p2g_dry_scalar(d, g, scale, want.data());
    run_vector_kernel(isa, D, [&]<int, int L>() {
      p2g_kernel<D, L>(0, points, d.npp, d.ids.data(), d.w.data(), d.dw.data(), d.mass.data(), d.volume.data(),
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
    run_vector_kernel(isa, D, [&]<int, int L>() {
      remap_two_phase<D, L>(0, points, d.npp, d.ids.data(), d.w.data(), d.mass.data(), d.liquid_mass.data(), scale,
                            d.vel.data(), d.liquid_vel.data(), got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "remap_two_phase" << on;
    want.assign(nodes * D, 0.0), got = want;
    for (std::size_t p = 0; p < points; ++p)
      for (int k = 0; k < d.npp; ++k) {
        const std::size_t q = p * d.npp + k;
        for (int i = 0; i < D; ++i) want[d.ids[q] * D + i] += d.w[q] * (scale * d.mass[p]) * d.vel[p * D + i];
      }
    run_vector_kernel(isa, D, [&]<int, int L>() {
      remap_kernel<D, L>(0, points, d.npp, d.ids.data(), d.w.data(), d.mass.data(), scale, d.vel.data(), got.data());
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
    run_vector_kernel(isa, D, [&]<int, int L>() {
      p2g_species<L>(0, points, d.npp, d.ids.data(), d.w.data(), d.volume.data(), d.n.data(),
                     d.liquid_mass.data(), d.fines.data(), d.carrying.data(), got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "p2g_species" << on;
    want.assign(nodes * 2, 0.0), got = want;
    weighted_scalar(d, 2, [&](std::size_t p, int c) {
      return d.n[p] <= 0 ? 0.0 : c == 0 ? d.volume[p] * d.rate[p] : d.volume[p];
    }, want.data());
    run_vector_kernel(isa, D, [&]<int, int L>() {
      p2g_pressure_rate<L>(0, points, d.npp, d.ids.data(), d.w.data(), d.volume.data(), d.n.data(), d.rate.data(),
                           got.data());
    });
    EXPECT_TRUE(same_bits(want, got)) << "p2g_pressure_rate" << on;
    // Grid to points, both phases.
    std::vector<double> x(points * D, 0.5), u(points * D, 0.1), v(points * D, -0.2), vl(points * D, 0.3);
    std::vector<double> x2 = x, u2 = u, v2 = v, vl2 = vl;
    g2p_scalar(d, dt, x.data(), u.data(), v.data(), vl.data());
    run_vector_kernel(isa, D, [&]<int, int L>() {
      g2p_kernel<D, true, L>(0, points, d.npp, dt, d.ids.data(), d.w.data(), d.node_a.data(), d.node_b.data(),
                             x2.data(), u2.data(), v2.data(), d.node_c.data(), vl2.data());
    });
    EXPECT_TRUE(same_bits(x, x2) && same_bits(u, u2) && same_bits(v, v2) && same_bits(vl, vl2)) << "g2p" << on;
    // Velocity gradient.
    std::vector<double> L1(points * D * D), L2 = L1;
    velocity_gradient_scalar(d, L1.data());
    run_vector_kernel(isa, D, [&]<int, int L>() {
      velocity_gradient_kernel<D, false, L>(0, points, d.npp, dt, d.ids.data(), d.dw.data(), d.node_a.data(),
                                            L2.data(), nullptr, nullptr);
    });
    EXPECT_TRUE(same_bits(L1, L2)) << "velocity_gradient" << on;
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
    run_vector_kernel(isa, D, [&]<int, int L>() {
      g2p_share<L>(0, points, d.npp, d.ids.data(), d.w.data(), d.volume.data(), d.n.data(), block.data(), amounts);
    });
    for (int s = 0; s < 3; ++s) EXPECT_TRUE(same_bits(held[s], held2[s])) << "g2p_share, species " << s << on;
  }
}

TEST(VectorKernels, EachIsItsScalarFormBitForBitIn2D) { expect_each_kernel_is_its_scalar_form<2>(); }
TEST(VectorKernels, EachIsItsScalarFormBitForBitIn3D) { expect_each_kernel_is_its_scalar_form<3>(); }

}  // namespace
