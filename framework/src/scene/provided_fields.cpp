#include "scene/provided_fields.hpp"

#include "mpm/point_order.hpp"
#include "mixture/saturated_mixture.hpp"
#include "transport/species_transport.hpp"

namespace suffuse::detail {

std::vector<ProvidedField> point_fields_of(const Scene& scene, const Registry& registry) {
  std::vector<ProvidedField> fields;
  const PointSet core(scene.dim);
  for (FieldId id = 0; id < core.field_count(); ++id) fields.push_back({core.info(id).name, "the core, always", true});
  fields.push_back({PointOrder::id_field_info().name, "the core, when /sort_points_at_spread is above 0",
                    scene.sort_points_at_spread > 0});
  const bool saturated = scene.saturated();
  for (const auto& f : SaturatedMixture::fields_declared())
    fields.push_back({f.info.name, "the saturated mixture, when a body has a \"liquid\"", saturated});
  for (const FieldInfo& f : {SaturatedMixture::saturation_field(), SaturatedMixture::potential_field()})
    fields.push_back({f.name, "the saturated mixture, when a material has \"phreatic\"", saturated && scene.phreatic()});
  // Whether fines are tracked depends on what the inlets bring: ask the
  // boundary conditions (their constructors only read parameters).
  std::vector<LiquidOpening> openings;
  for (const PluginNode& bc : scene.boundary_conditions) {
    if (!registry.find(bc.type)) continue;
    try {
      for (const LiquidOpening& o :
           registry.create<BoundaryCondition>(bc.type, {bc.params, scene.dim, bc.pointer})->liquid_openings())
        openings.push_back(o);
    } catch (const std::exception&) {
      // A condition that cannot be built says so, with its pointer, when the run builds it.
    }
  }
  const bool fines = saturated && SpeciesTransport::tracks_fines(scene, openings);
  for (const auto& f : SpeciesTransport::fines_fields_declared())
    fields.push_back({f.info.name,
                      "the species transport, when fines are tracked: a material has \"erosion\", a saturated body "
                      "has fines_content or concentration, or an inlet brings fines",
                      fines});
  return fields;
}

}  // namespace suffuse::detail
