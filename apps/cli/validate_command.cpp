// suffuse validate: checks a scene, builds the run it describes (memory and
// time step checked as `run` does) and prints what it would be; writes nothing.
#include <filesystem>
#include <iostream>
#include <string>

#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <cmath>
#include <suffuse/simulation.hpp>

#include "gradation_command.hpp"

#include "commands.hpp"

namespace fs = std::filesystem;

namespace suffuse::cli {

// The internal-stability criteria on each body's gradation, and a warning
// where an erosion law erodes a soil that every criterion finds stable.
void print_gradations(const suffuse::Scene& scene) {
  for (const suffuse::BodySpec& body : scene.bodies) {
    if (!body.internal_stability) continue;
    const suffuse::InternalStability& s = *body.internal_stability;
    std::cout << "\nbody '" << body.name << "': gradation " << body.gradation_source << "\n";
    suffuse::gradation_command::print_table(std::cout, s, "  ");
    if (body.fines_content_from_gradation)
      std::cout << "  fines_content = " << body.fines_content << " (fines_content_from_gradation)\n";
    const suffuse::MaterialSpec& material = scene.materials[body.material];
    if (material.erosion && s.stable())
      std::cout << "warning: body '" << body.name << "': every applicable criterion finds its gradation stable, yet "
                << "material '" << material.name << "' erodes it (" << material.erosion->type
                << "): suffusion is not expected in this soil\n";
  }
}

// A body whose erodible fines, all washed out, would leave a porosity no soil
// skeleton has (sands stay below about 0.5, the loosest clays near 0.9):
// fines content 0.99 in a soil of porosity 0.9 ends at 0.999.
void warn_about_open_skeletons(const suffuse::Scene& scene, std::ostream& out) {
  for (const suffuse::BodySpec& body : scene.bodies) {
    if (!body.liquid || !scene.materials[body.material].erosion) continue;
    const double n = body.porosity;
    const double final_porosity = n + (1 - n) * (body.fines_content - body.ultimate_fines_content);
    if (final_porosity > 0.9)
      out << "warning: body '" << body.name << "': washing out its erodible fines (fines_content "
          << body.fines_content << " - ultimate " << body.ultimate_fines_content << " of the solid) would leave "
          << "porosity " << final_porosity << ", more open than any soil skeleton (above 0.9): check porosity and "
          << "fines_content\n";
  }
}

int cmd_validate(const fs::path& scene_file) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::Scene scene = suffuse::load_scene(scene_file, registry, loader);
  // What the run would be: building it checks memory and the time step, as
  // `run` does, and gives the numbers (nothing is written).
  const suffuse::Simulation sim(scene, registry, 1);
  std::cout << scene_file.string() << " is valid: " << scene.dim << "D, " << scene.materials.size()
            << " material(s), " << scene.bodies.size() << " body(ies), " << scene.boundary_conditions.size()
            << " boundary condition(s), " << scene.outputs.size() << " output(s)\n";
  print_gradations(scene);
  warn_about_open_skeletons(scene, std::cout);
  if (scene.integration == suffuse::TimeIntegration::quasi_static) {
    // Steps adapt: only the largest is known, and so the fewest steps.
    const double largest = scene.quasi_static.max_dt > 0 ? scene.quasi_static.max_dt : sim.dt();
    std::cout << "  run: " << sim.point_count() << " material points, quasi-static, first dt = " << sim.dt()
              << " s, at most " << largest << " s: at least "
              << std::llround(std::ceil(scene.end_time / largest - 1e-9)) << " steps to t = " << scene.end_time
              << " s\n";
    return 0;
  }
  std::cout << "  run: " << sim.point_count() << " material points, dt = " << sim.dt() << " s ("
            << (scene.dt ? "fixed" : "automatic") << "), " << std::llround(std::ceil(scene.end_time / sim.dt() - 1e-9))
            << " steps to t = " << scene.end_time << " s\n";
  return 0;
}

}  // namespace suffuse::cli
