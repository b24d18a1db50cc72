// Materials (a phase, with its permeability and erosion laws) and liquids.
#include "scene_reader.hpp"

namespace suffuse::detail {

namespace {

void read_materials(SceneReader& r, Scene& scene) {
  if (!r.require("materials")) return;
  const Json& materials = r.root["materials"];
  if (!materials.is_object() || materials.empty()) {
    r.error("/materials", "wrong type", "an object naming at least one material", show(materials), "core (scene)");
    return;
  }
  for (const auto& [name, node] : materials.items()) {
    MaterialSpec m;
    m.name = name;
    const std::string ptr = pointer_append("/materials", name);
    m.phase = r.plugin_node(node, ptr, PluginKind::Phase, {"permeability", "erosion"});
    if (node.is_object() && node.contains("permeability"))
      m.permeability = r.plugin_node(node["permeability"], ptr + "/permeability", PluginKind::PermeabilityLaw);
    if (node.is_object() && node.contains("erosion"))
      m.erosion = r.plugin_node(node["erosion"], ptr + "/erosion", PluginKind::ErosionLaw);
    scene.materials.push_back(std::move(m));
  }
}

void read_liquids(SceneReader& r, Scene& scene) {
  if (!r.root.contains("liquids")) return;
  const Json& liquids = r.root["liquids"];
  if (!liquids.is_object()) {
    r.error("/liquids", "wrong type", "an object naming liquids", show(liquids), "core (scene)");
    return;
  }
  for (const auto& [name, node] : liquids.items())
    scene.liquids.push_back({name, r.plugin_node(node, pointer_append("/liquids", name), PluginKind::Liquid)});
}

}  // namespace

SceneSection materials_section() {
  return {"materials", "",
          "Named materials: a phase plugin node each, with optional permeability and erosion law nodes", nullptr,
          read_materials};
}

SceneSection liquids_section() {
  return {"liquids", "", "Named pore liquids: a liquid plugin node each", nullptr, read_liquids};
}

}  // namespace suffuse::detail
