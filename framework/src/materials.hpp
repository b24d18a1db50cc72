#pragma once
// The constitutive side of a run: one phase plugin per material, updating the
// (effective) stress of its points, with the eigenstrain a phase may impose.
#include <memory>
#include <optional>
#include <vector>

#include "domain.hpp"
#include "material_phase.hpp"
#include "suffuse/phase.hpp"

namespace suffuse::detail {

class Materials {
 public:
  Materials(const Scene& scene, const Registry& registry);

  const Phase& phase(std::size_t material) const { return phases_[material].phase(); }
  std::vector<const Phase*> phases() const;

  // After every other part registered its fields: the eigenstrain fields
  // (if some phase writes one), then each phase's own.
  void add_fields(PointSet& points);
  // Stage "stress": each material's phase on its bodies' points. A phase
  // that writes an eigenstrain is asked for it first; the core adds it to
  // the point's "eigenstrain" and hands it to the stress update.
  void update_stress(Domain& domain, double dt) const;

  // Quasi-static runs. The fields the stress stage writes (the stress, each
  // phase's state, the eigenstrain): an iteration starts from their values
  // at the start of the step.
  const std::vector<FieldId>& stress_state_fields() const { return state_fields_; }
  // The tangent stiffness of every point, 36 per point (Phase::tangent), or
  // the isotropic fallback of modulus p_wave_modulus() and Poisson's ratio
  // 0.3 for a phase that gives none.
  void tangent(Domain& domain, double dt, std::vector<double>& stiffness) const;

 private:
  std::vector<MaterialPhase> phases_;
  std::vector<std::string> names_;  // "phase/x of material 'm' (/materials/m)", for messages
  std::optional<FieldId> eigenstrain_, eigenstrain_increment_;
  std::vector<FieldId> state_fields_;
};

}  // namespace suffuse::detail
