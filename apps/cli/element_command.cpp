// suffuse element: drives one point of a phase along a test path.
#include <filesystem>
#include <iostream>
#include <string>

#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <fstream>
#include <suffuse/element_test.hpp>
#include <suffuse/version.hpp>

#include "commands.hpp"

namespace fs = std::filesystem;

namespace suffuse::cli {

int cmd_element(const fs::path& scene_file, const fs::path& output, bool quiet) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::ElementScene scene = suffuse::load_element_scene(scene_file, registry, loader);
  fs::create_directories(output);
  if (!quiet)
    std::cout << "suffuse " << suffuse::framework_version << ": element test of " << scene.material.type
              << (scene.material_base ? " around " + scene.material_base->type : std::string()) << ", "
              << scene.cases.size() << " case(s)\n";
  for (std::size_t c = 0; c < scene.cases.size(); ++c) {
    const std::string& name = scene.cases[c].name;
    const fs::path file = output / (scene.name + (name.empty() ? "" : "." + name) + ".element.csv");
    std::ofstream csv(file);
    if (!csv) throw suffuse::Error("cannot write " + file.string());
    const suffuse::ElementResult result = suffuse::run_element_test(scene, c, registry, csv);
    if (quiet) continue;
    std::cout << "  " << (name.empty() ? "" : name + ": ") << result.increments << " increments, rows in "
              << file.string() << "\n";
    for (const suffuse::ElementEvent& e : result.events) std::cout << "    " << e.message() << "\n";
  }
  return 0;
}

}  // namespace suffuse::cli
