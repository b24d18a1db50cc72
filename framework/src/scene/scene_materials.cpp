// Materials (a phase, with its permeability and erosion laws) and liquids.
#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema phreatic_schema() {
  ParameterSchema s;
  s.number("drainage_head").with_unit("m").above(0).fallback(0.05).doc(
      "Above the phreatic surface: the pressure head below zero over which the pores drain, S = 1 / (1 + (psi / "
      "(gamma_w drainage_head))^2); smaller gives a sharper phreatic surface (docs/phreatic.md)");
  s.number("residual_conductivity").with_unit("-").above(0).at_most(1).fallback(1e-3).doc(
      "Relative conductivity of drained pores, k_r = residual + (1 - residual) S^3: what still flows above the "
      "phreatic surface, the method's known error (docs/phreatic.md)");
  return s;
}

void read_phreatic(SceneReader& r, const Json& node, const std::string& ptr, MaterialSpec& m) {
  const Parameters p = validate_object(node, phreatic_schema(), ptr, "core (material)", r.dim, r.diags);
  DrainageSpec d;
  if (p.has("drainage_head")) d.drainage_head = p.number("drainage_head");
  if (p.has("residual_conductivity")) d.residual_conductivity = p.number("residual_conductivity");
  m.phreatic = d;
}

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
    read_phase(r, node, ptr, {"permeability", "erosion", "phreatic"}, m.phase, m.base);
    if (node.is_object() && node.contains("permeability"))
      m.permeability = r.plugin_node(node["permeability"], ptr + "/permeability", PluginKind::PermeabilityLaw);
    if (node.is_object() && node.contains("erosion"))
      m.erosion = r.plugin_node(node["erosion"], ptr + "/erosion", PluginKind::ErosionLaw);
    if (node.is_object() && node.contains("phreatic")) read_phreatic(r, node["phreatic"], ptr + "/phreatic", m);
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
  return {"materials", "phreatic",
          "A material's optional \"phreatic\" node (/materials/NAME/phreatic, beside its phase's parameters, "
          "\"permeability\" and \"erosion\"): its pores drain above the phreatic surface, in explicit and "
          "quasi-static runs (docs/phreatic.md)",
          phreatic_schema, read_materials};
}

SceneSection liquids_section() {
  return {"liquids", "", "Named pore liquids: a liquid plugin node each", nullptr, read_liquids};
}

}  // namespace suffuse::detail
