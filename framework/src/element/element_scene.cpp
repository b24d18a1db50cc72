// Element-test scenes: reading and validating them (suffuse element).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "mpm/material_phase.hpp"
#include "scene/scene_reader.hpp"
#include "suffuse/element_test.hpp"
#include "suffuse/error.hpp"

namespace suffuse {

namespace fs = std::filesystem;
using detail::Json;

namespace {

const char* const by_scene = "core (element)";
const char* const by_stage = "core (element stage)";

// What a stage may name: the coupling fields the phase reads (inputs) and
// every scalar field the CSV reports (limits).
struct SampleFields {
  std::vector<std::string> inputs, reported;
};

SampleFields sample_fields(const Registry& registry, const PluginNode& material, const std::optional<PluginNode>& base) {
  SampleFields f;
  PointSet points(3);
  for (const PluginNode* node : {&material, base ? &*base : nullptr}) {
    const PluginInfo* info = node ? registry.find(node->type) : nullptr;
    if (!info || !info->required_fields) continue;
    for (const std::string& name : info->required_fields(node->params, 3)) {
      if (points.find(name)) continue;
      points.add_field({name, FieldKind::Scalar, "-", "", false});
      if (!name.ends_with("_increment")) f.inputs.push_back(name);
    }
  }
  const FieldId first = points.field_count();
  detail::MaterialPhase phase(registry, material, base, 3);
  phase.add_fields(points);
  f.reported = {"eps_v", "eps_s", "p", "q", "eta"};
  f.reported.insert(f.reported.end(), f.inputs.begin(), f.inputs.end());
  for (FieldId id = first; id < points.field_count(); ++id)
    if (points.info(id).kind == FieldKind::Scalar && points.info(id).output) f.reported.push_back(points.info(id).name);
  return f;
}

// A stage's "inputs": {"field": end value, ...}, each a field the phase reads.
std::vector<ElementInput> read_inputs(const Json& node, const std::string& ptr, const std::vector<std::string>& fields,
                                      detail::SceneReader& r) {
  std::vector<ElementInput> inputs;
  if (!node.is_object()) {
    r.error(ptr, "wrong type", "an object of field names and their values at the stage's end", detail::show(node),
            by_stage);
    return inputs;
  }
  for (const auto& [name, value] : node.items()) {
    if (std::find(fields.begin(), fields.end(), name) == fields.end())
      r.error(ptr + "/" + name, "not a field the material reads",
              fields.empty() ? std::string("no inputs (the material reads no other part's field)")
                             : "one of " + detail::list(fields),
              name, by_stage);
    else if (!value.is_number() || !std::isfinite(value.get<double>()))
      r.error(ptr + "/" + name, "wrong type", "a finite number (the field's value at the stage's end)",
              detail::show(value), by_stage);
    else if (name == coupling::eroded_fraction && value.get<double>() >= 1)
      r.error(ptr + "/" + name, "value out of range", "a number < 1 (a fraction of the solid's initial mass)",
              detail::format(value.get<double>()), by_stage);
    else
      inputs.push_back({name, value.get<double>()});
  }
  return inputs;
}

// A stage's "until": {"field": limit, ...}, each a field of the CSV.
std::vector<ElementLimit> read_limits(const Json& node, const std::string& ptr, const std::vector<std::string>& fields,
                                      detail::SceneReader& r) {
  std::vector<ElementLimit> limits;
  if (!node.is_object()) {
    r.error(ptr, "wrong type", "an object of reported fields and the values that end the stage", detail::show(node),
            by_stage);
    return limits;
  }
  for (const auto& [name, value] : node.items()) {
    if (std::find(fields.begin(), fields.end(), name) == fields.end())
      r.error(ptr + "/" + name, "not a reported field", "one of " + detail::list(fields), name, by_stage);
    else if (!value.is_number() || !std::isfinite(value.get<double>()))
      r.error(ptr + "/" + name, "wrong type", "a finite number (the value that ends the stage)", detail::show(value),
              by_stage);
    else if ((name == "q" || name == "eta" || name == "eps_s") && value.get<double>() < 0)
      r.error(ptr + "/" + name, "value out of range", "a number >= 0 (the CSV reports q, eta and eps_s as magnitudes)",
              detail::format(value.get<double>()), by_stage);
    else
      limits.push_back({name, value.get<double>()});
  }
  return limits;
}

std::vector<ElementStage> read_path(const Json& path, const std::string& path_ptr, const SampleFields& fields,
                                    detail::SceneReader& r, bool may_be_empty) {
  std::vector<ElementStage> stages;
  if (!path.is_array() || (path.empty() && !may_be_empty)) {
    r.error(path_ptr, "wrong type", "a non-empty array of stages", detail::show(path), by_scene);
    return stages;
  }
  for (std::size_t i = 0; i < path.size(); ++i) {
    const std::string ptr = path_ptr + "/" + std::to_string(i);
    const Parameters s =
        detail::validate_object(path[i], element_stage_schema(), ptr, by_stage, 3, r.diags, {"inputs", "until"});
    if (!s.has("type") || !s.has("increments")) continue;  // reported by validate_object
    ElementStage stage;
    const std::string& type = s.string("type");
    stage.path = static_cast<ElementPath>(std::find(element_path_names().begin(), element_path_names().end(), type) -
                                          element_path_names().begin());
    stage.increments = static_cast<int>(s.integer("increments"));
    const bool stress_controlled = stage.path == ElementPath::stress_controlled;
    if (s.has("strain") && !stress_controlled) stage.strain = s.number("strain");
    if (!s.has("strain") && !stress_controlled)
      r.error(ptr + "/strain", "missing key", "the stage's strain (number, compression positive)", "absent", by_stage);
    if (stress_controlled && s.has("strain"))
      r.error(ptr + "/strain", "not a key of this stage", "p and q, or eta (a stress_controlled stage's strains follow)",
              detail::format(s.number("strain")), by_stage);
    for (const char* key : {"p", "q", "eta"})
      if (s.has(key) && !stress_controlled)
        r.error(ptr + "/" + key, "not a key of this stage", "strain (" + type + " is strain-controlled)",
                detail::format(s.number(key)), by_stage);
    if (s.has("eta") && (s.has("p") || s.has("q")))
      r.error(ptr + "/eta", "two stress targets", "either eta (along the drained path) or p and q", "eta with p or q",
              by_stage);
    if (stress_controlled) stage.p = s.maybe_number("p"), stage.q = s.maybe_number("q"), stage.eta = s.maybe_number("eta");
    if (path[i].is_object() && path[i].contains("inputs"))
      stage.inputs = read_inputs(path[i]["inputs"], ptr + "/inputs", fields.inputs, r);
    if (path[i].is_object() && path[i].contains("until"))
      stage.until = read_limits(path[i]["until"], ptr + "/until", fields.reported, r);
    stages.push_back(std::move(stage));
  }
  return stages;
}

}  // namespace

const std::vector<std::string>& element_path_names() {
  static const std::vector<std::string> names = {"isotropic", "oedometer", "drained_triaxial", "undrained_triaxial",
                                                 "stress_controlled"};
  return names;
}

ParameterSchema element_scene_schema() {
  ParameterSchema s;
  s.string("description").fallback(std::string()).doc("What the test shows");
  s.string_list("plugin_paths").fallback(std::vector<std::string>{}).doc(
      "Plugin libraries or directories searched first, relative to the scene file");
  s.number("initial_pressure").with_unit("Pa").above(0).doc(
      "Isotropic initial effective stress p'_0, compression positive; the phase's initialise() then sets its state");
  return s;
}

ParameterSchema element_stage_schema() {
  ParameterSchema s;
  s.choice("type", element_path_names()).doc(
      "isotropic: equal normal strains; oedometer: axial strain, no lateral strain; drained_triaxial: axial "
      "strain at the lateral stress of the stage's start; undrained_triaxial: axial strain at constant volume; "
      "stress_controlled: axial and lateral stresses driven to p and q, or to eta along the drained path (held "
      "where absent: a hold), the strains follow");
  s.number("strain").with_unit("-").may_be_absent().doc(
      "Strain of the stage, compression positive (negative: unloading): volumetric for isotropic, axial otherwise; "
      "required by every type but stress_controlled");
  s.integer("increments").with_unit("-").at_least(1).at_most(10000000).fallback(100LL).doc(
      "Increments of the stage (equal strain, stress and input steps)");
  s.number("p").with_unit("Pa").above(0).may_be_absent().doc(
      "stress_controlled: mean effective stress p' at the stage's end, compression positive (absent: held)");
  s.number("q").with_unit("Pa").may_be_absent().doc(
      "stress_controlled: deviator stress q = sigma_axial - sigma_lateral at the stage's end, compression positive, "
      "negative in extension (absent: held)");
  s.number("eta").with_unit("-").above(-1.5).below(3).may_be_absent().doc(
      "stress_controlled: stress ratio q/p' at the stage's end, reached along the drained triaxial path (the "
      "lateral stress held, dp' = dq/3), instead of p and q");
  return s;
}

ElementScene parse_element_scene(const std::string& text, const std::string& name, const fs::path& base_dir,
                                 Registry& registry, PluginLoader& loader) {
  const Json root = detail::parse_scene_text(text, name);
  detail::SceneReader r(root, registry, detail::load_plugins_of(root, base_dir, loader));
  r.skipped_libraries = loader.warnings();
  r.dim = 3;
  ElementScene scene;
  scene.name = fs::path(name).stem().string();
  if (!root.is_object()) {
    r.error("", "wrong type", "a JSON object", detail::show(root), by_scene);
    throw SceneError(name, r.diags);
  }
  const Parameters top =
      detail::validate_object(root, element_scene_schema(), "", by_scene, 3, r.diags, {"material", "path", "cases"});
  if (top.has("initial_pressure")) scene.initial_pressure = top.number("initial_pressure");
  if (r.require("material")) detail::read_phase(r, root["material"], "/material", {}, scene.material, scene.material_base);
  // The stages name fields of the phase: read them once the phase is valid.
  if (!r.diags.empty()) throw SceneError(name, r.diags);
  const SampleFields fields = sample_fields(registry, scene.material, scene.material_base);
  const bool has_cases = root.contains("cases");
  std::vector<ElementStage> common;
  if (root.contains("path") || !has_cases)
    if (r.require("path")) common = read_path(root["path"], "/path", fields, r, has_cases);
  if (!has_cases) {
    scene.cases.push_back({"", std::move(common)});
  } else if (!root["cases"].is_array() || root["cases"].empty()) {
    r.error("/cases", "wrong type", "a non-empty array of {\"name\", \"path\"}, each run after /path",
            detail::show(root["cases"]), by_scene);
  } else {
    const Json& cases = root["cases"];
    for (std::size_t c = 0; c < cases.size(); ++c) {
      const std::string ptr = "/cases/" + std::to_string(c);
      const Json& node = cases[c];
      if (!node.is_object() || !node.contains("name") || !node["name"].is_string() || !node.contains("path")) {
        r.error(ptr, "wrong type", "an object with a \"name\" (string) and a \"path\"", detail::show(node), by_scene);
        continue;
      }
      for (const auto& [key, value] : node.items())
        if (key != "name" && key != "path") r.error(ptr + "/" + key, "unknown key", "name, path", key, by_scene);
      ElementCase one{node["name"].get<std::string>(), common};
      const std::string& case_name = one.name;
      const bool taken = std::any_of(scene.cases.begin(), scene.cases.end(),
                                     [&](const ElementCase& other) { return other.name == case_name; });
      if (case_name.empty() || case_name.find_first_of("/\\ ") != std::string::npos || taken)
        r.error(ptr + "/name", taken ? "duplicate case name" : "invalid case name",
                "a unique name for the case's CSV, without spaces or slashes", "\"" + case_name + "\"", by_scene);
      for (ElementStage& s : read_path(node["path"], ptr + "/path", fields, r, false)) one.stages.push_back(std::move(s));
      scene.cases.push_back(std::move(one));
    }
  }
  if (!r.diags.empty()) throw SceneError(name, r.diags);
  return scene;
}

ElementScene load_element_scene(const fs::path& file, Registry& registry, PluginLoader& loader) {
  return parse_element_scene(detail::read_scene_file(file), file.string(), fs::absolute(file).parent_path(), registry,
                             loader);
}

}  // namespace suffuse
