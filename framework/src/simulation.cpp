#include "suffuse/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>

#include "suffuse/error.hpp"
#include "simulation_parallel.hpp"
#include "two_phase_kernels.hpp"

namespace suffuse {

namespace {

using Clock = std::chrono::steady_clock;

// Adds the wall time of a scope to a stage counter.
class StageTimer {
 public:
  explicit StageTimer(double& total) : total_(total), start_(Clock::now()) {}
  ~StageTimer() { total_ += std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  double& total_;
  Clock::time_point start_;
};

using detail::voigt_index;  // xx yy zz yz xz xy

// ---- kernels, one loop each, specialised by dimension ----

template <int D>
void p2g_kernel(std::size_t begin, std::size_t end, int npp, const std::int64_t* ids, const double* w, const double* dw,
                const double* mass, const double* volume, const double* vel, const double* stress,
                const std::array<double, 3>& g, double scale, double* node_mass, double* node_mom,
                double* node_force) {
  for (std::size_t p = begin; p < end; ++p) {
    const double m = mass[p], V = volume[p], inertia = scale * m;
    const double* v = vel + p * D;
    const double* s = stress + p * 6;
    for (int a = 0; a < npp; ++a) {
      const std::size_t k = p * npp + a;
      const std::int64_t I = ids[k];
      const double wm = w[k] * m, wi = w[k] * inertia;
      const double* grad = dw + k * D;
      node_mass[I] += wi;
      for (int i = 0; i < D; ++i) {
        node_mom[I * D + i] += wi * v[i];
        double f = wm * g[i];
        for (int j = 0; j < D; ++j) f -= V * s[voigt_index(i, j)] * grad[j];
        node_force[I * D + i] += f;
      }
    }
  }
}

template <int D>
void grid_update_kernel(std::size_t begin, std::size_t end, double dt, double damping, const double* mass, const double* mom,
                        double* force, double* vel) {
  for (std::size_t I = begin; I < end; ++I) {
    const double m = mass[I];
    if (m <= 0) {
      for (int i = 0; i < D; ++i) vel[I * D + i] = 0;
      continue;
    }
    for (int i = 0; i < D; ++i) {
      const double v_old = mom[I * D + i] / m;
      double f = force[I * D + i];
      // Local non-viscous damping (Cundall): a force opposing the motion,
      // proportional to the unbalanced force.
      if (damping > 0 && v_old != 0) f -= damping * std::abs(f) * (v_old > 0 ? 1.0 : -1.0);
      force[I * D + i] = f;
      vel[I * D + i] = v_old + f / m * dt;
    }
  }
}

template <int D>
void acceleration_kernel(std::size_t begin, std::size_t end, double dt, const double* mass, const double* mom, const double* vel,
                         double* acc) {
  for (std::size_t I = begin; I < end; ++I) {
    const double m = mass[I];
    for (int i = 0; i < D; ++i) acc[I * D + i] = m > 0 ? (vel[I * D + i] - mom[I * D + i] / m) / dt : 0.0;
  }
}

template <int D>
void g2p_kernel(std::size_t begin, std::size_t end, int npp, double dt, const std::int64_t* ids, const double* w, const double* node_vel,
                const double* node_acc, double* x, double* u, double* vel) {
  for (std::size_t p = begin; p < end; ++p) {
    double dv[D] = {}, vg[D] = {};
    for (int a = 0; a < npp; ++a) {
      const std::size_t k = p * npp + a;
      const std::int64_t I = ids[k];
      for (int i = 0; i < D; ++i) {
        dv[i] += w[k] * node_acc[I * D + i];
        vg[i] += w[k] * node_vel[I * D + i];
      }
    }
    for (int i = 0; i < D; ++i) {
      vel[p * D + i] += dt * dv[i];  // FLIP: velocity from the nodal acceleration
      x[p * D + i] += dt * vg[i];
      u[p * D + i] += dt * vg[i];
    }
  }
}

template <int D>
void remap_kernel(std::size_t begin, std::size_t end, int npp, const std::int64_t* ids, const double* w, const double* mass,
                  double scale, const double* vel, double* node_mom) {
  for (std::size_t p = begin; p < end; ++p) {
    const double m = scale * mass[p];
    for (int a = 0; a < npp; ++a) {
      const std::size_t k = p * npp + a;
      const std::int64_t I = ids[k];
      for (int i = 0; i < D; ++i) node_mom[I * D + i] += w[k] * m * vel[p * D + i];
    }
  }
}

template <int D>
void velocity_gradient_kernel(std::size_t begin, std::size_t end, int npp, double dt, const std::int64_t* ids, const double* dw,
                              const double* node_vel, double* L, double* strain, double* volume) {
  for (std::size_t p = begin; p < end; ++p) {
    double l[D][D] = {};
    for (int a = 0; a < npp; ++a) {
      const std::size_t k = p * npp + a;
      const std::int64_t I = ids[k];
      for (int i = 0; i < D; ++i)
        for (int j = 0; j < D; ++j) l[i][j] += node_vel[I * D + i] * dw[k * D + j];
    }
    double* Lp = L + p * D * D;
    double* e = strain + p * 6;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) Lp[i * D + j] = l[i][j];
    for (int i = 0; i < D; ++i)
      for (int j = i; j < D; ++j) e[voigt_index(i, j)] += 0.5 * (l[i][j] + l[j][i]) * dt;
    // Volume follows det(I + L dt) of the step.
    volume[p] *= detail::step_jacobian<D>(Lp, dt);
  }
}

}  // namespace

Simulation::Simulation(const Scene& scene, const Registry& registry, int threads)
    : threads_(std::max(1, threads)),
      scene_(scene),
      grid_(scene.dim, scene.grid_origin, scene.grid_cell_size, scene.grid_cells),
      points_(scene.dim) {
  const int dim = scene.dim;
  shape_ = registry.create<ShapeFunction>(scene.shape_function.type,
                                          {scene.shape_function.params, dim, scene.shape_function.pointer});
  npp_ = shape_->nodes_per_point(dim);
  for (const MaterialSpec& m : scene.materials) {
    phases_.push_back(registry.create<Phase>(m.phase.type, {m.phase.params, dim, m.phase.pointer}));
    phases_.back()->add_fields(points_);
    permeability_.push_back(m.permeability ? registry.create<PermeabilityLaw>(
                                                 m.permeability->type,
                                                 {m.permeability->params, dim, m.permeability->pointer})
                                           : nullptr);
    erosion_.push_back(m.erosion ? registry.create<ErosionLaw>(m.erosion->type,
                                                              {m.erosion->params, dim, m.erosion->pointer})
                                 : nullptr);
  }
  for (const LiquidSpec& l : scene.liquids)
    liquids_.push_back(registry.create<Liquid>(l.liquid.type, {l.liquid.params, dim, l.liquid.pointer}));
  for (const PluginNode& bc : scene.boundary_conditions) {
    bcs_.push_back(registry.create<BoundaryCondition>(bc.type, {bc.params, dim, bc.pointer}));
    bcs_.back()->setup(grid_);
  }
  saturated_ = scene.saturated();
  // Fines are tracked when a body holds some, a material erodes, or an inlet brings them.
  fines_ = scene.erodible();
  for (const BodySpec& b : scene.bodies) fines_ = fines_ || b.fines_content > 0 || b.concentration > 0;
  for (const auto& bc : bcs_)
    for (const LiquidOpening& o : bc->liquid_openings()) fines_ = fines_ || o.concentration > 0;
  if (saturated_) {
    add_saturated_fields();
    add_species_fields();
  }
  for (const OutputSpec& out : scene.outputs)
    writers_.push_back(registry.create<Writer>(out.writer.type, {out.writer.params, dim, out.writer.pointer}));
  nodes_.resize(grid_.node_count(), dim, saturated_);
  if (saturated_) {
    node_drag_.assign(grid_.node_count(), 0.0);
    node_darcy_.assign(grid_.node_count() * dim, 0.0);
    node_face_.assign(grid_.node_count() * dim, 0.0);
    for (auto* v : {&node_pore_, &node_liquid_, &node_fines_, &node_out_, &node_dliquid_,
                    &node_dfines_, &node_free_liquid_, &node_free_fines_})
      v->assign(grid_.node_count(), 0.0);
    setup_openings();
  }
  // Threads other than the first scatter into their own copy of the nodal
  // arrays, summed in thread order afterwards: no atomics, and the same
  // numbers for the same thread count.
  const std::size_t per_node = saturated_ ? 4 + 4 * dim : 1 + 2 * dim;
  scatter_.assign(threads_ - 1, std::vector<double>(grid_.node_count() * per_node));
  chunk_errors_.resize(threads_);
  create_points();
  for (const auto& bc : bcs_) bc->setup_points(grid_, points_);
  if (saturated_) {
    flux_magnitude_.assign(points_.size(), 0.0);
    const MassLedger start = mass_ledger();
    initial_solid_ = start.solid;
    initial_liquid_ = start.liquid;
    initial_fines_ = start.skeleton_fines + start.suspended_fines;
  }
  dt_ = scene.dt ? *scene.dt : critical_time_step();
}

Simulation::~Simulation() = default;

void Simulation::add_saturated_fields() {
  using K = FieldKind;
  sf_.porosity = points_.add_field({"porosity", K::Scalar, "-", "porosity n", true});
  sf_.pressure = points_.add_field({"pore_pressure", K::Scalar, "Pa", "pore pressure p, compression positive", true});
  sf_.liquid_velocity = points_.add_field({"liquid_velocity", K::Vector, "m/s", "velocity of the pore liquid", true});
  sf_.conductivity =
      points_.add_field({"hydraulic_conductivity", K::Scalar, "m/s", "hydraulic conductivity K", true});
  sf_.darcy_flux = points_.add_field({"darcy_flux", K::Vector, "m/s", "Darcy flux q = n (v_L - v_s)", true});
  sf_.liquid_density = points_.add_field({"liquid_density", K::Scalar, "kg/m^3", "density of the pore liquid", true});
  sf_.liquid_mass = points_.add_field(
      {"liquid_mass", K::Scalar, "kg", "pore liquid the point carries, transported (per metre in 2D)", true});
  sf_.moving_liquid_mass = points_.add_field(
      {"moving_liquid_mass", K::Scalar, "kg", "n rho_L V, the liquid mass of the momentum balance", false});
  sf_.bulk_modulus = points_.add_field({"liquid_bulk_modulus", K::Scalar, "Pa", "K_L of the pore liquid", false});
  sf_.pressure_rate =
      points_.add_field({"pore_pressure_rate", K::Scalar, "Pa/s", "unsmoothed rate of the pore pressure", false});
  node_pressure_rate_.assign(grid_.node_count(), 0.0);
  node_volume_.assign(grid_.node_count(), 0.0);
}

double Simulation::critical_time_step() const {
  // Dry bodies: h / sqrt(M / rho). Saturated bodies (Mieremet et al. 2016):
  // the undrained wave h / c_u, c_u = sqrt((M + K_L/n) / rho_sat), and the
  // explicit-drag limit 2 (1-n) rho_s K / (n g rho_sat).
  const double h = grid_.min_cell_size();
  double dt = std::numeric_limits<double>::infinity();
  for (const BodySpec& body : scene_.bodies) {
    const Phase& phase = *phases_[body.material];
    if (!body.liquid) {
      dt = std::min(dt, h / std::sqrt(phase.p_wave_modulus() / phase.density()));
      continue;
    }
    const Liquid& liquid = *liquids_[*body.liquid];
    const double n = body.porosity, rho_s = phase.density();
    const double rho_sat = (1 - n) * rho_s + n * liquid.density();
    dt = std::min(dt, h / std::sqrt((phase.p_wave_modulus() + liquid.bulk_modulus() / n) / rho_sat));
    double K = 0;
    permeability_[body.material]->conductivity(std::span(&n, 1), std::span(&K, 1));
    dt = std::min(dt, 2 * (1 - n) * rho_s * K / (n * reference_gravity * rho_sat));
  }
  if (!(dt > 0) || !std::isfinite(dt))
    throw Error("cannot choose a time step automatically: no material has a positive wave speed; set /time/dt");
  // Mass scaling multiplies every inertia by f: waves slow down by sqrt(f).
  return scene_.cfl * dt * std::sqrt(scene_.mass_scaling);
}

void Simulation::create_points() {
  const int dim = scene_.dim;
  for (const BodySpec& body : scene_.bodies) {
    std::array<std::size_t, 3> count{1, 1, 1};
    std::array<double, 3> spacing{1, 1, 1};
    std::size_t total = 1;
    for (int a = 0; a < dim; ++a) {
      const double extent = body.max[a] - body.min[a];
      count[a] = std::max<std::size_t>(
          1, static_cast<std::size_t>(std::llround(extent / grid_.cell_size()[a] * body.points_per_cell)));
      spacing[a] = extent / static_cast<double>(count[a]);
      total *= count[a];
    }
    const Phase& phase = *phases_[body.material];
    double volume = 1;
    for (int a = 0; a < dim; ++a) volume *= spacing[a];  // per unit thickness in 2D
    const std::size_t first = points_.append(total);
    const auto& f = points_.core();
    double* x = points_.data(f.position);
    double* v = points_.data(f.velocity);
    double* m = points_.data(f.mass);
    double* V = points_.data(f.volume);
    double* id = points_.data(f.material_id);
    double* size = points_.data(f.size);
    std::size_t p = first;
    for (std::size_t k = 0; k < count[2]; ++k)
      for (std::size_t j = 0; j < count[1]; ++j)
        for (std::size_t i = 0; i < count[0]; ++i, ++p) {
          const std::size_t idx[3] = {i, j, k};
          for (int a = 0; a < dim; ++a) {
            x[p * dim + a] = body.min[a] + (static_cast<double>(idx[a]) + 0.5) * spacing[a];
            v[p * dim + a] = body.velocity[a];
            size[p * dim + a] = spacing[a];
          }
          for (int c = 0; c < 6; ++c) points_.data(f.stress)[p * 6 + c] = body.stress[c];
          V[p] = volume;
          m[p] = volume * phase.density() * (body.liquid ? 1 - body.porosity : 1.0);
          id[p] = static_cast<double>(body.material);
        }
    const PointRange range{first, first + total};
    ranges_.push_back({body.material, range, body.liquid.has_value()});
    if (body.liquid) {
      const Liquid& liquid = *liquids_[*body.liquid];
      for (std::size_t q = range.begin; q < range.end; ++q) {
        points_.data(sf_.porosity)[q] = body.porosity;
        points_.data(sf_.pressure)[q] = body.pore_pressure;
        points_.data(sf_.bulk_modulus)[q] = liquid.bulk_modulus();
        for (int a = 0; a < dim; ++a) points_.data(sf_.liquid_velocity)[q * dim + a] = body.velocity[a];
      }
      set_species_state(body, range);
      update_conductivity(ranges_.back());
    }
    set_geostatic_state(body, range);
    body_names_.push_back(body.name);
    body_ranges_.push_back(range);
    phase.initialise(points_, range);
  }
}

void Simulation::set_geostatic_state(const BodySpec& body, PointRange range) {
  // Vertical axis: the last one; g: the gravity component along it, downward.
  const int dim = scene_.dim, v = dim - 1;
  const double g = -scene_.gravity[v];
  const double* x = points_.data(points_.core().position);
  const double rho_l = body.liquid ? liquids_[*body.liquid]->density() : 0.0;
  if (body.k0) {
    const double rho = phases_[body.material]->density();
    const double unit_weight = body.liquid ? (1 - body.porosity) * (rho - rho_l) * g : rho * g;
    double* s = points_.data(points_.core().stress);
    for (std::size_t p = range.begin; p < range.end; ++p) {
      const double sv = -unit_weight * (body.max[v] - x[p * dim + v]);
      for (int a = 0; a < 3; ++a) s[p * 6 + a] += (a == v ? 1.0 : *body.k0) * sv;
    }
  }
  if (body.liquid && body.water_table) {
    double* pr = points_.data(sf_.pressure);
    for (std::size_t p = range.begin; p < range.end; ++p)
      pr[p] += rho_l * g * std::max(0.0, *body.water_table - x[p * dim + v]);
  }
}

void Simulation::check_points_in_grid() const {
  const int dim = scene_.dim;
  const double* x = points_.data(points_.core().position);
  for (std::size_t p = 0; p < points_.size(); ++p) {
    if (grid_.contains(x + p * dim)) continue;
    std::string body;
    for (std::size_t b = 0; b < body_ranges_.size(); ++b)
      if (p >= body_ranges_[b].begin && p < body_ranges_[b].end) body = body_names_[b];
    std::ostringstream pos;
    for (int a = 0; a < dim; ++a) pos << (a ? ", " : "") << x[p * dim + a];
    throw Error("material point " + std::to_string(p) + " of body '" + body + "' left the grid at step " +
                std::to_string(step_) + " (t = " + std::to_string(time_) + " s): position (" + pos.str() +
                "); enlarge /grid or check the boundary conditions and the time step");
  }
}

void Simulation::compute_shape_functions() {
  StageTimer t(times_.shape);
  check_points_in_grid();
  const std::size_t n = points_.size();
  node_ids_.resize(n * npp_);
  weights_.resize(n * npp_);
  gradients_.resize(n * npp_ * scene_.dim);
  const int dim = scene_.dim;
  const auto x = points_.values(points_.core().position);
  const auto size = points_.values(points_.core().size);
  for_chunks(n, [&](int, std::size_t b, std::size_t e) {
    shape_->evaluate(grid_, x.subspan(b * dim, (e - b) * dim), size.subspan(b * dim, (e - b) * dim),
                     std::span(node_ids_).subspan(b * npp_, (e - b) * npp_),
                     std::span(weights_).subspan(b * npp_, (e - b) * npp_),
                     std::span(gradients_).subspan(b * npp_ * dim, (e - b) * npp_ * dim));
  });
}

void Simulation::update_conductivity(const MaterialRange& r) {
  const PermeabilityLaw& law = *permeability_[r.material];
  for_chunks(r.range.size(), [&](int, std::size_t b, std::size_t e) {
    law.conductivity(points_.values(sf_.porosity).subspan(r.range.begin + b, e - b),
                     points_.values(sf_.conductivity).subspan(r.range.begin + b, e - b));
  });
}

void Simulation::reset_grid() {
  StageTimer t(times_.reset);
  for (auto* v : {&nodes_.mass, &nodes_.momentum, &nodes_.force, &nodes_.liquid_mass, &nodes_.liquid_momentum,
                  &nodes_.liquid_force, &nodes_.liquid_inertia, &node_drag_})
    std::fill(v->begin(), v->end(), 0.0);
}

void Simulation::points_to_grid() {
  StageTimer t(times_.p2g);
  if (saturated_) return points_to_grid_saturated();
  const auto& f = points_.core();
  auto kernel = scene_.dim == 2 ? &p2g_kernel<2> : &p2g_kernel<3>;
  ScatterTargets targets;
  targets.add(nodes_.mass);
  targets.add(nodes_.momentum);
  targets.add(nodes_.force);
  scatter(targets, [&](std::size_t b, std::size_t e, double* const* out) {
    kernel(b, e, npp_, node_ids_.data(), weights_.data(), gradients_.data(), points_.data(f.mass),
           points_.data(f.volume), points_.data(f.velocity), points_.data(f.stress), scene_.gravity,
           scene_.mass_scaling, out[0], out[1], out[2]);
  });
}

void Simulation::points_to_grid_saturated() {
  const auto& f = points_.core();
  auto kernel = scene_.dim == 2 ? &detail::p2g_saturated<2> : &detail::p2g_saturated<3>;
  const detail::SaturatedPoints pt{points_.data(f.mass),           points_.data(f.volume),
                                   points_.data(f.velocity),       points_.data(f.stress),
                                   points_.data(sf_.porosity),     points_.data(sf_.pressure),
                                   points_.data(sf_.liquid_velocity), points_.data(sf_.moving_liquid_mass),
                                   points_.data(sf_.conductivity), points_.data(ef_.water_density)};
  ScatterTargets targets;
  targets.add(nodes_.mass);
  targets.add(nodes_.momentum);
  targets.add(nodes_.force);
  targets.add(nodes_.liquid_mass);
  targets.add(nodes_.liquid_momentum);
  targets.add(nodes_.liquid_force);
  targets.add(nodes_.liquid_inertia);
  targets.add(node_drag_);
  scatter(targets, [&](std::size_t b, std::size_t e, double* const* out) {
    kernel(b, e, npp_, node_ids_.data(), weights_.data(), gradients_.data(), pt, scene_.gravity.data(),
           scene_.mass_scaling, detail::SaturatedNodes{out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7]});
  });
}

void Simulation::apply_external_forces() {
  StageTimer t(times_.grid_update);
  for (const auto& bc : bcs_) {
    bc->apply_forces(grid_, nodes_, time_);
    bc->apply_point_forces(grid_, points_, nodes_, time_);
  }
}

void Simulation::constrain_velocity() {
  for (const auto& bc : bcs_) bc->constrain_velocity(grid_, nodes_, time_ + dt_);
}

void Simulation::update_grid() {
  StageTimer t(times_.grid_update);
  const std::size_t nn = grid_.node_count();
  if (saturated_) {
    auto update = scene_.dim == 2 ? &detail::grid_update_saturated<2> : &detail::grid_update_saturated<3>;
    for_chunks(nn, [&](int, std::size_t b, std::size_t e) {
      update(b, e, dt_, scene_.damping, nodes_.mass.data(), nodes_.momentum.data(), nodes_.force.data(),
             nodes_.liquid_mass.data(), nodes_.liquid_momentum.data(), nodes_.liquid_force.data(),
             nodes_.liquid_inertia.data(), node_drag_.data(), nodes_.velocity.data(), nodes_.liquid_velocity.data());
    });
  } else {
    auto update = scene_.dim == 2 ? &grid_update_kernel<2> : &grid_update_kernel<3>;
    for_chunks(nn, [&](int, std::size_t b, std::size_t e) {
      update(b, e, dt_, scene_.damping, nodes_.mass.data(), nodes_.momentum.data(), nodes_.force.data(),
             nodes_.velocity.data());
    });
  }
  constrain_velocity();
  auto acc = scene_.dim == 2 ? &acceleration_kernel<2> : &acceleration_kernel<3>;
  for_chunks(nn, [&](int, std::size_t b, std::size_t e) {
    acc(b, e, dt_, nodes_.mass.data(), nodes_.momentum.data(), nodes_.velocity.data(), nodes_.acceleration.data());
    if (saturated_)
      acc(b, e, dt_, nodes_.liquid_mass.data(), nodes_.liquid_momentum.data(), nodes_.liquid_velocity.data(),
          nodes_.liquid_acceleration.data());
  });
}

void Simulation::grid_to_points() {
  StageTimer t(times_.g2p);
  const auto& f = points_.core();
  auto kernel = scene_.dim == 2 ? &g2p_kernel<2> : &g2p_kernel<3>;
  for_chunks(points_.size(), [&](int, std::size_t b, std::size_t e) {
    kernel(b, e, npp_, dt_, node_ids_.data(), weights_.data(), nodes_.velocity.data(), nodes_.acceleration.data(),
           points_.data(f.position), points_.data(f.displacement), points_.data(f.velocity));
    if (saturated_)
      (scene_.dim == 2 ? &detail::g2p_liquid<2> : &detail::g2p_liquid<3>)(
          b, e, npp_, dt_, node_ids_.data(), weights_.data(), nodes_.liquid_acceleration.data(),
          points_.data(sf_.liquid_velocity));
  });
}

void Simulation::remap_momentum() {
  StageTimer t(times_.remap);
  // MUSL: nodal velocities for the strain rate come from the updated point
  // momenta, which damps the small-mass-node noise of plain USL.
  std::fill(nodes_.momentum.begin(), nodes_.momentum.end(), 0.0);
  std::fill(nodes_.liquid_momentum.begin(), nodes_.liquid_momentum.end(), 0.0);
  const auto& f = points_.core();
  auto kernel = scene_.dim == 2 ? &remap_kernel<2> : &remap_kernel<3>;
  ScatterTargets targets;
  targets.add(nodes_.momentum);
  if (saturated_) targets.add(nodes_.liquid_momentum);
  scatter(targets, [&](std::size_t b, std::size_t e, double* const* out) {
    kernel(b, e, npp_, node_ids_.data(), weights_.data(), points_.data(f.mass), scene_.mass_scaling,
           points_.data(f.velocity), out[0]);
    if (saturated_)
      kernel(b, e, npp_, node_ids_.data(), weights_.data(), points_.data(sf_.moving_liquid_mass), scene_.mass_scaling,
             points_.data(sf_.liquid_velocity), out[1]);
  });
  const std::size_t dim = scene_.dim;
  for_chunks(grid_.node_count(), [&](int, std::size_t b, std::size_t e) {
    for (std::size_t I = b; I < e; ++I) {
      const double m = nodes_.mass[I];
      for (std::size_t i = 0; i < dim; ++i)
        nodes_.velocity[I * dim + i] = m > 0 ? nodes_.momentum[I * dim + i] / m : 0.0;
      if (!saturated_) continue;
      const double ml = nodes_.liquid_mass[I];
      for (std::size_t i = 0; i < dim; ++i)
        nodes_.liquid_velocity[I * dim + i] = ml > 0 ? nodes_.liquid_momentum[I * dim + i] / ml : 0.0;
    }
  });
  constrain_velocity();
}

void Simulation::update_stress() {
  StageTimer t(times_.stress);
  const auto& f = points_.core();
  auto kernel = scene_.dim == 2 ? &velocity_gradient_kernel<2> : &velocity_gradient_kernel<3>;
  for_chunks(points_.size(), [&](int, std::size_t b, std::size_t e) {
    kernel(b, e, npp_, dt_, node_ids_.data(), gradients_.data(), nodes_.velocity.data(),
           points_.data(f.velocity_gradient), points_.data(f.strain), points_.data(f.volume));
  });
  if (saturated_) {
    // The nodal Darcy flux q_I = n_I (v_L - v_s)_I, n_I = sum N n rho_L V / sum N rho_L V:
    // one field for the pressure rate (div q) and the transport.
    const std::size_t dim = scene_.dim;
    for_chunks(grid_.node_count(), [&](int, std::size_t b, std::size_t e) {
      for (std::size_t I = b; I < e; ++I) {
        const double inertia = nodes_.liquid_inertia[I];
        const double nI = inertia > 0 ? nodes_.liquid_mass[I] / inertia : 0.0;
        for (std::size_t i = 0; i < dim; ++i)
          node_darcy_[I * dim + i] = nI * (nodes_.liquid_velocity[I * dim + i] - nodes_.velocity[I * dim + i]);
      }
    });
    auto porous = scene_.dim == 2 ? &detail::porous_update<2> : &detail::porous_update<3>;
    for_chunks(points_.size(), [&](int, std::size_t b, std::size_t e) {
      const std::size_t bad = porous(b, e, npp_, dt_, node_ids_.data(), gradients_.data(), node_darcy_.data(),
             points_.data(f.velocity_gradient), points_.data(sf_.bulk_modulus), points_.data(f.velocity),
             points_.data(sf_.liquid_velocity), points_.data(sf_.porosity), points_.data(sf_.pressure_rate),
             points_.data(sf_.darcy_flux));
      if (bad != e)
        throw Error("material point " + std::to_string(bad) + " was compressed to porosity " +
                    std::to_string(points_.data(sf_.porosity)[bad]) + " at step " + std::to_string(step_) +
                    " (t = " + std::to_string(time_) +
                    " s): its grains cannot be compressed; reduce the time step or check the loads");
    });
    // Pressure smoothing: the pore-pressure rate is averaged over the nodes
    // and interpolated back. Raw point rates carry the checkerboard modes of a
    // nearly incompressible mixture on linear cells (as in Anura3D).
    std::fill(node_pressure_rate_.begin(), node_pressure_rate_.end(), 0.0);
    std::fill(node_volume_.begin(), node_volume_.end(), 0.0);
    ScatterTargets targets;
    targets.add(node_pressure_rate_);
    targets.add(node_volume_);
    scatter(targets, [&](std::size_t b, std::size_t e, double* const* out) {
      detail::p2g_pressure_rate(b, e, npp_, node_ids_.data(), weights_.data(), points_.data(f.volume),
                                   points_.data(sf_.porosity), points_.data(sf_.pressure_rate), out[0], out[1]);
    });
    for_chunks(points_.size(), [&](int, std::size_t b, std::size_t e) {
      detail::g2p_pressure(b, e, npp_, dt_, node_ids_.data(), weights_.data(), node_pressure_rate_.data(),
                           node_volume_.data(), points_.data(sf_.porosity), points_.data(sf_.pressure));
    });
  }
  for (const MaterialRange& r : ranges_) {
    // The phase updates the effective stress in a saturated body.
    for_chunks(r.range.size(), [&](int, std::size_t b, std::size_t e) {
      phases_[r.material]->update_stress(points_, {r.range.begin + b, r.range.begin + e}, dt_);
    });
  }
}

void Simulation::step() {
  compute_shape_functions();
  reset_grid();
  points_to_grid();
  apply_external_forces();
  update_grid();
  grid_to_points();
  remap_momentum();
  update_stress();
  if (saturated_) {
    erode();                // skeleton -> liquid, at the points
    update_permeability();  // K follows the porosity
    transport_liquid();     // liquid and suspended fines cross the grid with the Darcy flux
  }
  time_ += dt_;
  ++step_;
}

double Simulation::total_mass() const {
  const double* m = points_.data(points_.core().mass);
  double total = 0;
  for (std::size_t p = 0; p < points_.size(); ++p) total += m[p];
  return total;
}

std::array<double, 3> Simulation::total_momentum() const {
  const int dim = scene_.dim;
  const double* m = points_.data(points_.core().mass);
  const double* v = points_.data(points_.core().velocity);
  std::array<double, 3> total{0, 0, 0};
  for (std::size_t p = 0; p < points_.size(); ++p)
    for (int i = 0; i < dim; ++i) total[i] += m[p] * v[p * dim + i];
  return total;
}

}  // namespace suffuse
