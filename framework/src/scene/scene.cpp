// Reading a scene: the reader's shared helpers, the sections in reading
// order, the checks that span sections, and the entry points.
#include "suffuse/scene.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "common/fnv1a.hpp"
#include "scene/provided_fields.hpp"
#include "scene/scene_reader.hpp"

namespace suffuse {

namespace fs = std::filesystem;
using json = detail::Json;

namespace detail {

std::array<double, 3> to_array(const std::vector<double>& v) {
  std::array<double, 3> a{0, 0, 0};
  for (std::size_t i = 0; i < v.size() && i < 3; ++i) a[i] = v[i];
  return a;
}

std::string format(double v) {
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

std::string list(const std::vector<std::string>& names) {
  std::string s = "{";
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
  return s + "}";
}

const std::vector<SceneSection>& scene_sections() {
  static const std::vector<SceneSection> sections = {
      top_level_section(), grid_section(),   shape_function_section(),      time_section(),   materials_section(),
      liquids_section(),   bodies_section(), boundary_conditions_section(), outputs_section(),
      factor_of_safety_section(), failure_section()};
  return sections;
}

bool SceneReader::require(const std::string& key) {
  if (root.contains(key)) return true;
  error("/" + key, "missing required section", "an object", "nothing", "core (scene)");
  return false;
}

namespace {

// A plugin no library on the search path registers: say where to add one.
constexpr const char* kUnknownPlugin =
    "unknown plugin (no library found registers it; `suffuse plugins` lists what was found; add its library "
    "with the scene's \"plugin_paths\" or $SUFFUSE_PLUGIN_PATH)";

}  // namespace

PluginNode SceneReader::plugin_node(const Json& node, const std::string& ptr, PluginKind kind,
                                    const std::set<std::string>& core_keys) {
  PluginNode result;
  result.pointer = ptr;
  const std::vector<std::string> valid = registry.names_of(kind);
  const std::string kind_name = to_string(kind);
  const std::string article = std::string("aeiou").find(kind_name.front()) != std::string::npos ? "an " : "a ";
  const std::string expected = article + kind_name + " plugin, one of " + list(valid);
  if (!node.is_object()) {
    error(ptr, "wrong type", "an object with a \"type\" key naming " + expected, show(node), "core");
    return result;
  }
  if (!node.contains("type")) {
    error(ptr + "/type", "missing plugin type", expected, "nothing", "core");
    return result;
  }
  const Json& type = node["type"];
  if (!type.is_string()) {
    error(ptr + "/type", "wrong type", expected, show(type), "core");
    return result;
  }
  result.type = type.get<std::string>();
  const PluginInfo* info = registry.find(result.type);
  if (!info) {
    std::string problem = kUnknownPlugin;
    // A library that failed to load is skipped in a directory scan: it may be the one.
    for (const std::string& w : skipped_libraries) problem += "; skipped: " + w;
    error(ptr + "/type", problem, expected, "\"" + result.type + "\"", "core");
    return result;
  }
  if (info->kind != kind) {
    error(ptr + "/type", "plugin of the wrong kind (" + to_string(info->kind) + ")", expected,
          "\"" + result.type + "\"", "core");
    return result;
  }
  std::set<std::string> reserved = core_keys;
  reserved.insert("type");
  const std::size_t before = diags.size();
  result.params = validate_object(node, info->schema(), ptr, result.type, dim, diags, reserved, base_dir);
  if (info->check && diags.size() == before && dim != 0) {
    std::vector<ParameterIssue> issues;
    try {
      issues = info->check(result.params, dim);
    } catch (const std::exception& e) {
      issues.push_back({"", std::string("the plugin's check failed: ") + e.what(), "", ""});
    }
    for (const ParameterIssue& issue : issues)
      error(issue.key.empty() ? ptr : pointer_append(ptr, issue.key), issue.problem, issue.expected, issue.found,
            result.type);
  }
  return result;
}

namespace {

// The scene as its values: keys sorted and every number a double, so that
// a file rewritten by another tool (jq writes 1.0e7 as 10000000; Python's
// json.dump with sort_keys reorders the keys) keeps its fingerprint. The
// scene itself keeps the file's order (Json), for messages.
nlohmann::json canonical(const Json& j) {
  if (j.is_object()) {
    nlohmann::json object = nlohmann::json::object();  // a std::map: sorted
    for (const auto& [key, value] : j.items()) object[key] = canonical(value);
    return object;
  }
  if (j.is_array()) {
    nlohmann::json array = nlohmann::json::array();
    for (const auto& value : j) array.push_back(canonical(value));
    return array;
  }
  if (j.is_number()) return j.get<double>();
  return j;
}

// FNV-1a of the scene's canonical JSON without what a restart may change.
std::string fingerprint_of(Json root) {
  root.erase("description");
  // When and how finely the factor of safety is found changes no step (a
  // run with it and one without step alike); whether it is found does (the
  // mechanism's point field).
  if (root.contains("factor_of_safety")) root["factor_of_safety"] = Json::object();
  // The failure criterion changes no step either: a run stops at a failure.
  root.erase("failure");
  if (root.contains("time") && root["time"].is_object())
    for (const char* key : {"end", "checkpoint_interval", "checkpoint_at_end"}) root["time"].erase(key);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a(canonical(root).dump())));
  return hex;
}

// Plugins that read point fields of other parts (a phase coupled to the
// erosion): each field must be one this scene's run provides.
void check_required_fields(SceneReader& r, const Scene& scene) {
  const std::vector<ProvidedField> fields = point_fields_of(scene, r.registry);
  std::vector<const PluginNode*> nodes = {&scene.shape_function};
  for (const MaterialSpec& m : scene.materials) {
    nodes.push_back(&m.phase);
    if (m.base) nodes.push_back(&*m.base);
    if (m.permeability) nodes.push_back(&*m.permeability);
    if (m.erosion) nodes.push_back(&*m.erosion);
  }
  for (const LiquidSpec& l : scene.liquids) nodes.push_back(&l.liquid);
  for (const PluginNode& bc : scene.boundary_conditions) nodes.push_back(&bc);
  for (const OutputSpec& o : scene.outputs) nodes.push_back(&o.writer);
  for (const PluginNode* node : nodes) {
    const PluginInfo* info = r.registry.find(node->type);
    if (!info || !info->required_fields) continue;
    std::vector<std::string> required;
    try {
      required = info->required_fields(node->params, r.dim);
    } catch (const std::exception& e) {
      r.error(node->pointer + "/type", std::string("the plugin's required_fields() failed: ") + e.what(), "", "",
              node->type);
    }
    for (const std::string& name : required) {
      auto f = std::find_if(fields.begin(), fields.end(), [&](const auto& p) { return p.name == name; });
      if (f == fields.end())
        r.error(node->pointer + "/type", "reads point field '" + name + "', which no part of the core provides",
                "a plugin reading fields of the core (see docs/plugins.md)", "\"" + node->type + "\"", node->type);
      else if (!f->provided)
        r.error(node->pointer + "/type", "reads point field '" + name + "', which this scene does not provide",
                "a scene where it exists: it comes from " + f->owner, "\"" + node->type + "\"", node->type);
    }
  }
}

}  // namespace

std::vector<Diagnostic> load_plugins_of(const Json& root, const fs::path& base_dir, PluginLoader& loader) {
  std::vector<Diagnostic> path_errors;
  if (root.is_object() && root.contains("plugin_paths") && root["plugin_paths"].is_array()) {
    const Json& paths = root["plugin_paths"];
    for (std::size_t i = 0; i < paths.size(); ++i) {
      if (!paths[i].is_string()) continue;  // reported by validation
      fs::path path = paths[i].get<std::string>();
      if (path.is_relative()) path = base_dir / path;
      std::error_code ec;
      if (!fs::exists(path, ec)) {
        path_errors.push_back({"/plugin_paths/" + std::to_string(i), "no such file or directory",
                               "a plugin library or a directory of them", path.string(), "core (scene)"});
        continue;
      }
      loader.load_path(path);  // a library that exists but fails to load is fatal
    }
  }
  for (const auto& path : PluginLoader::default_search_path()) loader.load_path(path);
  return path_errors;
}

Scene read_scene(const Json& root, Registry& registry, const std::string& name, std::vector<Diagnostic> earlier,
                 std::vector<std::string> skipped_libraries, const fs::path& base_dir) {
  SceneReader r(root, registry, std::move(earlier));
  r.base_dir = base_dir;
  r.skipped_libraries = std::move(skipped_libraries);
  Scene scene;
  if (!root.is_object()) {
    r.error("", "wrong type", "a JSON object", show(root), "core");
    throw SceneError(name, r.diags);
  }
  for (const SceneSection& section : scene_sections()) section.read(r, scene);
  check_periodic_grid(r, scene);
  if (r.diags.empty()) check_required_fields(r, scene);
  if (!r.diags.empty()) throw SceneError(name, r.diags);
  scene.fingerprint = fingerprint_of(root);
  return scene;
}

}  // namespace detail

std::vector<CoreSection> core_sections() {
  std::vector<CoreSection> sections;
  for (const detail::SceneSection& s : detail::scene_sections())
    if (s.schema) sections.push_back({s.schema_name, s.description, s.schema()});
  return sections;
}

Scene parse_scene(const std::string& text, const std::string& name, const fs::path& base_dir, Registry& registry,
                  PluginLoader& loader) {
  const json root = detail::parse_scene_text(text, name);
  // Plugins first: their schemas are needed to validate the rest.
  std::vector<Diagnostic> path_errors = detail::load_plugins_of(root, base_dir, loader);
  Scene scene = detail::read_scene(root, registry, name, std::move(path_errors), loader.warnings(), base_dir);
  scene.name = fs::path(name).stem().string();
  return scene;
}

Scene load_scene(const fs::path& file, Registry& registry, PluginLoader& loader) {
  Scene scene =
      parse_scene(detail::read_scene_file(file), file.string(), fs::absolute(file).parent_path(), registry, loader);
  scene.file = file;
  scene.name = file.stem().string();
  return scene;
}

}  // namespace suffuse
