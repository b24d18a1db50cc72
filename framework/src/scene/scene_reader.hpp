#pragma once
// Reading a scene file: the state shared by every section (the JSON, the
// registry, the problems found so far) and the sections themselves. Each
// section is read next to the plugin kinds and core parameters it
// configures (scene_<section>.cpp); scene.cpp lists them in reading order.
#include <array>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "suffuse/scene.hpp"
#include "scene/validation.hpp"

namespace suffuse::detail {

class SceneReader {
 public:
  SceneReader(const Json& root, Registry& registry, std::vector<Diagnostic> earlier)
      : root(root), registry(registry), diags(std::move(earlier)) {}

  void error(std::string ptr, std::string problem, std::string expected, std::string found, std::string by) {
    diags.push_back({std::move(ptr), std::move(problem), std::move(expected), std::move(found), std::move(by)});
  }
  // True if the top level has `key`; otherwise reports it missing.
  bool require(const std::string& key);
  // Validates a plugin node of `kind` (its "type", its parameters against the
  // plugin's schema, the plugin's own check); `core_keys` are the core's.
  PluginNode plugin_node(const Json& node, const std::string& ptr, PluginKind kind,
                         const std::set<std::string>& core_keys = {});

  const Json& root;
  Registry& registry;
  std::vector<Diagnostic> diags;
  std::vector<std::string> skipped_libraries;  // files of plugin directories that did not load, and why
  std::filesystem::path base_dir;  // the scene file's directory: files a scene names are relative to it
  int dim = 0;           // 0 until /dimension is valid
  bool grid_ok = false;  // the grid is valid, so bodies can be checked against it
};

// A phase node (a material's, or an element test's) with its "base" if its
// plugin wraps one; `core_keys` are the core's other keys of the node.
// A body's gradation ("gradation" file or inline "gradation_points") and the
// fines content it gives ("fines_content_from_gradation"); `b` holds the
// body's validated parameters, read from `node`.
void read_gradation(SceneReader& r, const Json& node, const Parameters& b, const std::string& ptr, BodySpec& body);

void read_phase(SceneReader& r, const Json& node, const std::string& ptr, std::set<std::string> core_keys,
                PluginNode& phase, std::optional<PluginNode>& base);

// One section of a scene file.
struct SceneSection {
  std::string key;          // top-level key ("" for the top level itself)
  std::string schema_name;  // name of its core schema for `suffuse describe` ("" if none)
  std::string description;
  std::function<ParameterSchema()> schema;  // the core's parameters of the section (or of each entry)
  std::function<void(SceneReader&, Scene&)> read;
};

SceneSection top_level_section();
SceneSection grid_section();
// After every section: what a periodic grid does not wrap yet (scene_grid.cpp).
void check_periodic_grid(SceneReader& r, const Scene& scene);
SceneSection shape_function_section();
SceneSection time_section();
SceneSection materials_section();
SceneSection liquids_section();
SceneSection bodies_section();
SceneSection boundary_conditions_section();
SceneSection outputs_section();
SceneSection factor_of_safety_section();
SceneSection failure_section();

// The sections in reading order: the top level (dimension) first, the grid
// before the bodies checked against it, materials and liquids before the
// bodies that name them.
const std::vector<SceneSection>& scene_sections();

// Loads the libraries of a scene's "plugin_paths" (relative to base_dir),
// then the default search path; returns the paths that do not exist.
std::vector<Diagnostic> load_plugins_of(const Json& root, const std::filesystem::path& base_dir, PluginLoader& loader);

// Reads and validates a whole scene; throws SceneError listing every problem.
Scene read_scene(const Json& root, Registry& registry, const std::string& name, std::vector<Diagnostic> earlier,
                 std::vector<std::string> skipped_libraries = {}, const std::filesystem::path& base_dir = {});

// Shared by the sections.
std::array<double, 3> to_array(const std::vector<double>& v);
std::string format(double v);  // numbers in messages: as short as possible, as precise as needed
std::string list(const std::vector<std::string>& names);  // {a, b, c}

}  // namespace suffuse::detail
