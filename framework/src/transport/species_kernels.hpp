#pragma once
// Kernels of the species balances of a saturated run (docs/erosion.md):
// erosion moves solid from the skeleton to the liquid at the points; the
// liquid and its suspended fines then move across the grid with the Darcy
// flux, by a finite-volume scheme on the dual cells of the nodes (MUSCL with
// the van Leer limiter; the fines as the liquid times its limited fines
// fraction). Every exchange is a transfer between two accounts, so the mass of
// each species is conserved to round-off.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

#include "parallel/lanes.hpp"
#include "mpm/point_supports.hpp"
#include "suffuse/grid.hpp"

namespace suffuse::detail {

// Volume fraction of fines in the liquid a point carries: fines volume over
// fines plus water volume. In [0, 1] whatever the amounts, so a point where
// the transport piles liquid up (below a free surface) keeps a physical c.
// For one point (T = double) or several (T = Lanes<L>, lanes.hpp).
template <class T>
[[gnu::always_inline]] inline T suspended_concentration(T fines, T liquid, T rho_s, T rho_w) {
  const T v_fines = fines / rho_s, v_water = lane_max(T{}, liquid - fines) / rho_w;
  return pick(v_fines > T{}, v_fines / (v_fines + v_water), T{});
}

// Per-point state of the species, spans of the point count.
struct SpeciesPoints {
  double* solid_mass;       // the skeleton's solid, its fines included [kg]
  double* skeleton_fines;   // erodible fines still in the skeleton [kg]
  double* suspended_fines;  // fines carried by the pore liquid [kg]
  double* liquid_mass;      // pore liquid, suspended fines included [kg]
  double* eroded_mass;      // solid this point has lost to the liquid, net [kg]
  const double* volume;
  double* porosity;
  const double* grain_density;  // rho_s
  // The part of liquid_mass that carries the suspension (its fines included),
  // may be null: eroded fines join it, deposited ones leave it.
  double* carrying_liquid = nullptr;
};

// The pore liquid of a point as the transport leaves it: a carrying part
// (fines and the water that took them up) and clean water, mixed only where
// the transport has smeared a suspension front over a few cells. In volume:
// `share`, the carrying part's fraction of the pore liquid, and
// `concentration`, the carrying part's own c. Where all the liquid carries
// (share 1) the concentration is suspended_concentration's, bit for bit.
template <class T>
struct CarrierState {
  T share, concentration;
};
template <class T>
[[gnu::always_inline]] inline CarrierState<T> carrier_state(T fines, T carrying, T liquid, T rho_s, T rho_w) {
  const T v_fines = fines / rho_s;
  const T v_carrying = v_fines + lane_max(T{}, carrying - fines) / rho_w;
  const T v_liquid = v_fines + lane_max(T{}, liquid - fines) / rho_w;
  const auto all_carries = carrying >= liquid;
  const T part = pick(v_liquid > T{}, lane_min(splat<T>(1.0), v_carrying / v_liquid), T{});
  return {pick(all_carries, splat<T>(1.0), part),
          suspended_concentration(fines, pick(all_carries, liquid, carrying), rho_s, rho_w)};
}

// Applies the rates n_e [1/s] of a law to the points at p (lane_count<T> of
// them): moves rho_s n_e V dt from skeleton to liquid, limited so that
// f_c >= f_c_inf and no point deposits more fines than it carries.
// Overwrites `rate` with the rate actually applied.
template <class T>
[[gnu::always_inline]] inline void apply_erosion_at(std::size_t p, double dt, const SpeciesPoints& pt,
                                                    const double* ultimate_fines, double* rate) {
  const T rho_s = load_at<T>(pt.grain_density + p), V = load_at<T>(pt.volume + p);
  const T ms = load_at<T>(pt.solid_mass + p), fines = load_at<T>(pt.skeleton_fines + p);
  const T f_inf = load_at<T>(ultimate_fines + p), suspended = load_at<T>(pt.suspended_fines + p);
  const T wanted = rho_s * load_at<T>(rate + p) * V * dt;
  // Eroding: (fines - moved) / (ms - moved) >= f_inf. Depositing: at most
  // the suspended fines.
  const T erodible = lane_max(T{}, (fines - f_inf * ms) / (splat<T>(1.0) - f_inf));
  const T moved = pick(wanted > T{}, lane_min(wanted, erodible), lane_max(wanted, -suspended));
  store_at(pt.solid_mass + p, ms - moved);
  store_at(pt.skeleton_fines + p, fines - moved);
  store_at(pt.suspended_fines + p, suspended + moved);
  store_at(pt.liquid_mass + p, load_at<T>(pt.liquid_mass + p) + moved);
  if (pt.carrying_liquid)
    store_at(pt.carrying_liquid + p, lane_max(T{}, load_at<T>(pt.carrying_liquid + p) + moved));
  store_at(pt.eroded_mass + p, load_at<T>(pt.eroded_mass + p) + moved);
  store_at(pt.porosity + p, load_at<T>(pt.porosity + p) + moved / (rho_s * V));
  store_at(rate + p, moved / (rho_s * V * dt));
}

inline void apply_erosion(std::size_t begin, std::size_t end, double dt, const SpeciesPoints& pt,
                          const double* ultimate_fines, double* rate) {
  for (std::size_t p = begin; p < end; ++p) apply_erosion_at<double>(p, dt, pt, ultimate_fines, rate);
}

// What the erosion law reads at the points (ErosionBatch), beside the
// fields it reads directly.
struct ErosionInputs {
  const double *darcy_flux, *conductivity, *water_density;
  double *flux_magnitude, *hydraulic_gradient, *fines_content, *concentration;
  // The liquid that carries the fines: its share of the pore liquid (by
  // volume) and its own c (carrier_state).
  double *carrier_share, *carrier_concentration;
};

// Fills ErosionInputs at points [begin, end) (pt.carrying_liquid must be
// set: a run with fines tracks it). flux_magnitude, carrier_share and
// carrier_concentration are a block's scratch, not point fields: point p's
// value is at p - begin. Returns whether any of the points holds clean
// water beside the suspension (a carrier share below 1).
template <int D, int L>
[[gnu::always_inline]] inline bool erosion_inputs(std::size_t begin, std::size_t end, const SpeciesPoints& pt,
                                                  const ErosionInputs& in) {
  bool mixed = false;
  for_points_in_lanes<L>(begin, end, [&]<class T>(std::size_t p) {
    T q2{};
    for (int i = 0; i < D; ++i) {
      const T q = load_at<T, D>(in.darcy_flux + p * D + i);
      q2 += q * q;
    }
    const T magnitude = lane_sqrt(q2);
    store_at(in.flux_magnitude + (p - begin), magnitude);
    store_at(in.hydraulic_gradient + p, magnitude / load_at<T>(in.conductivity + p));  // Darcy: q = K i
    store_at(in.fines_content + p, load_at<T>(pt.skeleton_fines + p) / load_at<T>(pt.solid_mass + p));
    const T fines = load_at<T>(pt.suspended_fines + p), liquid = load_at<T>(pt.liquid_mass + p);
    const T rho_s = load_at<T>(pt.grain_density + p), rho_w = load_at<T>(in.water_density + p);
    store_at(in.concentration + p, suspended_concentration(fines, liquid, rho_s, rho_w));
    const CarrierState<T> carrier =
        carrier_state(fines, load_at<T>(pt.carrying_liquid + p), liquid, rho_s, rho_w);
    store_at(in.carrier_share + (p - begin), carrier.share);
    store_at(in.carrier_concentration + (p - begin), carrier.concentration);
    mixed = any_lane(carrier.share < splat<T>(1.0)) || mixed;
  });
  return mixed;
}

// The fields erosion changes beside SpeciesPoints, and the step's
// increments of porosity, fines content and eroded fraction.
struct ErosionState {
  double *fines_content, *eroded_fraction;
  double *porosity_increment, *fines_content_increment, *eroded_fraction_increment;
};

// apply_erosion_at at points [begin, end), then their fines content, eroded
// fraction and increments (the porosity's includes the deformation's share,
// added earlier in the step). Returns whether any point eroded or deposited.
template <int L>
[[gnu::always_inline]] inline bool erode_points(std::size_t begin, std::size_t end, double dt,
                                                const SpeciesPoints& pt, const double* ultimate_fines, double* rate,
                                                const ErosionState& st) {
  bool moved = false;
  for_points_in_lanes<L>(begin, end, [&]<class T>(std::size_t p) {
    const T n0 = load_at<T>(pt.porosity + p), fc0 = load_at<T>(st.fines_content + p);
    const T fer0 = load_at<T>(st.eroded_fraction + p);
    apply_erosion_at<T>(p, dt, pt, ultimate_fines, rate);
    const T solid = load_at<T>(pt.solid_mass + p), eroded = load_at<T>(pt.eroded_mass + p);
    const T fc = load_at<T>(pt.skeleton_fines + p) / solid, fer = eroded / (solid + eroded);
    store_at(st.fines_content + p, fc);
    store_at(st.eroded_fraction + p, fer);
    store_at(st.porosity_increment + p, load_at<T>(st.porosity_increment + p) - n0 + load_at<T>(pt.porosity + p));
    store_at(st.fines_content_increment + p, fc - fc0);
    store_at(st.eroded_fraction_increment + p, fer - fer0);
    moved = any_lane(load_at<T>(rate + p) != T{}) || moved;
  });
  return moved;
}

// Scatter: pore volume, liquid, suspended fines and the liquid carrying
// them, summed per node into one block of species_block values in that
// order (the fines' two are zero where the run tracks none). Each is N times
// the point's amount.
inline constexpr int species_block = 4;

template <int D, int L = 2>
[[gnu::always_inline]] inline void p2g_species(std::size_t begin, std::size_t end, const PointSupports& s,
                 const double* volume, const double* n, const double* liquid, const double* fines,
                 const double* carrying, double* __restrict block) {
  for (std::size_t p = begin; p < end; ++p) {
    if (n[p] <= 0) continue;  // a dry point holds no liquid
    const double a[species_block] = {n[p] * volume[p], liquid[p], fines ? fines[p] : 0.0,
                                     carrying ? carrying[p] : 0.0};
    const WeightedValues<species_block, L> amounts(a);
    for_each_weight<D>(s, p, [&](std::size_t node, double N) { amounts.add_to(block + node * species_block, N); });
  }
}

inline void unpack_species_block(std::size_t begin, std::size_t end, const double* block, double* node_pore,
                                 double* node_liquid, double* node_fines, double* node_carrying) {
  for (std::size_t I = begin; I < end; ++I) {
    const double* b = block + I * species_block;
    node_pore[I] = b[0], node_liquid[I] = b[1];
    if (node_fines) node_fines[I] = b[2], node_carrying[I] = b[3];
  }
}

// The grid the transport runs on: nodal amounts and Darcy fluxes.
struct TransportGrid {
  std::array<int, 3> nodes;   // per axis
  std::array<double, 3> h;    // cell size
  double dt;
  const double* pore;         // sum N n V [m^3]
  const double* liquid;       // sum N m_L [kg]
  const double* fines;        // sum N m_f [kg], may be null
  const double* carrying;     // sum N m_carrying [kg], the liquid carrying the suspension; null if fines is
  const double* darcy;        // D per node: the nodal Darcy flux n_I (v_L - v_s)_I, as the pressure uses it
  double* face;               // D per node: volume crossing the face to I + e_a this step (pass 0 fills it)
  // Per node and axis (node * D + axis): the liquid and fines per volume
  // entering through an open grid face at that node; NaN elsewhere.
  const double* inflow_liquid;
  const double* inflow_fines;
  const double* inflow_carrying;
  // Per node: 1 where still water stands above it this step (a water level,
  // bc/water_level), whose clean water (inflow_water per volume) enters
  // through the node's free-surface faces where the flux points in; null
  // without water levels.
  const char* submerged = nullptr;
  double inflow_water = 0;
};

// What the exchange reads of each node, formed once per node rather than at
// each of its faces (every face was computed from both of its nodes):
// liquid per pore volume (NaN without pores), the fines' and the carrying
// liquid's shares of the liquid, the share of its content the node may send
// (Transport::scale); and per face to I + e_a, 3 per node and axis, the
// liquid, fines and carrying liquid crossing it (face_transfer).
struct NodeShares {
  double *per_pore, *fines_ratio, *carrying_ratio, *send, *flow;
};

template <int D>
struct Transport {
  const TransportGrid& g;

  std::array<int, 3> ijk(std::int64_t I) const {
    std::array<int, 3> c{0, 0, 0};
    c[0] = static_cast<int>(I % g.nodes[0]);
    if (D > 1) c[1] = static_cast<int>((I / g.nodes[0]) % g.nodes[1]);
    if (D > 2) c[2] = static_cast<int>(I / (static_cast<std::int64_t>(g.nodes[0]) * g.nodes[1]));
    return c;
  }
  // body(n, ijk of n) for n in [begin, end): the coordinates counted on
  // from the first node's, without two integer divisions per node.
  template <class Body>
  [[gnu::always_inline]] void for_nodes(std::size_t begin, std::size_t end, const Body& body) const {
    if (begin >= end) return;
    auto c = ijk(static_cast<std::int64_t>(begin));
    for (std::size_t n = begin; n < end; ++n) {
      body(n, std::as_const(c));
      if (++c[0] == g.nodes[0]) {
        c[0] = 0;
        if (++c[1] == g.nodes[1] && D > 2) c[1] = 0, ++c[2];
      }
    }
  }
  std::int64_t stride(int a) const {
    return a == 0 ? 1 : (a == 1 ? g.nodes[0] : static_cast<std::int64_t>(g.nodes[0]) * g.nodes[1]);
  }
  // Area of the dual-cell face normal to axis a at a node (halved at grid edges).
  double face_area(const std::array<int, 3>& c, int a) const { return dual_face_area(g.nodes, g.h, c, a, D); }
  // Darcy flux component a at node I (zero where the node holds no liquid).
  double darcy(std::int64_t I, int a) const { return g.pore[I] > 0 ? g.darcy[I * D + a] : 0.0; }

  // Pass 0: the volume of liquid crossing each face between I and I + e_a in
  // one step, positive towards I + e_a; zero unless both nodes hold liquid.
  void faces(std::size_t begin, std::size_t end) const {
    for_nodes(begin, end, [&](std::size_t n, const std::array<int, 3>& c) {
      const auto I = static_cast<std::int64_t>(n);
      for (int a = 0; a < D; ++a) {
        double vol = 0;
        if (c[a] < g.nodes[a] - 1 && g.pore[I] > 0 && g.pore[I + stride(a)] > 0)
          vol = g.dt * face_area(c, a) * 0.5 * (darcy(I, a) + darcy(I + stride(a), a));
        g.face[n * D + a] = vol;
      }
    });
  }
  double face_volume(std::int64_t I, int a, const std::array<int, 3>&) const { return g.face[I * D + a]; }

  // A free surface is a face between a node with liquid and a grid node
  // without: the weak form leaves p = 0 there (drained), so liquid may leave
  // but none enters. Volume leaving node I through its free-surface faces.
  double free_surface_volume(std::int64_t I, const std::array<int, 3>& c) const {
    if (g.pore[I] <= 0) return 0.0;
    double sum = 0;
    for (int a = 0; a < D; ++a) {
      if (c[a] < g.nodes[a] - 1 && g.pore[I + stride(a)] <= 0)
        sum += std::max(0.0, g.dt * face_area(c, a) * darcy(I, a));
      if (c[a] > 0 && g.pore[I - stride(a)] <= 0) sum += std::max(0.0, -g.dt * face_area(c, a) * darcy(I, a));
    }
    return sum;
  }

  // Volume entering node I through its free-surface faces from still water
  // standing over it (none where no water stands: the drained surface lets
  // liquid out only).
  double submerged_inflow_volume(std::int64_t I, const std::array<int, 3>& c) const {
    if (!g.submerged || !g.submerged[I] || g.pore[I] <= 0) return 0.0;
    double sum = 0;
    for (int a = 0; a < D; ++a) {
      if (c[a] < g.nodes[a] - 1 && g.pore[I + stride(a)] <= 0)
        sum += std::max(0.0, -g.dt * face_area(c, a) * darcy(I, a));
      if (c[a] > 0 && g.pore[I - stride(a)] <= 0) sum += std::max(0.0, g.dt * face_area(c, a) * darcy(I, a));
    }
    return sum;
  }

  // Pass 1: volume leaving each node through its interior and free-surface faces.
  void outflow(std::size_t begin, std::size_t end, double* out) const {
    for_nodes(begin, end, [&](std::size_t I, const std::array<int, 3>& c) {
      double sum = 0;
      for (int a = 0; a < D; ++a) {
        if (c[a] < g.nodes[a] - 1) sum += std::max(0.0, face_volume(static_cast<std::int64_t>(I), a, c));
        if (c[a] > 0) {
          auto below = c;
          --below[a];
          sum += std::max(0.0, -face_volume(static_cast<std::int64_t>(I) - stride(a), a, below));
        }
      }
      // Free-surface outflow takes the node's own mean (first order), not a
      // limited face value of up to four times it: it counts a quarter.
      out[I] = sum + 0.25 * free_surface_volume(static_cast<std::int64_t>(I), c);
    });
  }

  // Share of its content a node may send this step: 1, or less when the
  // outflow would exceed a quarter of its pore volume (see face_transfer;
  // `out` counts what leaves through free surfaces and open faces, at the
  // node's own mean, a quarter).
  double scale(std::int64_t I, const double* out) const {
    return 4 * out[I] > g.pore[I] ? g.pore[I] / (4 * out[I]) : 1.0;
  }

  // MUSCL face value of a per-node quantity: the upwind node's, plus half its
  // van Leer limited slope. Second order where the profile is smooth, upwind
  // at extrema, no new extrema (TVD); at most twice the upwind value.
  // `far` is the value upstream of the upwind node (NaN: none).
  static double limited(double up, double down, double far) {
    if (std::isnan(far)) return up;
    const double s_back = up - far, s_ahead = down - up;
    return s_back * s_ahead > 0 ? up + s_back * s_ahead / (s_back + s_ahead) : up;  // half the harmonic mean
  }

  // Pass 2: per node, what its faces read (NodeShares), once `out` is final.
  void shares(std::size_t begin, std::size_t end, const double* out, const NodeShares& s) const {
    for (std::size_t I = begin; I < end; ++I) {
      s.per_pore[I] = g.pore[I] > 0 ? g.liquid[I] / g.pore[I] : std::numeric_limits<double>::quiet_NaN();
      if (g.fines) s.fines_ratio[I] = ratio(g.fines, I), s.carrying_ratio[I] = ratio(g.carrying, I);
      s.send[I] = scale(static_cast<std::int64_t>(I), out);
    }
  }

  // Pass 3: what crosses each face between a node I and I + e_a.
  void flows(std::size_t begin, std::size_t end, const NodeShares& s) const {
    for_nodes(begin, end, [&](std::size_t n, const std::array<int, 3>& c) {
      for (int a = 0; a < D; ++a)
        if (c[a] < g.nodes[a] - 1) face_transfer(static_cast<std::int64_t>(n), a, c, s, s.flow + (n * D + a) * 3);
    });
  }

  // Liquid and fines crossing the face between I and I + e_a, positive
  // towards I + e_a. The liquid's face value is limited per pore volume;
  // the fines' is the liquid's times the limited fines-to-liquid ratio, so
  // the water crossing is never negative. A node sends at most a quarter of
  // its pore volume per step: with face values at most twice the node's,
  // neither amount can turn negative. The liquid carrying the suspension
  // crosses as the fines do, with its own limited share of the liquid (a
  // tracer: at a suspension front its share and the fines are smeared alike,
  // see carrier_state). flow: liquid, fines, carrying liquid.
  void face_transfer(std::int64_t I, int a, const std::array<int, 3>& c, const NodeShares& s, double* flow) const {
    flow[0] = flow[1] = flow[2] = 0;
    const double vol = face_volume(I, a, c);
    if (vol == 0) return;  // both nodes hold liquid otherwise (faces)
    const bool forward = vol > 0;
    const std::int64_t up = forward ? I : I + stride(a), down = forward ? I + stride(a) : I;
    // Upstream of the upwind node: its neighbour, or at an inlet face what
    // enters there (the boundary node's dual cell is half a cell).
    const int up_index = forward ? c[a] : c[a] + 1;
    const bool has_far = forward ? up_index > 0 : up_index < g.nodes[a] - 1;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    double far_liquid = nan, far_ratio = nan, far_carrying = nan;
    if (has_far) {
      const std::int64_t far = forward ? up - stride(a) : up + stride(a);
      if (g.pore[far] > 0) {
        far_liquid = s.per_pore[far];
        if (g.fines) far_ratio = s.fines_ratio[far], far_carrying = s.carrying_ratio[far];
      }
    } else if (!std::isnan(g.inflow_liquid[up * D + a])) {
      far_liquid = g.inflow_liquid[up * D + a];
      far_ratio = g.inflow_fines[up * D + a] / far_liquid;
      far_carrying = g.inflow_carrying[up * D + a] / far_liquid;
    }
    const double value = limited(s.per_pore[up], s.per_pore[down], far_liquid);
    flow[0] = s.send[up] * vol * value;
    if (g.fines) {
      flow[1] = flow[0] * limited(s.fines_ratio[up], s.fines_ratio[down], far_ratio);
      flow[2] = flow[0] * limited(s.carrying_ratio[up], s.carrying_ratio[down], far_carrying);
    }
  }
  // Share of a node's liquid an amount is (fines, carrying liquid).
  double ratio(const double* amount, std::size_t I) const { return g.liquid[I] > 0 ? amount[I] / g.liquid[I] : 0.0; }

  // Pass 4: net change of liquid, fines and carrying liquid at each node from
  // its interior faces. Also writes what each node loses through free
  // surfaces, and the clean water it takes in through them from still water
  // (free_water_in, written only where g.submerged is given).
  void exchange(std::size_t begin, std::size_t end, const NodeShares& s, double* d_liquid, double* d_fines,
                double* d_carrying, double* free_liquid, double* free_fines, double* free_carrying,
                double* free_water_in = nullptr) const {
    for_nodes(begin, end, [&](std::size_t n, const std::array<int, 3>& c) {
      const auto I = static_cast<std::int64_t>(n);
      double dl = 0, df = 0, dc = 0;
      for (int a = 0; a < D; ++a) {
        if (c[a] < g.nodes[a] - 1) {
          const double* f = s.flow + (n * D + a) * 3;
          dl -= f[0];
          df -= f[1];
          dc -= f[2];
        }
        if (c[a] > 0) {
          const double* f = s.flow + (static_cast<std::size_t>(I - stride(a)) * D + a) * 3;
          dl += f[0];
          df += f[1];
          dc += f[2];
        }
      }
      // Free-surface outflow: what the node sends out of the liquid region.
      const double free = free_surface_volume(I, c);
      if (free > 0) {
        const double share = s.send[n] * free / g.pore[I];
        free_liquid[n] = share * g.liquid[I];
        free_fines[n] = g.fines ? share * g.fines[I] : 0.0;
        free_carrying[n] = g.fines ? share * g.carrying[I] : 0.0;
        dl -= free_liquid[n];
        df -= free_fines[n];
        dc -= free_carrying[n];
      } else {
        free_liquid[n] = free_fines[n] = free_carrying[n] = 0;
      }
      if (g.submerged) {
        free_water_in[n] = g.inflow_water * submerged_inflow_volume(I, c);
        dl += free_water_in[n];
      }
      d_liquid[n] = dl;
      d_fines[n] = df;
      d_carrying[n] = dc;
    });
  }
};

// Gather: each point takes its share of the nodal changes. Losses are shared
// in proportion to what the points hold, gains in proportion to their pore
// volume, so the shares of a node add up to its change exactly.
// First, per node, the change per amount held (losses) and per pore volume
// (gains): one division per node rather than one per point and node. They go
// into one block per node, share_block values: species s's rate per amount
// at s, per pore volume at 4 + s (liquid, fines, carrying liquid; the fourth
// of each stays zero, so that each half fills whole vectors).
inline constexpr int share_block = 8, share_per_pore = 4;

inline void share_rates(std::size_t begin, std::size_t end, int species, const double* node_pore,
                        const double* node_amount, const double* node_change, double* block) {
  for (std::size_t I = begin; I < end; ++I) {
    const double d = node_change[I];
    block[I * share_block + species] = d < 0 && node_amount[I] > 0 ? d / node_amount[I] : 0.0;
    block[I * share_block + share_per_pore + species] = d > 0 ? d / node_pore[I] : 0.0;
  }
}

// Up to three species in one pass over the points' nodes (null: absent).
template <int D, int L = 2>
[[gnu::always_inline]] inline void g2p_share(std::size_t begin, std::size_t end, const PointSupports& s,
               const double* volume, const double* n, const double* block, double* const (&amount)[3]) {
  constexpr int vectors = share_per_pore / L;
  const int count = amount[2] ? 3 : amount[1] ? 2 : 1;
  for (std::size_t p = begin; p < end; ++p) {
    if (n[p] <= 0) continue;
    const double pore = n[p] * volume[p];
    double held[share_per_pore] = {};
    for (int s = 0; s < count; ++s) held[s] = amount[s][p];
    Lanes<L> H[vectors], change[vectors] = {};
    for (int v = 0; v < vectors; ++v) H[v] = lanes_of<L>(held + v * L);
    for_each_weight<D>(s, p, [&](std::size_t node, double N) {
      const double* b = block + node * share_block;
      // One of the two rates is zero: the sum is the other term exactly.
      for (int v = 0; v < vectors; ++v)
        change[v] += N * (H[v] * load_lanes<L>(b + v * L) + pore * load_lanes<L>(b + share_per_pore + v * L));
    });
    for (int s = 0; s < count; ++s) amount[s][p] += change[s / L][s % L];
  }
}

// After the transport: each point's pore liquid, rho_L = c rho_s + (1 - c)
// rho_w (liquid.hpp's suspension_density), and the liquid mass the momentum
// balance moves with the point, the pores full of it: n V rho_L. Not the
// carried mass itself, which near a free surface inside the grid can pile up
// (docs/two-phase.md, known defects). Dry points (n <= 0) keep their values.
struct PoreLiquidPoints {
  const double *volume, *porosity, *grain_density, *water_density;
  const double *suspended_fines, *liquid_mass;  // suspended_fines may be null: clean water
  double *concentration, *density, *moving_mass;  // concentration may be null
};
template <int L>
[[gnu::always_inline]] inline void pore_liquid_density(std::size_t begin, std::size_t end, const PoreLiquidPoints& pt) {
  for_points_in_lanes<L>(begin, end, [&]<class T>(std::size_t p) {
    const T n = load_at<T>(pt.porosity + p);
    const auto dry = n <= T{};
    const T rho_s = load_at<T>(pt.grain_density + p), rho_w = load_at<T>(pt.water_density + p);
    const T c = pt.suspended_fines ? suspended_concentration(load_at<T>(pt.suspended_fines + p),
                                                             load_at<T>(pt.liquid_mass + p), rho_s, rho_w)
                                   : T{};
    if (pt.concentration) store_at(pt.concentration + p, pick(dry, load_at<T>(pt.concentration + p), c));
    const T rho = c * rho_s + (splat<T>(1.0) - c) * rho_w;
    store_at(pt.density + p, pick(dry, load_at<T>(pt.density + p), rho));
    store_at(pt.moving_mass + p, pick(dry, load_at<T>(pt.moving_mass + p), n * load_at<T>(pt.volume + p) * rho));
  });
}

}  // namespace suffuse::detail
