#pragma once
// Checks at the end of every step that the state is still a state: finite
// velocities, stresses and pore pressures, no point moving more than a cell
// in a step (the explicit scheme has then already lost stability), porosity
// inside (0, 1), pore liquid crossing less than half a cell's pores in a
// step (the transport's Courant number q dt / (n h) below 0.5: beyond, the
// liquid a point carries departs from its pore volume). A run stops at its
// first failing check, in that order of the fields (a blow-up's first sign,
// a point moving too far, is named before the NaNs it spreads), naming the
// point, its body, position, field and value, and what to try.
#include <cstddef>
#include <optional>
#include <vector>

#include "mpm/domain.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

class StepGuard {
 public:
  struct Failure {
    int check;  // its rank in the order of the checks
    std::size_t point;
    const char* field;
    double value;
    const char* problem;
  };
  // The mixture's fields, absent in dry runs.
  struct MixtureIds {
    FieldId porosity, pore_pressure, darcy_flux;
  };
  StepGuard(const Scene& scene, std::optional<MixtureIds> mixture) : scene_(scene), mixture_(mixture) {}
  // Throws suffuse::Error describing the first failing point of the step
  // that ended at `time` (step number `step`, size `dt`).
  // `transport_dt`: the step of the transport (dt, or a quasi-static step's substep).
  void check(Domain& d, std::size_t step, double time, double dt, double transport_dt) const;

 private:
  const Scene& scene_;
  std::optional<MixtureIds> mixture_;
  mutable std::vector<std::optional<Failure>> found_;  // per thread, the first failing point
};

}  // namespace suffuse::detail
