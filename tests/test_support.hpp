#pragma once
// Helpers shared by the tests: the bundled plugins and scenes built in code.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <span>
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

// Largest |a - b| relative to the largest |a|: how far a run drifted from a
// reference run of the same field (0 if both are zero).
inline double max_relative_difference(std::span<const double> a, std::span<const double> b) {
  double scale = 0, diff = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    scale = std::max(scale, std::abs(a[k]));
    diff = std::max(diff, std::abs(a[k] - b[k]));
  }
  return scale > 0 ? diff / scale : diff;
}

// A Scene from JSON, with the bundled plugins loaded into `registry`.
inline Scene scene_from(const nlohmann::json& j, Registry& registry) {
  PluginLoader loader(registry);
  return parse_scene(j.dump(), "test.json", source_dir(), registry, loader);
}

}  // namespace suffuse::test
