// suffuse plugins, describe, schema and reference: what the plugins found
// and the scene's sections take, as text, JSON or the Markdown manual.
#include <filesystem>
#include <iostream>
#include <string>

#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <nlohmann/json.hpp>
#include <suffuse/parameters.hpp>
#include <suffuse/version.hpp>

#include "commands.hpp"

namespace fs = std::filesystem;

namespace suffuse::cli {

void load_default_plugins(suffuse::PluginLoader& loader) {
  for (const auto& path : suffuse::PluginLoader::default_search_path()) loader.load_path(path);
}

void print_schema_table(const std::string& title, const std::string& description,
                        const suffuse::ParameterSchema& schema) {
  std::cout << title << "\n  " << description << "\n";
  if (schema.params().empty()) {
    std::cout << "  (no parameters)\n";
    return;
  }
  std::cout << "\n";
  for (const suffuse::Param& p : schema.params()) {
    std::cout << "  " << p.name << "\n";
    std::cout << "      " << p.description << "\n";
    std::cout << "      type: " << p.expectation(0);
    if (p.default_value && p.type == suffuse::ParamType::Vector &&
        std::get<std::vector<double>>(*p.default_value).empty())
      std::cout << "; default: zeros";
    else if (p.default_value) std::cout << "; default: " << suffuse::to_string(*p.default_value);
    else if (p.optional) std::cout << "; optional";
    else std::cout << "; required";
    std::cout << "\n";
  }
}

int cmd_plugins() {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  for (const auto& lib : loader.libraries()) {
    std::cout << lib.path.string() << "  (built for suffuse " << lib.framework_version << ", ABI " << lib.abi_major
              << "." << lib.abi_minor << ")\n";
    for (const auto& name : lib.plugins) {
      const suffuse::PluginInfo* info = registry.find(name);
      std::cout << "  " << std::left << std::setw(20) << suffuse::to_string(info->kind) << std::setw(28) << name
                << info->description << "\n";
    }
  }
  return 0;
}

int cmd_describe(const std::string& name) {
  for (const auto& section : suffuse::core_sections()) {
    if (section.name == name) {
      print_schema_table("core section " + name, section.description, section.schema);
      return 0;
    }
  }
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  const suffuse::PluginInfo* info = registry.find(name);
  if (!info) {
    std::string names;
    for (const auto& [n, i] : registry.all()) names += (names.empty() ? "" : ", ") + n;
    throw suffuse::Error("no plugin or core section named '" + name + "'; known plugins: " + names);
  }
  print_schema_table(name + " (" + suffuse::to_string(info->kind) + ", from " + info->library + ")",
                     info->description, info->schema());
  return 0;
}

nlohmann::json schema_json(const suffuse::ParameterSchema& schema) {
  nlohmann::json params = nlohmann::json::array();
  for (const suffuse::Param& p : schema.params()) {
    nlohmann::json j = {{"name", p.name}, {"type", suffuse::to_string(p.type)}, {"unit", p.unit},
                        {"description", p.description}, {"expected", p.expectation(0)},
                        {"required", p.required()}};
    if (p.default_value) j["default"] = suffuse::to_string(*p.default_value);
    if (!p.choices.empty()) j["choices"] = p.choices;
    params.push_back(j);
  }
  return params;
}

int cmd_schema() {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  nlohmann::json out;
  out["suffuse_version"] = suffuse::framework_version;
  for (const auto& s : suffuse::core_sections())
    out["core"][s.name] = {{"description", s.description}, {"parameters", schema_json(s.schema)}};
  for (const auto& [name, info] : registry.all())
    out["plugins"][name] = {{"kind", suffuse::to_string(info.kind)}, {"description", info.description},
                            {"parameters", schema_json(info.schema())}};
  std::cout << out.dump(2) << "\n";
  return 0;
}

std::string markdown_table(const suffuse::ParameterSchema& schema) {
  if (schema.params().empty()) return "No parameters.\n";
  std::string t = "| key | expected | default | description |\n|---|---|---|---|\n";
  for (const suffuse::Param& p : schema.params()) {
    std::string def = p.default_value ? "`" + suffuse::to_string(*p.default_value) + "`"
                      : p.optional    ? "optional"
                                      : "**required**";
    if (def == "`[]`" && p.type == suffuse::ParamType::Vector) def = "zeros";
    t += "| `" + p.name + "` | " + p.expectation(0) + " | " + def + " | " + p.description + " |\n";
  }
  return t;
}

// The scene reference manual, generated from the schemas (docs/scene-reference.md).
int cmd_reference() {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  std::cout << "# Scene reference\n\n"
               "Generated by `suffuse reference` from the parameter schemas that the core and each plugin "
               "declare; do not edit by hand. Units are SI. A vector has one component per dimension unless "
               "stated. Every node that names a plugin has a `\"type\"` key; all other keys are checked against "
               "the plugin's schema and an unknown key is an error.\n\n"
               "A scene is one JSON object:\n\n"
               "```\n"
               "{ description, dimension, plugin_paths, gravity, damping, volumetric_strain,\n"
               "  grid: {...}, time: {...},\n"
               "  shape_function: { type: \"shape/...\", ... },\n"
               "  materials: { NAME: { type: \"phase/...\", ... }, ... },\n"
               "  bodies: [ { material: NAME, min, max, ... }, ... ],\n"
               "  boundary_conditions: [ { type: \"bc/...\", reaction, ... }, ... ],\n"
               "  outputs: [ { type: \"writer/...\", interval, ... }, ... ] }\n"
               "```\n\n## Core sections\n\n";
  for (const auto& s : suffuse::core_sections())
    std::cout << "### " << s.name << "\n\n" << s.description << ".\n\n" << markdown_table(s.schema) << "\n";
  std::cout << "## Plugins\n\n";
  for (auto kind : suffuse::all_plugin_kinds) {
    for (const auto& name : registry.names_of(kind)) {
      const suffuse::PluginInfo* info = registry.find(name);
      std::cout << "### " << name << " (" << suffuse::to_string(kind) << ")\n\n"
                << info->description << ".\n\n" << markdown_table(info->schema()) << "\n";
    }
  }
  return 0;
}

}  // namespace suffuse::cli
