#include "mixture/saturated_mixture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mpm/plugin_batch.hpp"
#include "mpm/solid_kernels.hpp"
#include "mpm/initial_values.hpp"
#include "suffuse/error.hpp"
#include "suffuse/grid_face.hpp"
#include "mixture/drainage.hpp"
#include "mixture/two_phase_kernels.hpp"

namespace suffuse::detail {

std::vector<FieldDeclaration<MixtureFields>> SaturatedMixture::fields_declared() {
  using K = FieldKind;
  using F = MixtureFields;
  return {
      {{coupling::porosity, K::Scalar, "-", "porosity n", true}, &F::porosity},
      {{coupling::porosity_increment, K::Scalar, "-", "change of the porosity over the step", false},
       &F::porosity_increment},
      {{"pore_pressure", K::Scalar, "Pa", "pore pressure p, compression positive", true}, &F::pressure},
      {{"pore_pressure_rate", K::Scalar, "Pa/s", "unsmoothed rate of the pore pressure", false}, &F::pressure_rate},
      {{"liquid_velocity", K::Vector, "m/s", "velocity of the pore liquid", true}, &F::liquid_velocity},
      {{"hydraulic_conductivity", K::Scalar, "m/s", "hydraulic conductivity K", true}, &F::conductivity},
      {{"darcy_flux", K::Vector, "m/s", "Darcy flux q = n (v_L - v_s)", true}, &F::darcy_flux},
      {{"liquid_density", K::Scalar, "kg/m^3", "density of the pore liquid", true}, &F::liquid_density},
      {{"liquid_mass", K::Scalar, "kg", "pore liquid the point carries, transported (per metre in 2D)", true},
       &F::liquid_mass},
      {{"moving_liquid_mass", K::Scalar, "kg", "n rho_L V, the liquid mass of the momentum balance", false},
       &F::moving_liquid_mass},
      {{"liquid_bulk_modulus", K::Scalar, "Pa", "K_L of the pore liquid", false}, &F::bulk_modulus},
      {{"grain_density", K::Scalar, "kg/m^3", "density rho_s of the solid", false}, &F::grain_density},
      {{"water_density", K::Scalar, "kg/m^3", "density rho_w of the clean pore liquid", false}, &F::water_density},
  };
}

FieldInfo SaturatedMixture::saturation_field() {
  return {"saturation", FieldKind::Scalar, "-",
          "degree of saturation S: 1 below the phreatic surface, less above it where the pores drained", true};
}

FieldInfo SaturatedMixture::potential_field() {
  return {"water_potential", FieldKind::Scalar, "Pa",
          "water potential psi: the pore pressure where the pores are full, below zero where they drained "
          "(docs/phreatic.md)",
          true};
}

SaturatedMixture::SaturatedMixture(const Scene& scene, const Registry& registry, Domain& domain,
                                   const std::vector<const Phase*>& phases,
                                   const std::vector<std::unique_ptr<BoundaryCondition>>& conditions)
    : d_(domain), gravity_(scene.gravity), mass_scaling_(scene.mass_scaling), phases_(phases) {
  const int dim = scene.dim;
  for (const LiquidSpec& l : scene.liquids)
    liquids_.push_back(registry.create<Liquid>(l.liquid.type, {l.liquid.params, dim, l.liquid.pointer}));
  for (const MaterialSpec& m : scene.materials) {
    permeability_.push_back(m.permeability ? registry.create<PermeabilityLaw>(
                                                 m.permeability->type,
                                                 {m.permeability->params, dim, m.permeability->pointer})
                                           : nullptr);
    permeability_names_.push_back(m.permeability ? plugin_of_material("permeability law", *m.permeability, m.name)
                                                 : std::string());
    drains_.push_back(m.phreatic ? std::optional<Drainage>(Drainage(*m.phreatic)) : std::nullopt);
  }
  f_ = register_fields(d_.points, fields_declared());
  if (scene.integration == TimeIntegration::quasi_static && scene.failure && scene.failure->collapse)
    close_grid_faces(conditions);
  if (scene.phreatic()) {
    f_.saturation = d_.points.add_field(saturation_field());
    f_.potential = d_.points.add_field(potential_field());
    for (const auto& condition : conditions)
      for (const LiquidOpening& o : condition->liquid_openings())
        for (const std::int64_t I : o.nodes.empty() ? face_nodes(d_.grid, o.face) : o.nodes)
          open_nodes_.push_back({static_cast<std::size_t>(I), o.face.axis,
                                 (o.face.upper ? 1.0 : -1.0) * d_.periodic.face_area(d_.grid, o.face, I)});
  }
  const std::size_t nn = d_.grid.node_count();
  for (auto* v : {&node_drag_, &node_pressure_rate_}) v->assign(nn, 0.0);
  node_darcy_.assign(nn * dim, 0.0);
}

void SaturatedMixture::close_grid_faces(const std::vector<std::unique_ptr<BoundaryCondition>>& conditions) {
  const int dim = d_.dim();
  std::vector<std::vector<bool>> opened(static_cast<std::size_t>(2 * dim));  // per face: which nodes are open
  for (const auto& condition : conditions)
    for (const LiquidOpening& o : condition->liquid_openings()) {
      std::vector<bool>& open = opened[static_cast<std::size_t>(2 * o.face.axis + (o.face.upper ? 1 : 0))];
      open.resize(d_.grid.node_count(), false);
      for (const std::int64_t I : o.nodes.empty() ? face_nodes(d_.grid, o.face) : o.nodes)
        open[static_cast<std::size_t>(I)] = true;
    }
  for (int axis = 0; axis < dim; ++axis)
    for (const bool upper : {false, true}) {
      const std::vector<bool>& open = opened[static_cast<std::size_t>(2 * axis + (upper ? 1 : 0))];
      for (const std::int64_t I : face_nodes(d_.grid, GridFace{axis, upper}))
        if (open.empty() || !open[static_cast<std::size_t>(I)])
          closed_nodes_.push_back({static_cast<std::size_t>(I), axis});
    }
}

void SaturatedMixture::hold_liquid_on_closed_faces(NodeState& nodes) const {
  const auto dim = static_cast<std::size_t>(d_.dim());
  for (const ClosedNode& c : closed_nodes_) {
    const std::size_t k = c.node * dim + static_cast<std::size_t>(c.axis);
    nodes.liquid_velocity[k] = nodes.velocity[k];
  }
}

void SaturatedMixture::initialise(const BodySpec& body, const BodyPoints& b, const InitialValues& initial) {
  if (!body.liquid) return;
  const int dim = d_.dim();
  PointSet& pts = d_.points;
  const Liquid& liquid = *liquids_[*body.liquid];
  const double rho_s = phases_[body.material]->density(), rho_w = liquid.density();
  const double rho_l = suspension_density(body.concentration, rho_s, rho_w);
  const double* V = pts.data(pts.core().volume);
  const double* x = pts.data(pts.core().position);
  const double g = -gravity_[dim - 1];  // along the vertical (last) axis, downward
  const std::optional<Drainage>& drains = drains_[body.material];
  for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
    const double n = initial.porosity(p), pore = n * V[p];
    pts.data(f_.porosity)[p] = n;
    double pressure = initial.pore_pressure(p);
    if (body.water_table) pressure += rho_w * g * std::max(0.0, *body.water_table - x[p * dim + dim - 1]);
    double S = 1;
    if (f_.saturation) {
      // Pores that drain hold, above the water table, what the retention
      // curve gives at the hydrostatic potential there (none of it
      // pressure), and that much of the liquid.
      double psi = pressure;
      if (drains && body.water_table && x[p * dim + dim - 1] > *body.water_table)
        psi = pressure - rho_w * g * (x[p * dim + dim - 1] - *body.water_table);
      const std::optional<double> given = initial.saturation(p);
      if (drains && given) psi = drains->potential(pressure, *given, rho_w);
      S = given.value_or(drains ? drains->saturation(psi, rho_w) : 1.0);
      pts.data(*f_.saturation)[p] = S;
      pts.data(*f_.potential)[p] = psi;
      pressure = std::max(psi, 0.0);
    }
    pts.data(f_.pressure)[p] = pressure;
    pts.data(f_.bulk_modulus)[p] = liquid.bulk_modulus();
    for (int a = 0; a < dim; ++a) pts.data(f_.liquid_velocity)[p * dim + a] = initial.liquid_velocity(p, a);
    pts.data(f_.grain_density)[p] = rho_s;
    pts.data(f_.water_density)[p] = rho_w;
    pts.data(f_.liquid_density)[p] = rho_l;
    pts.data(f_.liquid_mass)[p] = pore * S * rho_l;
    pts.data(f_.moving_liquid_mass)[p] = pore * S * rho_l;
  }
  update_conductivity(b);
}

double SaturatedMixture::stable_time_step(const BodySpec& body, const Phase& phase, double h) const {
  // Mieremet et al. 2016: the undrained wave h / c_u, c_u = sqrt((M + K_L/n)
  // / rho_sat). Not their explicit-drag limit 2 (1-n) rho_s K / (n g rho_sat):
  // the drag turns semi-implicit at nodes where the step exceeds half of it
  // (grid_update_saturated). A body of points whose file gives each its
  // porosity: the smallest step over them.
  const Liquid& liquid = *liquids_[*body.liquid];
  const double rho_s = phase.density();
  const std::vector<double>& given = body.point_values.porosity;
  const std::span<const double> porosities = given.empty() ? std::span(&body.porosity, 1) : std::span(given);
  double dt = std::numeric_limits<double>::infinity();
  for (const double n : porosities) {
    const double rho_sat = (1 - n) * rho_s + n * liquid.density();
    dt = std::min(dt, h / std::sqrt((phase.p_wave_modulus() + liquid.bulk_modulus() / n) / rho_sat));
  }
  return dt;
}

void SaturatedMixture::points_to_grid() {
  NodeState& n = d_.nodes;
  const bool drains = f_.potential.has_value();
  if (drains) prepare_drained_pores();  // (its own scatter, through block_)
  const int W = d_.dim() == 2 ? saturated_block<2> : saturated_block<3>;
  d_.clear_nodal(block_, static_cast<std::size_t>(W));
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const SaturatedPoints pt{pts.data(c.mass),
                           pts.data(c.volume),
                           pts.data(c.velocity),
                           pts.data(c.stress),
                           drains ? wet_porosity_.data() : pts.data(f_.porosity),
                           pts.data(f_.pressure),
                           pts.data(f_.liquid_velocity),
                           pts.data(f_.moving_liquid_mass),
                           drains ? wet_conductivity_.data() : pts.data(f_.conductivity),
                           pts.data(f_.water_density),
                           drains ? suction_force_.data() : nullptr};
  const Interpolation& s = d_.shape;
  ScatterTargets targets = s.targets(d_.grid.node_count());
  targets.add(block_);
  d_.exec.scatter(pts.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      if (drains)
        p2g_saturated<D, L, true>(b, e, s.view(), pt, gravity_.data(), mass_scaling_, out[0]);
      else
        p2g_saturated<D, L>(b, e, s.view(), pt, gravity_.data(), mass_scaling_, out[0]);
    });
  });
  const SaturatedNodes nodes{n.mass.data(),         n.momentum.data(),     n.force.data(),
                             n.liquid_mass.data(),  n.liquid_momentum.data(), n.liquid_force.data(),
                             n.liquid_inertia.data(), node_drag_.data()};
  auto unpack = d_.dim() == 2 ? &unpack_saturated_block<2> : &unpack_saturated_block<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) { unpack(b, e, block_.data(), nodes); });
  if (drains) add_suction_on_openings(n.liquid_force.data());
}

void SaturatedMixture::integrate_grid(double dt, double damping) {
  NodeState& n = d_.nodes;
  auto update = d_.dim() == 2 ? &grid_update_saturated<2> : &grid_update_saturated<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    update(b, e, dt, damping, n.mass.data(), n.momentum.data(), n.force.data(), n.liquid_mass.data(),
           n.liquid_momentum.data(), n.liquid_force.data(), n.liquid_inertia.data(), node_drag_.data(),
           n.velocity.data(), n.liquid_velocity.data());
  });
  free_velocity_ = n.velocity;
  free_liquid_velocity_ = n.liquid_velocity;
}

void SaturatedMixture::drag_against_held_solid(NodeState& n, double dt) const {
  auto redrag = d_.dim() == 2 ? &drag_against_held_solid_kernel<2> : &drag_against_held_solid_kernel<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    redrag(b, e, dt, n.mass.data(), n.liquid_mass.data(), n.liquid_momentum.data(), n.liquid_force.data(),
           n.liquid_inertia.data(), node_drag_.data(), free_velocity_.data(), free_liquid_velocity_.data(),
           n.velocity.data(), n.liquid_velocity.data());
  });
}

void SaturatedMixture::accelerations(double dt) {
  NodeState& n = d_.nodes;
  auto acc = d_.dim() == 2 ? &acceleration_kernel<2> : &acceleration_kernel<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    acc(b, e, dt, n.mass.data(), n.momentum.data(), n.velocity.data(), n.acceleration.data());
    acc(b, e, dt, n.liquid_mass.data(), n.liquid_momentum.data(), n.liquid_velocity.data(),
        n.liquid_acceleration.data());
  });
}

void SaturatedMixture::grid_to_points(double dt) {
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const Interpolation& s = d_.shape;
  d_.exec.for_chunks(pts.size(), [&](int, std::size_t b, std::size_t e) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      g2p_kernel<D, true, L>(b, e, dt, s.view(), d_.nodes.velocity.data(),
                             d_.nodes.acceleration.data(), pts.data(c.position), pts.data(c.displacement),
                             pts.data(c.velocity), d_.nodes.liquid_acceleration.data(),
                             pts.data(f_.liquid_velocity));
    });
  });
}

void SaturatedMixture::remap() {
  NodeState& n = d_.nodes;
  const std::size_t dim = d_.dim();
  d_.clear_nodal(block_, 2 * dim);
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const Interpolation& s = d_.shape;
  ScatterTargets targets = s.targets(d_.grid.node_count());
  targets.add(block_);
  d_.exec.scatter(pts.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      remap_two_phase<D, L>(b, e, s.view(), pts.data(c.mass),
                            pts.data(f_.moving_liquid_mass), mass_scaling_, pts.data(c.velocity),
                            pts.data(f_.liquid_velocity), out[0]);
    });
  });
  auto unpack = dim == 2 ? &unpack_remap_block<2> : &unpack_remap_block<3>;
  auto velocity = dim == 2 ? &velocity_from_momentum<2> : &velocity_from_momentum<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    unpack(b, e, block_.data(), n.momentum.data(), n.liquid_momentum.data());
    velocity(b, e, n.mass.data(), n.momentum.data(), n.velocity.data());
    velocity(b, e, n.liquid_mass.data(), n.liquid_momentum.data(), n.liquid_velocity.data());
  });
}

void SaturatedMixture::update_pore_pressure(double dt, std::size_t step, double time) {
  const NodeState& n = d_.nodes;
  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const Interpolation& s = d_.shape;
  const std::size_t dim = d_.dim();
  // The nodal Darcy flux q_I = n_I (v_L - v_s)_I, n_I = sum N n rho_L V / sum N rho_L V:
  // one field for the pressure rate (div q) and the transport.
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    for (std::size_t I = b; I < e; ++I) {
      const double inertia = n.liquid_inertia[I];
      const double nI = inertia > 0 ? n.liquid_mass[I] / inertia : 0.0;
      for (std::size_t i = 0; i < dim; ++i)
        node_darcy_[I * dim + i] = nI * (n.liquid_velocity[I * dim + i] - n.velocity[I * dim + i]);
    }
  });
  if (f_.potential) close_free_surfaces();
  const PorousPoints porous{pts.data(c.velocity_gradient), pts.data(f_.bulk_modulus),
                            pts.data(c.velocity),          pts.data(f_.liquid_velocity),
                            pts.data(f_.porosity),         pts.data(f_.porosity_increment),
                            pts.data(f_.pressure_rate),    pts.data(f_.darcy_flux),
                            f_.saturation ? pts.data(*f_.saturation) : nullptr};
  d_.exec.for_chunks(pts.size(), [&](int, std::size_t b, std::size_t e) {
    std::size_t bad = e;
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      bad = porous_update<D, L>(b, e, dt, s.view(), node_darcy_.data(), porous);
    });
    if (bad != e)
      throw Error(d_.point_name(bad) + " was compressed to porosity " +
                  std::to_string(pts.data(f_.porosity)[bad]) + " at step " + std::to_string(step) + " (t = " +
                  std::to_string(time) + " s): its grains cannot be compressed; reduce the time step or check the loads");
  });
  // Pressure smoothing: the pore-pressure rate is averaged over the nodes and
  // interpolated back. Raw point rates carry the checkerboard modes of a
  // nearly incompressible mixture on linear cells (as in Anura3D). Where
  // pores drain, the potential's rate, from the water each point gained.
  if (f_.potential) {
    update_potential(dt);
    return;
  }
  d_.clear_nodal(block_, 2);
  ScatterTargets targets = s.targets(d_.grid.node_count());
  targets.add(block_);
  d_.exec.scatter(pts.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      p2g_pressure_rate<D, L>(b, e, s.view(), pts.data(c.volume), pts.data(f_.porosity),
                           pts.data(f_.pressure_rate), out[0]);
    });
  });
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    nodal_pressure_rate(b, e, block_.data(), node_pressure_rate_.data());
  });
  auto gather = d_.dim() == 2 ? &g2p_pressure<2> : &g2p_pressure<3>;
  d_.exec.for_chunks(pts.size(), [&](int, std::size_t b, std::size_t e) {
    gather(b, e, dt, s.view(), node_pressure_rate_.data(), pts.data(f_.porosity), pts.data(f_.pressure));
  });
}

void SaturatedMixture::update_conductivity(const BodyPoints& b) {
  const PermeabilityLaw& law = *permeability_[b.material];
  PointSet& pts = d_.points;
  d_.exec.for_chunks(b.range.size(), [&](int, std::size_t lo, std::size_t hi) {
    const PointRange batch{b.range.begin + lo, b.range.begin + hi};
    run_plugin_on_batch(d_, b, batch, permeability_names_[b.material], [&] {
      law.conductivity(pts.values(f_.porosity).subspan(batch.begin, batch.size()),
                       pts.values(f_.conductivity).subspan(batch.begin, batch.size()));
    });
  });
}

void SaturatedMixture::update_permeability() {
  for (const BodyPoints& b : d_.bodies)
    if (b.saturated) update_conductivity(b);
}

}  // namespace suffuse::detail
