// Materials (a phase, with its permeability and erosion laws) and liquids.
#include "scene/scene_reader.hpp"

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
    read_phase(r, node, ptr, {"permeability", "erosion"}, m.phase, m.base);
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

void read_phase(SceneReader& r, const Json& node, const std::string& ptr, std::set<std::string> core_keys,
                PluginNode& phase, std::optional<PluginNode>& base) {
  const PluginInfo* info = node.is_object() && node.contains("type") && node["type"].is_string()
                               ? r.registry.find(node["type"].get<std::string>())
                               : nullptr;
  const bool wraps = info && info->kind == PluginKind::Phase && info->wraps_phase;
  if (wraps) core_keys.insert("base");
  phase = r.plugin_node(node, ptr, PluginKind::Phase, core_keys);
  if (!wraps) return;
  if (!node.contains("base")) {
    r.error(ptr + "/base", "missing base phase", "the phase node " + phase.type + " wraps (e.g. phase/mohr_coulomb)",
            "nothing", phase.type);
    return;
  }
  const Json& b = node["base"];
  const PluginInfo* base_info =
      b.is_object() && b.contains("type") && b["type"].is_string() ? r.registry.find(b["type"].get<std::string>()) : nullptr;
  if (base_info && base_info->kind == PluginKind::Phase && base_info->wraps_phase) {
    r.error(ptr + "/base/type", "a wrapping phase as a base", "a phase that wraps none (e.g. phase/modified_cam_clay)",
            "\"" + base_info->name + "\"", phase.type);
    return;
  }
  base = r.plugin_node(b, ptr + "/base", PluginKind::Phase);
}

SceneSection materials_section() {
  return {"materials", "",
          "Named materials: a phase plugin node each, with optional permeability and erosion law nodes", nullptr,
          read_materials};
}

SceneSection liquids_section() {
  return {"liquids", "", "Named pore liquids: a liquid plugin node each", nullptr, read_liquids};
}

}  // namespace suffuse::detail
