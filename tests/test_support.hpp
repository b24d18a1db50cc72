#pragma once
// Helpers shared by the tests: the bundled plugins and scenes built in code.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>

namespace suffuse::test {

inline nlohmann::json read_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return nlohmann::json::parse(s.str());
}

inline std::filesystem::path source_dir() { return SUFFUSE_SOURCE_DIR; }

// A Scene from JSON, with the bundled plugins loaded into `registry`.
inline Scene scene_from(const nlohmann::json& j, Registry& registry) {
  PluginLoader loader(registry);
  return parse_scene(j.dump(), "test.json", source_dir(), registry, loader);
}

}  // namespace suffuse::test
