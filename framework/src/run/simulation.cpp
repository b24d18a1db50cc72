#include "suffuse/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "parallel/distributed_system.hpp"
#include "mpm/domain.hpp"
#include "mpm/dry_momentum.hpp"
#include "mpm/geostatic_stress.hpp"
#include "mpm/initial_values.hpp"
#include "io/grid_projection.hpp"
#include "run/memory_estimate.hpp"
#include "mpm/point_order.hpp"
#include "scene/scene_reader.hpp"
#include "run/named_condition.hpp"
#include "run/step_guard.hpp"
#include "mpm/materials.hpp"
#include "mixture/drainage.hpp"
#include "mixture/standing_water.hpp"
#include "quasi_static/quasi_static.hpp"
#include "quasi_static/strength_reduction.hpp"
#include "mpm/reactions.hpp"
#include "mixture/saturated_mixture.hpp"
#include "transport/species_transport.hpp"
#include "common/stage_timer.hpp"
#include "suffuse/error.hpp"
#include "suffuse/liquid.hpp"

namespace suffuse {

const char* stage_name(Stage stage) {
  static const char* names[stage_count] = {"shape",     "p2g",   "grid",   "g2p",          "remap",
                                           "strain",    "pore_pressure",   "erosion", "permeability",
                                           "stress",    "transport",       "check",   "output", "solve",
                                           "safety"};
  return names[static_cast<std::size_t>(stage)];
}

void SimulationClock::run_until(double end) {
  // Times are counted from an origin while they stay on its multiples (so a
  // restarted run steps exactly as the run it continues); after a shortened
  // step they are counted from the time reached.
  if (time_ != origin_ + static_cast<double>(since_origin_) * nominal_) {
    origin_ = time_;
    since_origin_ = 0;
  }
  end_ = end;
  dt_ = std::min(nominal_, end_ - time_);
}

void SimulationClock::restore(const State& s) {
  nominal_ = s.nominal;
  time_ = s.time;
  origin_ = s.origin;
  steps_ = s.steps;
  since_origin_ = s.since_origin;
  dt_ = std::min(nominal_, end_ - time_);
}

void SimulationClock::set_step(double dt) {
  nominal_ = dt;
  origin_ = time_;
  since_origin_ = 0;
  dt_ = std::min(nominal_, end_ - time_);
}

void SimulationClock::advance() {
  ++steps_;
  ++since_origin_;
  time_ = std::min(end_, origin_ + static_cast<double>(since_origin_) * nominal_);
  if (time_ >= end_ - eps()) time_ = end_;
  dt_ = std::min(nominal_, end_ - time_);
}

Simulation::Simulation(const Scene& scene, const Registry& registry, int threads)
    : scene_((detail::check_memory(scene), scene)),  // before anything is allocated
      domain_(std::make_unique<detail::Domain>(scene, registry, threads)),
      materials_(std::make_unique<detail::Materials>(scene, registry)),
      reactions_(std::make_unique<detail::Reactions>(scene.reactions, scene.dim)) {
  const int dim = scene.dim;
  if (scene.factor_of_safety && !materials_->reduces_strength())
    throw Error("/factor_of_safety: no material's phase reduces its strength, so no factor of safety exists "
                "(phase/mohr_coulomb does, and phase/suffosion around it)");
  for (const PluginNode& bc : scene.boundary_conditions) {
    bcs_.push_back(std::make_unique<detail::NamedCondition>(
        registry.create<BoundaryCondition>(bc.type, {bc.params, dim, bc.pointer}), bc));
    bcs_.back()->setup(domain_->grid);
  }
  refuse_what_one_process_only_runs();
  // Every part registers its point fields before the phases look theirs up.
  if (scene.saturated()) {
    mixture_ = std::make_unique<detail::SaturatedMixture>(scene, registry, *domain_, materials_->phases(), bcs_);
    species_ = std::make_unique<detail::SpeciesTransport>(scene, registry, *domain_, *mixture_, bcs_);
    momentum_ = mixture_.get();
  }
  refuse_or_keep_standing_water();
  if (!scene.saturated()) {
    dry_ = std::make_unique<detail::DryMomentum>(*domain_, scene.gravity, scene.mass_scaling);
    momentum_ = dry_.get();
  }
  materials_->add_fields(domain_->points);
  if (scene.factor_of_safety)
    safety_shear_strain_ = domain_->points.add_field(
        {"safety_shear_strain", FieldKind::Scalar, "-",
         "the mechanism of the last factor of safety: the equivalent shear strain sqrt(2/3 e:e) the strength "
         "reduction added up to the largest factor that held",
         true});
  add_collapse_fields();
  point_order_ = std::make_unique<detail::PointOrder>(scene.sort_points_at_spread);
  for (const OutputSpec& out : scene.outputs)
    writers_.push_back(registry.create<Writer>(out.writer.type, {out.writer.params, dim, out.writer.pointer}));
  std::optional<detail::StepGuard::MixtureIds> mixture_ids;
  if (mixture_) mixture_ids = {mixture_->fields().porosity, mixture_->fields().pressure, mixture_->fields().darcy_flux};
  guard_ = std::make_unique<detail::StepGuard>(scene_, mixture_ids);
  grid_projection_ = std::make_unique<detail::GridProjection>(
      mixture_ ? &mixture_->fields() : nullptr, mixture_ ? &mixture_->nodal_darcy_flux() : nullptr);
  create_bodies();
  point_order_->number_points(domain_->points);
  // Every point still on every process: conditions that load points keep
  // the serial run's point numbers.
  for (const auto& bc : bcs_) bc->setup_points(domain_->grid, domain_->points);
  // The points whose fields the loads read on many processes (apply_loads).
  for (const auto& bc : bcs_) {
    if (!bc->loads_points()) continue;
    const std::vector<std::size_t> loaded = bc->loaded_points();
    load_every_point_ = load_every_point_ || loaded.empty();
    loaded_points_.insert(loaded_points_.end(), loaded.begin(), loaded.end());
  }
  std::sort(loaded_points_.begin(), loaded_points_.end());
  loaded_points_.erase(std::unique(loaded_points_.begin(), loaded_points_.end()), loaded_points_.end());
  if (!loaded_points_.empty() && loaded_points_.back() >= domain_->points.size())
    throw Error("a boundary condition names point " + std::to_string(loaded_points_.back()) + " among those it loads, of " +
                std::to_string(domain_->points.size()));
  // Sorting the points renumbers them: a condition that loads points and
  // does not follow is refused now, before anything is written.
  for (std::size_t b = 0; b < bcs_.size(); ++b) {
    loaded_ids_.push_back(bcs_[b]->loads_points() ? bcs_[b]->loaded_points() : std::vector<std::size_t>{});
    if (scene.sort_points_at_spread > 0 && bcs_[b]->loads_points() && !bcs_[b]->follows_renumbering())
      throw Error(scene.boundary_conditions[b].pointer + " (" + scene.boundary_conditions[b].type +
                  "): it loads material points and does not follow when they are sorted again into the grid's "
                  "order (BoundaryCondition::follows_renumbering); set /sort_points_at_spread to 0");
  }
  domain_->distribute_points();  // on many processes: each keeps its share
  // On many processes, the node layers beyond its points' that each process
  // updates: what the transport's stencils read within a step (twice as far
  // in the quasi-static substeps: Heun's second stage reads the first's
  // results), and one layer for the outputs' projection (the points moved
  // since the step's shape functions, by less than a cell).
  const bool quasi_static = scene.integration == TimeIntegration::quasi_static;
  const int transport_layers = (quasi_static ? 2 : 1) * detail::SpeciesTransport::halo_layers;
  domain_->set_halo_layers(std::max(1, species_ ? transport_layers : 0));
  if (species_) species_->start_ledger();
  if (quasi_static) {
    quasi_static_ = std::make_unique<detail::QuasiStatic>(scene_, *domain_, *materials_, mixture_.get(), bcs_,
                                                         [this](NodeState& n, double t) { apply_loads(n, t); });
    quasi_static_->set_standing_water(water_.get());
    clock_ = SimulationClock(*scene.dt);  // validation requires it
    if (scene.failure && scene.failure->collapse) check_collapse_steps();
    return;
  }
  clock_ = SimulationClock(scene.dt ? *scene.dt : critical_time_step());
  check_time_step();
}

// Scenes that validate but cannot run: a fixed step above the stable one
// blows up within a few steps; a step so small that the run would not end
// in a lifetime (a modulus of 1e300, dt = 1e-12) is refused with its count.
void Simulation::check_time_step() const {
  const double stable = critical_time_step() / scene_.cfl;
  if (scene_.dt && *scene_.dt > stable * (1 + 1e-12) && !scene_.dt_above_stable)
    throw Error("/time/dt = " + detail::format(*scene_.dt) + " s is above this scene's stable time step, " +
                detail::format(stable) + " s (cell size over the fastest wave speed" +
                (saturated() ? ", the undrained wave in saturated bodies" : "") +
                "): the run would blow up; remove /time/dt for the automatic step (or, if nothing moves, set "
                "/time/dt_above_stable)");
  const double steps = scene_.end_time / clock_.nominal_dt();
  if (steps > max_steps)
    throw Error("the run would take " + detail::format(steps) + " steps of " + detail::format(clock_.nominal_dt()) +
                " s to reach /time/end = " + detail::format(scene_.end_time) + " s (at most " +
                detail::format(max_steps) +
                "): check the moduli and /time/dt, or use /time/mass_scaling for a quasi-static run");
}

Simulation::~Simulation() = default;

// Runs on many processes cover the explicit scheme and the conditions on
// the grid (docs/parallel.md); the rest is refused before any point is made.
void Simulation::refuse_what_one_process_only_runs() const {
  const detail::Communicator& comm = domain_->comm;
  if (!comm.parallel()) return;
  const std::string processes = " on " + std::to_string(comm.size()) + " processes: ";
  if (scene_.integration == TimeIntegration::quasi_static && !detail::built_with_petsc())
    throw Error("/time/integration \"quasi_static\" runs on many processes through PETSc, which this build lacks, "
                "not" + processes + "install libpetsc-real-dev and rebuild, or run it without mpirun (docs/parallel.md)");
  const bool explicit_steps = scene_.integration == TimeIntegration::explicit_dynamics ||
                              (scene_.failure && scene_.failure->collapse);
  if (domain_->periodic.along(scene_.dim - 1) && explicit_steps)
    throw Error("/grid/periodic: explicit steps wrap along the last axis on one process only, not" + processes +
                "the processes' slabs are cut along it (docs/parallel.md); run it without mpirun");
}

std::size_t Simulation::point_count() const { return domain_->total_points(); }
int Simulation::processes() const { return domain_->comm.size(); }
int Simulation::process_rank() const { return domain_->comm.rank(); }

void Simulation::create_bodies() {
  const std::vector<double> weights = unit_weights();
  const double g = -scene_.gravity[scene_.dim - 1];  // along the vertical (last) axis, downward
  // A body's weight between two heights: its unit weight, less the liquid
  // its pores do not hold where they drain above its water table (the water
  // at rest there: docs/phreatic.md), as the quasi-static step weighs it.
  const detail::WeightBetween weight = [&](std::size_t k, double lo, double hi) {
    const BodySpec& body = scene_.bodies[k];
    double w = weights[k] * (hi - lo);
    const std::optional<DrainageSpec>& drains = scene_.materials[body.material].phreatic;
    if (body.liquid && drains && body.water_table) {
      // Above the table psi = p_0 - rho_w g (y - wt) (p_0 the body's pore
      // pressure key), zero at y0, as the mixture sets S (initialise).
      const double wt = *body.water_table, from = std::max(lo, wt), to = std::max(hi, wt);
      const double rho_w = mixture_->liquid(*body.liquid).density();
      const double y0 = g > 0 ? wt + body.pore_pressure / (rho_w * g) : wt;
      const double rho_l = suspension_density(body.concentration, materials_->phase(body.material).density(), rho_w);
      w -= body.porosity * rho_l * g * ((to - from) - detail::Drainage(*drains).saturated_height(from, to, y0, g));
    }
    return w;
  };
  for (std::size_t i = 0; i < scene_.bodies.size(); ++i) {
    const BodySpec& body = scene_.bodies[i];
    const Phase& phase = materials_->phase(body.material);
    std::vector<std::size_t> file_rows;
    const detail::BodyPoints b =
        domain_->create_body(body, phase.density(), std::span(scene_.bodies).first(i), file_rows);
    const detail::InitialValues initial(body, b, file_rows, scene_.dim);
    if (b.range.begin == b.range.end)
      throw Error("/bodies/" + std::to_string(i) + " ('" + body.name +
                  "'): no material point: the body lies within earlier bodies (a later body fills only what earlier "
                  "ones left) or is thinner than a point's spacing, grid cell / points_per_cell (docs/geometry.md)");
    if (mixture_) mixture_->initialise(body, b, initial);
    if (species_) species_->initialise(body, b, initial);
    const double rho_w = body.liquid ? mixture_->liquid(*body.liquid).density() : 0.0;
    detail::add_geostatic_stress(scene_, weight, i, rho_w, g, domain_->points, b.range);
    phase.initialise(domain_->points, b.range);
  }
}

// Each body's total unit weight: its grains, and the liquid (with the fines
// it carries) filling its pores if saturated.
std::vector<double> Simulation::unit_weights() const {
  const double g = -scene_.gravity[scene_.dim - 1];
  std::vector<double> weights;
  for (const BodySpec& body : scene_.bodies) {
    const double rho_s = materials_->phase(body.material).density();
    double rho = rho_s;
    if (body.liquid) {
      const double rho_l = suspension_density(body.concentration, rho_s, mixture_->liquid(*body.liquid).density());
      rho = (1 - body.porosity) * rho_s + body.porosity * rho_l;
    }
    weights.push_back(rho * g);
  }
  return weights;
}

double Simulation::critical_time_step() const {
  // Dry bodies: h / sqrt(M / rho); saturated bodies: the mixture's limits.
  const double h = domain_->grid.min_cell_size();
  double dt = std::numeric_limits<double>::infinity();
  for (const BodySpec& body : scene_.bodies) {
    const Phase& phase = materials_->phase(body.material);
    dt = std::min(dt, body.liquid ? mixture_->stable_time_step(body, phase, h)
                                  : h / std::sqrt(phase.p_wave_modulus() / phase.density()));
  }
  dt = domain_->comm.min(dt);
  if (!(dt > 0) || !std::isfinite(dt))
    throw Error("cannot choose a time step automatically: no material has a positive wave speed; set /time/dt");
  // Mass scaling multiplies every inertia by f: waves slow down by sqrt(f).
  return scene_.cfl * dt * std::sqrt(scene_.mass_scaling);
}

template <class Work>
void Simulation::timed(Stage stage, Work&& work) {
  detail::StageTimer timer(times_, stage);
  try {
    work();
  } catch (const std::exception& e) {
    // What failed (a plugin, a guard) says what and where; this says when.
    const std::string what = e.what();
    if (what.rfind("step ", 0) == 0 || what.find("blew up at step") != std::string::npos ||
        what.find("left the grid at step") != std::string::npos)
      throw;
    throw Error("step " + std::to_string(clock_.steps() + 1) + " (t = " + detail::format(clock_.time()) +
                " s), stage " + stage_name(stage) + ": " + what);
  }
}

// Water levels (bc/water_level) press on saturated bodies in explicit runs.
void Simulation::refuse_or_keep_standing_water() {
  std::vector<const BoundaryCondition*> conditions;
  std::vector<std::string> names;
  for (std::size_t b = 0; b < bcs_.size(); ++b) {
    conditions.push_back(bcs_[b].get());
    names.push_back(scene_.boundary_conditions[b].pointer + " (" + scene_.boundary_conditions[b].type + ")");
  }
  auto water = std::make_unique<detail::StandingWaterLoad>(conditions, names);
  if (!water->any()) return;
  const std::string& first = names[static_cast<std::size_t>(
      std::find_if(conditions.begin(), conditions.end(), [](const BoundaryCondition* c) { return c->standing_water(0.0).has_value(); }) -
      conditions.begin())];
  if (!scene_.saturated())
    throw Error(first + ": a water level presses on saturated bodies and feeds their pores; expected a body with "
                "\"liquid\", found dry bodies only");
  water_ = std::move(water);
  species_->set_standing_water(water_.get());
  mixture_->set_standing_water(water_.get());
}

void Simulation::points_renumbered() {
  renumber_loaded_points();
  // The writers, on the process that writes: every point's new number.
  detail::Domain& d = *domain_;
  const std::vector<std::size_t>& renumbered = point_order_->new_numbers();  // this process's points
  std::vector<double> mine(renumbered.begin(), renumbered.end()), all;
  d.comm.gather_to_root(mine, d.comm.all_counts(mine.size()), all);
  if (!d.comm.root()) return;
  const std::vector<std::size_t> new_number(all.begin(), all.end());
  for (const auto& w : writers_) w->points_renumbered(new_number);
}

void Simulation::renumber_loaded_points() {
  std::vector<std::size_t> ids;  // every point a condition loads, by id
  for (const auto& named : loaded_ids_) ids.insert(ids.end(), named.begin(), named.end());
  if (ids.empty() || !point_order_->id_field()) return;
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  // Each process finds those among its points; every process gets all.
  detail::Domain& d = *domain_;
  const double* id = d.points.data(*point_order_->id_field());
  std::vector<double> mine, all;
  for (std::size_t q = 0; q < d.points.size(); ++q)
    if (std::binary_search(ids.begin(), ids.end(), static_cast<std::size_t>(id[q]))) {
      mine.push_back(id[q]);
      mine.push_back(static_cast<double>(d.first_point() + q));
    }
  d.comm.all_gather(mine, d.comm.all_counts(mine.size()), all);
  std::vector<std::size_t> now(ids.size());
  for (std::size_t k = 0; k + 1 < all.size(); k += 2)
    now[static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), static_cast<std::size_t>(all[k])) -
                                 ids.begin())] = static_cast<std::size_t>(all[k + 1]);
  loaded_points_.clear();
  for (std::size_t b = 0; b < bcs_.size(); ++b) {
    if (loaded_ids_[b].empty()) continue;
    std::vector<std::size_t> numbers(loaded_ids_[b].size());
    for (std::size_t k = 0; k < numbers.size(); ++k)
      numbers[k] = now[static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), loaded_ids_[b][k]) -
                                                ids.begin())];
    bcs_[b]->renumber_loaded_points(numbers);
    loaded_points_.insert(loaded_points_.end(), numbers.begin(), numbers.end());
  }
  std::sort(loaded_points_.begin(), loaded_points_.end());
  loaded_points_.erase(std::unique(loaded_points_.begin(), loaded_points_.end()), loaded_points_.end());
}

std::size_t Simulation::point_sorts() const { return point_order_->sorts(); }

void Simulation::constrain_velocity(double time) {
  for (const auto& bc : bcs_) bc->constrain_velocity(domain_->grid, domain_->nodes, time);
  if (mixture_) mixture_->hold_liquid_on_closed_faces(domain_->nodes);  // a collapse's, as its quasi-static run's
  domain_->periodic.copy_to_images(domain_->nodes.velocity, scene_.dim);  // (a condition on a box may hold one)
}

void Simulation::constrain_velocity_recording_reactions(double time, double dt, double damping) {
  reactions_->start_constraints(*domain_, damping);
  for (std::size_t b = 0; b < bcs_.size(); ++b)
    reactions_->constrain(b, *bcs_[b], *domain_, time, dt);
  if (mixture_) {
    mixture_->drag_against_held_solid(domain_->nodes, dt);
    mixture_->hold_liquid_on_closed_faces(domain_->nodes);
  }
}

void Simulation::step() {
  timed(Stage::shape, [&] { locate_points(); });  // shape functions at the points (sorted again if they mixed)
  if (quasi_static_ && !collapse_from_)
    step_quasi_static();
  else
    step_explicit();  // explicit runs, and the collapse after a quasi-static run's failure
}

void Simulation::locate_points() {
  detail::Domain& d = *domain_;
  d.locate_points(clock_.steps(), clock_.time());
  if (!point_order_->sort_if_spread(d)) return;
  d.locate_points(clock_.steps(), clock_.time());  // in their new order
  point_order_->take_reference(d);
  points_renumbered();
}

// The MUSL step. Every stage is one call; the parts hold what differs
// between dry and saturated runs.
void Simulation::step_explicit() {
  const double t = clock_.time(), dt = clock_.dt();
  const double damping = scene_.damping_at(t);  // (zero from /damping_until on: a damped start)
  const std::size_t n = clock_.steps();
  detail::Domain& d = *domain_;
  timed(Stage::p2g, [&] { momentum_->points_to_grid(); });      // nodal mass, momentum, forces
  timed(Stage::grid, [&] {
    apply_loads(d.nodes, t);
    momentum_->integrate_grid(dt, damping);                     // nodal velocities at t + dt
    constrain_velocity_recording_reactions(t + dt, dt, damping);
    momentum_->accelerations(dt);
  });
  timed(Stage::g2p, [&] { momentum_->grid_to_points(dt); });    // point velocities and positions
  timed(Stage::remap, [&] {                                     // MUSL: nodal velocities again
    momentum_->remap();
    constrain_velocity(t + dt);
  });
  timed(Stage::strain, [&] { d.update_kinematics(dt); });       // L, strain, volume
  if (mixture_) {
    timed(Stage::pore_pressure, [&] { mixture_->update_pore_pressure(dt, n, t); });  // porosity, Darcy flux, p
    timed(Stage::erosion, [&] { species_->erode(dt); });        // skeleton -> liquid, at the points
    timed(Stage::permeability, [&] { mixture_->update_permeability(); });  // K follows the porosity
  }
  timed(Stage::stress, [&] { materials_->update_stress(d, dt); });  // (effective) stress, phase state
  if (species_) timed(Stage::transport, [&] { species_->transport(dt); });  // liquid and fines cross the grid
  timed(Stage::check, [&] { guard_->check(d, n + 1, t + dt, dt, dt); });  // a state, not a blow-up
  clock_.advance();
}

// The equilibrium at the end of the quasi-static step, halved until one converges: the step
// taken, or none under /failure (failure_ set; the state stays). Without /failure, an error.
std::optional<double> Simulation::find_equilibrium() {
  const double t = clock_.time();
  const std::size_t n = clock_.steps();
  const double nominal = clock_.nominal_dt();
  double dt = clock_.dt();
  double mechanism = 0;  // under /failure: the last equilibrium rejected for moving a cell or more
  for (;;) {
    std::optional<int> iterations;
    timed(Stage::solve, [&] { iterations = quasi_static_->solve(t, dt); });
    // Under /failure, an equilibrium a cell or more away is a mechanism's,
    // not the step's (the guard would stop the run at it): halved as one
    // not found, so that the failure is found at the load that starts it.
    mechanism = 0;
    if (iterations && scene_.failure) {
      const double moved = quasi_static_->largest_increment();
      if (moved >= domain_->grid.min_cell_size()) {
        mechanism = moved, iterations.reset();
        quasi_static_->reject_attempt();  // the next attempt starts from the step's start again
      }
    }
    if (iterations) {
      quasi_static_->accept_step();
      newton_iterations_ += static_cast<std::size_t>(*iterations);
      newton_residuals_ = quasi_static_->residuals();  // a factor of safety's solves come later
      if (const std::size_t held = quasi_static_->creep_held_points(); held > 0) {
        if (creep_held_first_ == 0) creep_held_first_ = held, creep_held_from_ = t + dt;
        if (held > creep_held_most_) creep_held_most_ = held, creep_held_most_at_ = t + dt;
      }
      return dt;
    }
    ++halved_steps_;
    if (dt < 1e-6 * *scene_.dt) break;
    dt /= 2;
    clock_.set_step(dt);
  }
  const std::string lost = "no equilibrium within /time/max_iterations = " +
                           std::to_string(scene_.quasi_static.max_iterations) +
                           " iterations, even after halving the step to " + detail::format(dt) + " s";
  const std::string last = mechanism > 0 ? ". The last attempt's equilibrium moved a node " +
                                               detail::format(mechanism) + " m, a cell or more: a mechanism"
                           : quasi_static_->failure().empty() ? ""
                                                              : ". At the last attempt " + quasi_static_->failure();
  if (!scene_.failure)
    throw Error("step " + std::to_string(n + 1) + " (t = " + detail::format(t) + " s): " + lost +
                ": the soil may be failing (a collapse has no quasi-static path; run it explicit, or give the scene "
                "a /failure section to stop there with its outputs and a checkpoint)" + last);
  failure_ = RunFailure{t, "step " + std::to_string(n + 1) + " found " + lost + last};
  clock_.set_step(nominal);
  return std::nullopt;
}

// The quasi-static step: the equilibrium at t + dt, then erosion and
// transport in substeps short enough for the transport, the erosion with the
// mean of the Darcy flux at t and at that equilibrium, the transport with the
// equilibrium's. The skeleton responds to this step's erosion in the next
// step's equilibrium.
void Simulation::step_quasi_static() {
  const double t = clock_.time();
  const std::size_t n = clock_.steps();
  detail::Domain& d = *domain_;
  const QuasiStaticControls& control = scene_.quasi_static;
  const std::optional<double> found = find_equilibrium();  // the step halved until one converges
  if (!found) return;  // under /failure none was found: the run has failed at t
  const double dt = *found;
  for (std::size_t r = 0; r < reactions_->size(); ++r) {
    const auto held = quasi_static_->held_by(reactions_->condition(r));
    reactions_->add_equilibrium(r, held.force, held.displacement, dt);
  }
  if (species_) species_->keep_flux_at_start();  // the erosion's flux: the mean of the step's start and end
  timed(Stage::g2p, [&] { quasi_static_->update_points(dt); });  // positions, strain, porosity, p, Darcy flux
  double transport_dt = dt;
  if (species_) {
    const double rate = quasi_static_->transport_rate();
    const auto substeps = static_cast<int>(std::max(1.0, std::ceil(dt * rate / control.transport_courant)));
    transport_dt = dt / substeps;
    species_->start_step();
    for (int k = 0; k < substeps; ++k) {
      bool eroded = false;
      double change = 0;
      timed(Stage::erosion, [&] { eroded = d.comm.any(species_->erode(transport_dt)); });  // on any process
      timed(Stage::transport, [&] {
        species_->transport(transport_dt, detail::TransportScheme::heun);
        change = species_->composition_change();
      });
      ++transport_substeps_;
      // Steady: nothing erodes, and the substeps left, each changing the
      // composition as much as this one, would stay within the tolerance.
      // One implicit step then takes the rest (thousands of substeps in a
      // washed-out column: docs/time-integration.md).
      const int left = substeps - k - 1;
      // (Not with water levels: the implicit step lets no water in through a
      // submerged surface.)
      if (left > 0 && !eroded && !water_ && change * left <= control.steady_transport_tolerance) {
        timed(Stage::transport,
              [&] { species_->transport(left * transport_dt, detail::TransportScheme::backward_euler); });
        ++steady_transport_steps_;
        break;
      }
    }
    species_->finish_step();
  }
  if (mixture_) timed(Stage::permeability, [&] { mixture_->update_permeability(); });
  timed(Stage::check, [&] { guard_->check(d, n + 1, t + dt, dt, transport_dt); });
  clock_.advance();
  // The next step: grown, unless this one eroded more than the tolerance.
  double next = std::min(control.max_dt > 0 ? control.max_dt : *scene_.dt, control.growth * clock_.nominal_dt());
  if (species_) {
    const double eroded = species_->largest_eroded_fraction_increment();
    if (eroded > 0) next = std::min(next, dt * control.eroded_fraction_tolerance / eroded);
  }
  clock_.set_step(next);
}

SafetyFactor Simulation::factor_of_safety() {
  if (!quasi_static_)
    throw Error("factor_of_safety: a strength reduction solves equilibria: it needs /time/integration "
                "\"quasi_static\"");
  if (!materials_->reduces_strength())
    throw Error("factor_of_safety: no material's phase reduces its strength (phase/mohr_coulomb does, and "
                "phase/suffosion around it)");
  timed(Stage::shape, [&] { locate_points(); });  // the points moved since the step's shape functions
  if (!strength_reduction_)
    strength_reduction_ = std::make_unique<detail::StrengthReduction>(
        scene_.factor_of_safety.value_or(FactorOfSafetySpec{}), *domain_, *materials_, *quasi_static_,
        safety_shear_strain_);
  SafetyFactor result;
  timed(Stage::safety, [&] { result = strength_reduction_->evaluate(clock_.time(), clock_.nominal_dt()); });
  return result;
}

int Simulation::threads() const { return domain_->exec.threads(); }
std::string Simulation::kernels() const { return detail::kernel_isa_name(domain_->exec.isa()); }
const PointSet& Simulation::points() const { return domain_->points; }
PointSet& Simulation::points() { return domain_->points; }
const GridGeometry& Simulation::grid() const { return domain_->grid; }
const NodeState& Simulation::nodes() const { return domain_->nodes; }

const Liquid& Simulation::liquid(std::size_t index) const {
  if (!mixture_) throw Error("liquid: the scene has no saturated body");
  return mixture_->liquid(index);
}

MassLedger Simulation::mass_ledger() const {
  if (!species_) throw Error("mass_ledger: the scene has no saturated body");
  return species_->mass_ledger(clock_.time());
}

double Simulation::total_mass() const {
  const PointSet& points = domain_->points;
  const double* m = points.data(points.core().mass);
  return domain_->exec.totals(points.size(), 1, [&](std::size_t p, double* sum) { sum[0] += m[p]; })[0];
}

std::array<double, 3> Simulation::total_momentum() const {
  const PointSet& points = domain_->points;
  const int dim = scene_.dim;
  const double* m = points.data(points.core().mass);
  const double* v = points.data(points.core().velocity);
  const auto t = domain_->exec.totals(points.size(), dim, [&](std::size_t p, double* sum) {
    for (int i = 0; i < dim; ++i) sum[i] += m[p] * v[p * dim + i];
  });
  return {t[0], t[1], t[2]};
}

}  // namespace suffuse
