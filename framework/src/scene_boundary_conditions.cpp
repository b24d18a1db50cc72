// Boundary conditions: a list of boundary-condition plugin nodes.
#include "scene_reader.hpp"

namespace suffuse::detail {

namespace {

void read_boundary_conditions(SceneReader& r, Scene& scene) {
  if (!r.root.contains("boundary_conditions")) return;
  const Json& bcs = r.root["boundary_conditions"];
  if (!bcs.is_array()) {
    r.error("/boundary_conditions", "wrong type", "array of boundary condition nodes", show(bcs), "core (scene)");
    return;
  }
  for (std::size_t i = 0; i < bcs.size(); ++i)
    scene.boundary_conditions.push_back(
        r.plugin_node(bcs[i], "/boundary_conditions/" + std::to_string(i), PluginKind::BoundaryCondition));
}

}  // namespace

SceneSection boundary_conditions_section() {
  return {"boundary_conditions", "", "Boundary conditions: a list of boundary condition plugin nodes", nullptr,
          read_boundary_conditions};
}

}  // namespace suffuse::detail
