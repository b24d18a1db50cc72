#pragma once
// Checks at the end of every step that the state is still a state: finite
// velocities, stresses and pore pressures, no point moving more than a cell
// in a step (the explicit scheme has then already lost stability), porosity
// inside (0, 1). The first point that fails stops the run with its index,
// body, position, field and value, and what to try.
#include <cstddef>
#include <optional>

#include "domain.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

class StepGuard {
 public:
  // `porosity`, `pore_pressure`: the mixture's fields, absent in dry runs.
  StepGuard(const Scene& scene, std::optional<FieldId> porosity, std::optional<FieldId> pore_pressure)
      : scene_(scene), porosity_(porosity), pore_pressure_(pore_pressure) {}
  // Throws suffuse::Error describing the first failing point of the step
  // that ended at `time` (step number `step`, size `dt`).
  void check(Domain& d, std::size_t step, double time, double dt) const;

 private:
  const Scene& scene_;
  std::optional<FieldId> porosity_, pore_pressure_;
};

}  // namespace suffuse::detail
