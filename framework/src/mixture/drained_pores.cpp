// The explicit step's pores that drain above the phreatic surface
// (drained_pores.hpp; docs/phreatic.md, Explicit runs).
#include "mixture/drained_pores.hpp"

#include "mixture/saturated_mixture.hpp"
#include "mixture/standing_water.hpp"
#include "mixture/two_phase_kernels.hpp"

namespace suffuse::detail {

void SaturatedMixture::prepare_drained_pores() {
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const std::size_t np = pts.size(), dim = static_cast<std::size_t>(d_.dim());
  const double* n = pts.data(f_.porosity);
  const double* S = pts.data(*f_.saturation);
  const double* K = pts.data(f_.conductivity);
  const double* material = pts.data(c.material_id);
  wet_porosity_.resize(np);
  wet_conductivity_.resize(np);
  suction_force_.resize(np * dim);
  d_.exec.for_chunks(np, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      const std::optional<Drainage>& d = drains_[static_cast<std::size_t>(material[p])];
      wet_porosity_[p] = d ? n[p] * S[p] : n[p];
      wet_conductivity_[p] = d ? K[p] * d->relative_conductivity(S[p]) : K[p];
    }
  });
  // The suction projected onto the nodes, and its gradient at the points.
  const Interpolation& s = d_.shape;
  const double* V = pts.data(c.volume);
  const double* psi = pts.data(*f_.potential);
  d_.clear_nodal(block_, 2);
  ScatterTargets targets = s.targets(d_.grid.node_count());
  targets.add(block_);
  d_.exec.scatter(np, targets, [&](std::size_t b, std::size_t e, double* const* out) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() { p2g_suction<D, L>(b, e, s.view(), V, n, psi, out[0]); });
  });
  node_suction_.resize(d_.grid.node_count());
  d_.for_nodes([&](int, std::size_t b, std::size_t e) { nodal_suction(b, e, block_.data(), node_suction_.data()); });
  auto gather = dim == 2 ? &suction_force<2> : &suction_force<3>;
  d_.exec.for_chunks(np, [&](int, std::size_t b, std::size_t e) {
    gather(b, e, s.view(), V, n, node_suction_.data(), suction_force_.data());
  });
}

void SaturatedMixture::add_suction_on_openings(double* liquid_force) const {
  // The suction's force is -integral of N grad psi-, which leaves out the
  // boundary term integral of N psi- n: on a free surface no water is drawn
  // in. Where a face is open to the liquid, psi- is zero on it: the term
  // is added back, psi-_I n A_I at its nodes, so that a drain holds the
  // water above it by suction instead of letting it fall through.
  const std::size_t dim = static_cast<std::size_t>(d_.dim());
  const ScatterRange r = d_.node_range();
  for (const OpenNode& o : open_nodes_)
    if (o.node >= r.first && o.node < r.last)
      liquid_force[o.node * dim + static_cast<std::size_t>(o.axis)] += node_suction_[o.node] * o.outward_area;
}

void SaturatedMixture::close_free_surfaces() {
  const NodeState& n = d_.nodes;
  const int dim = d_.dim();
  const std::array<int, 3>& nodes = d_.grid.nodes_per_axis();
  const std::int64_t stride[3] = {1, nodes[0], static_cast<std::int64_t>(nodes[0]) * nodes[1]};
  const std::optional<WaterProfile> water = water_ ? std::optional(water_->current()) : std::nullopt;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    for (std::size_t I = b; I < e; ++I) {
      if (!(n.liquid_inertia[I] > 0)) continue;
      const auto i = static_cast<std::int64_t>(I);
      bool submerged = false;  // still water stands above it
      if (water) {
        const auto x = d_.grid.node_position(i);
        submerged = x[static_cast<std::size_t>(dim - 1)] < water->level(x[0]).first;
      }
      const std::array<int, 3> c = d_.grid.node_ijk(i);
      const bool drained = node_suction_[I] < 0;  // water leaves a surface only where its pores are full
      for (int a = 0; a < dim; ++a) {
        double& q = node_darcy_[I * static_cast<std::size_t>(dim) + static_cast<std::size_t>(a)];
        const bool empty_below = c[a] > 0 && !(n.liquid_inertia[static_cast<std::size_t>(i - stride[a])] > 0);
        const bool empty_above = c[a] < nodes[a] - 1 && !(n.liquid_inertia[static_cast<std::size_t>(i + stride[a])] > 0);
        const bool in = (q > 0 && empty_below) || (q < 0 && empty_above);
        const bool out = (q < 0 && empty_below) || (q > 0 && empty_above);
        if ((in && !submerged) || (out && drained)) q = 0;
      }
    }
  });
}

void SaturatedMixture::update_potential(double dt) {
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const std::size_t np = pts.size();
  const DrainedPoints drained{pts.data(f_.porosity),       pts.data(f_.bulk_modulus),  pts.data(f_.water_density),
                              pts.data(f_.liquid_density), pts.data(c.volume),         pts.data(c.material_id),
                              pts.data(f_.pressure_rate),  pts.data(*f_.potential),    pts.data(f_.pressure),
                              pts.data(*f_.saturation),    pts.data(f_.moving_liquid_mass)};
  d_.exec.for_chunks(np, [&](int, std::size_t b, std::size_t e) { potential_rate(b, e, dt, drains_.data(), drained); });
  // The rates are smoothed among the points whose pores are full and,
  // apart, among those that drain (drained_pores.hpp, g2p_potential).
  full_porosity_.resize(np);
  draining_porosity_.resize(np);
  d_.exec.for_chunks(np, [&](int, std::size_t b, std::size_t e) {
    split_by_drainage(b, e, drains_.data(), drained, full_porosity_.data(), draining_porosity_.data());
  });
  node_draining_rate_.resize(d_.grid.node_count());
  const Interpolation& s = d_.shape;
  // (Named pointers, not a structured binding: clang 14 lets no lambda capture one.)
  for (const auto& pass : {std::pair{&full_porosity_, &node_pressure_rate_},
                           std::pair{&draining_porosity_, &node_draining_rate_}}) {
    const double* porosity = pass.first->data();
    double* node_rate = pass.second->data();
    d_.clear_nodal(block_, 2);
    ScatterTargets targets = s.targets(d_.grid.node_count());
    targets.add(block_);
    d_.exec.scatter(np, targets, [&](std::size_t b, std::size_t e, double* const* out) {
      d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
        p2g_pressure_rate<D, L>(b, e, s.view(), pts.data(c.volume), porosity, drained.rate, out[0]);
      });
    });
    d_.for_nodes([&](int, std::size_t b, std::size_t e) { nodal_pressure_rate(b, e, block_.data(), node_rate); });
  }
  using Drains = std::optional<Drainage>;
  auto gather = d_.dim() == 2 ? &g2p_potential<2, Drains> : &g2p_potential<3, Drains>;
  d_.exec.for_chunks(np, [&](int, std::size_t b, std::size_t e) {
    gather(b, e, dt, s.view(), node_pressure_rate_.data(), node_draining_rate_.data(), drains_.data(), drained);
  });
}

}  // namespace suffuse::detail
