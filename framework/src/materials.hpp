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

 private:
  std::vector<MaterialPhase> phases_;
  std::vector<std::string> names_;  // "phase/x of material 'm' (/materials/m)", for messages
  std::optional<FieldId> eigenstrain_, eigenstrain_increment_;
};

}  // namespace suffuse::detail
