#pragma once
// The constitutive side of a run: one phase plugin per material, updating the
// (effective) stress of its points, with the eigenstrain a phase may impose.
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "mpm/domain.hpp"
#include "mpm/material_phase.hpp"
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
  // The same in two parts, for quasi-static steps, whose Newton iterations
  // share the step's eigenstrain: asked once, before the solve, from the
  // state at the step's start (impose_eigenstrain), then handed to every
  // iteration's stress update (update_stress_with_imposed_eigenstrain).
  bool writes_eigenstrain() const { return eigenstrain_.has_value(); }
  // The field of the step's eigenstrain increment (if some phase writes one).
  std::optional<FieldId> eigenstrain_increment_field() const { return eigenstrain_increment_; }
  void impose_eigenstrain(Domain& domain, double dt) const;
  // `strength_reduction`: the factor F a strength reduction divides the
  // phases' strengths by (StressBatch::strength_reduction; 1 in a run's steps).
  void update_stress_with_imposed_eigenstrain(Domain& domain, double dt, double strength_reduction = 1.0) const;
  // Whether some material's phase reduces its strength (Phase::reduces_strength).
  bool reduces_strength() const;

  // Quasi-static runs. The fields the stress stage writes (the stress, each
  // phase's state, the eigenstrain): an iteration starts from their values
  // at the start of the step.
  const std::vector<FieldId>& stress_state_fields() const { return state_fields_; }
  // The tangent stiffness of every point, 36 per point (Phase::tangent), or
  // the isotropic fallback of modulus p_wave_modulus() and Poisson's ratio
  // 0.3 for a phase that gives none.
  void tangent(Domain& domain, double dt, std::vector<double>& stiffness, double strength_reduction = 1.0) const;

 private:
  std::vector<MaterialPhase> phases_;
  std::vector<std::string> names_;  // "phase phase/x of material 'm' (/materials/m)", for messages
  std::optional<FieldId> eigenstrain_, eigenstrain_increment_;
  std::vector<FieldId> state_fields_;

  // f(phase, range) on every batch of every body, a phase that throws named
  // with the points of its batch.
  template <class F>
  void for_each_batch(Domain& domain, const F& f) const;
  void impose_eigenstrain(const Phase& phase, PointSet& points, const PointRange& range, double dt) const;
  std::span<const double> imposed_eigenstrain(const Phase& phase, PointSet& points, const PointRange& range) const;
};

}  // namespace suffuse::detail
