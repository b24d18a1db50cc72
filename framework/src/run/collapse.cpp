// From a quasi-static run's failure to the collapse (/failure/collapse): the
// state of the last equilibrium goes on as an explicit run, which follows
// the mechanism the equilibrium could not (docs/slope-stability.md,
// Collapse).
#include <algorithm>
#include <cmath>
#include <limits>

#include "mixture/saturated_mixture.hpp"
#include "mpm/domain.hpp"
#include "scene/scene_reader.hpp"
#include "suffuse/error.hpp"
#include "suffuse/simulation.hpp"

namespace suffuse {

// The explicit step of the collapse: /failure/collapse_cfl times the cell
// over the fastest wave (the undrained one in saturated bodies, with the
// liquid's own stiffness), without mass scaling (a quasi-static scene has
// none). The drag needs no smaller step: it turns semi-implicit where it is
// faster than the step (docs/two-phase.md).
double Simulation::collapse_time_step() const {
  return scene_.failure->collapse_cfl / scene_.cfl * critical_time_step();
}

// A collapse that would not end in a lifetime is refused before anything is
// written, as an explicit run's end is (check_time_step).
void Simulation::check_collapse_steps() const {
  const double dt = collapse_time_step(), steps = *scene_.failure->collapse / dt;
  if (steps > max_steps)
    throw Error("/failure/collapse = " + detail::format(*scene_.failure->collapse) + " s would take " +
                detail::format(steps) + " explicit steps of " + detail::format(dt) + " s (at most " +
                detail::format(max_steps) + "): shorten it");
}

double Simulation::collapse_output_interval() const {
  return scene_.failure->collapse_output_interval.value_or(*scene_.failure->collapse / 10);
}

double Simulation::end_time() const {
  return collapse_from_ ? *collapse_from_ + *scene_.failure->collapse : scene_.end_time;
}

// The points start at rest at the last equilibrium, the liquid moving
// relative to them as its Darcy flux there (v_L = q / (n S)): the seepage goes
// on, and what moves is the mechanism's response to the load the
// equilibrium could not carry. Stresses, pore pressures, porosities and the
// fines carry over as they are; the ledger goes on counting.
void Simulation::start_collapse() {
  collapse_from_ = clock_.time();
  detail::Domain& d = *domain_;
  PointSet& pts = d.points;
  const int dim = scene_.dim;
  double* v = pts.data(pts.core().velocity);
  std::fill(v, v + pts.size() * static_cast<std::size_t>(dim), 0.0);
  if (mixture_) {
    const auto& f = mixture_->fields();
    const double* n = pts.data(f.porosity);
    const double* S = f.saturation ? pts.data(*f.saturation) : nullptr;
    const double* q = pts.data(f.darcy_flux);
    double* vl = pts.data(f.liquid_velocity);
    for (std::size_t p = 0; p < pts.size(); ++p) {
      const double wet = n[p] * (S ? S[p] : 1.0);  // the water flows through the pores it fills
      for (int i = 0; i < dim; ++i) {
        const std::size_t k = p * static_cast<std::size_t>(dim) + static_cast<std::size_t>(i);
        vl[k] = wet > 0 ? q[k] / wet : 0.0;
      }
    }
  }
  clock_.set_step(collapse_time_step());
  clock_.run_until(end_time());
  const double* u = pts.data(pts.core().displacement);
  std::copy(u, u + pts.size() * static_cast<std::size_t>(dim), pts.data(*failure_displacement_));
  measure_collapse();
}

void Simulation::add_collapse_fields() {
  if (!scene_.failure || !scene_.failure->collapse) return;
  PointSet& pts = domain_->points;
  failure_displacement_ = pts.add_field({"failure_displacement", FieldKind::Vector, "m",
                                         "the displacement at the failure, which the collapse starts from", false});
  collapse_displacement_ = pts.add_field(
      {"collapse_displacement", FieldKind::Vector, "m",
       "the movement since the failure, in the explicit run that follows the collapse (/failure/collapse); zero "
       "before it",
       true});
}

void Simulation::measure_collapse() {
  PointSet& pts = domain_->points;
  const double* u = pts.data(pts.core().displacement);
  const double* at_failure = pts.data(*failure_displacement_);
  double* moved = pts.data(*collapse_displacement_);
  for (std::size_t k = 0; k < pts.size() * static_cast<std::size_t>(scene_.dim); ++k) moved[k] = u[k] - at_failure[k];
}

// The largest movement since the failure, and where its point is: the
// process that holds it gives the position (every other gives -inf).
void Simulation::summarise_collapse(RunSummary& summary) const {
  const PointSet& pts = domain_->points;
  const auto dim = static_cast<std::size_t>(scene_.dim);
  const double* moved = pts.data(*collapse_displacement_);
  const double* x = pts.data(pts.core().position);
  double largest = 0;
  std::size_t at = pts.size();
  for (std::size_t p = 0; p < pts.size(); ++p) {
    double sq = 0;
    for (std::size_t i = 0; i < dim; ++i) sq += moved[p * dim + i] * moved[p * dim + i];
    if (std::sqrt(sq) > largest || at == pts.size()) largest = std::sqrt(sq), at = p;
  }
  summary.collapse_movement = domain_->comm.max(largest);
  const bool holds = at < pts.size() && largest == summary.collapse_movement;
  for (std::size_t i = 0; i < dim; ++i)
    summary.collapse_movement_at[i] =
        domain_->comm.max(holds ? x[at * dim + i] : -std::numeric_limits<double>::infinity());
}

}  // namespace suffuse
