// Boundary conditions: a list of boundary-condition plugin nodes, each of
// which may ask for its reaction to be recorded.
#include <algorithm>

#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema boundary_condition_schema() {
  ParameterSchema s;
  s.string("reaction").may_be_absent().doc(
      "Record this condition's reaction under this name: the force its velocity constraints exert on the soil "
      "(N, per metre of thickness in 2D; in saturated runs the total force, pore pressure included) and the mean displacement of the nodes they hold, in "
      "<scene>.reactions.csv (for example the load-settlement curve of a footing)");
  return s;
}

void read_boundary_conditions(SceneReader& r, Scene& scene) {
  if (!r.root.contains("boundary_conditions")) return;
  const Json& bcs = r.root["boundary_conditions"];
  if (!bcs.is_array()) {
    r.error("/boundary_conditions", "wrong type", "array of boundary condition nodes", show(bcs), "core (scene)");
    return;
  }
  const ParameterSchema core = boundary_condition_schema();
  std::set<std::string> core_keys;
  for (const Param& p : core.params()) core_keys.insert(p.name);
  for (std::size_t i = 0; i < bcs.size(); ++i) {
    const std::string ptr = "/boundary_conditions/" + std::to_string(i);
    scene.boundary_conditions.push_back(r.plugin_node(bcs[i], ptr, PluginKind::BoundaryCondition, core_keys));
    if (!bcs[i].is_object()) continue;
    // Unknown keys are the plugin's to report: the core checks only its own.
    std::set<std::string> others;
    for (const auto& [k, v] : bcs[i].items())
      if (!core_keys.count(k)) others.insert(k);
    const Parameters c = validate_object(bcs[i], core, ptr, "core (boundary condition)", r.dim, r.diags, others);
    if (!c.has("reaction")) continue;
    const std::string& name = c.string("reaction");
    const bool taken = std::any_of(scene.reactions.begin(), scene.reactions.end(),
                                   [&](const ReactionSpec& s) { return s.name == name; });
    if (name.empty() || name.find_first_of(",\"\n") != std::string::npos || taken)
      r.error(ptr + "/reaction", taken ? "duplicate reaction name" : "invalid reaction name",
              "a non-empty name without commas, quotes or line breaks, unique among the reactions",
              "\"" + name + "\"", "core (boundary condition)");
    else
      scene.reactions.push_back({i, name});
  }
}

}  // namespace

SceneSection boundary_conditions_section() {
  return {"boundary_conditions", "boundary_condition",
          "Keys every boundary condition node accepts besides its plugin's own (an entry of /boundary_conditions)",
          boundary_condition_schema, read_boundary_conditions};
}

}  // namespace suffuse::detail
