// From a quasi-static run's failure to the collapse (/failure/collapse): the
// state of the last equilibrium goes on as an explicit run, which follows
// the mechanism the equilibrium could not (docs/slope-stability.md,
// Collapse).
#include <algorithm>
#include <cmath>

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
}

}  // namespace suffuse
