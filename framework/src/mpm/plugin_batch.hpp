#pragma once
// A plugin's work on a batch of a body's points, and what the run says when
// it fails: the plugin, its material, the points and the body ("phase
// phase/x of material 'm' (/materials/m) failed on material points 0 to 79
// of body 'bar': ..."). The step and the stage are added by the step
// (Simulation::timed). Phases, erosion laws and permeability laws all fail so.
#include <exception>
#include <string>

#include "mpm/domain.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

// `plugin`: what failed, e.g. "erosion law erosion/x of material 'm' (/materials/m/erosion)".
template <class Work>
void run_plugin_on_batch(const Domain& d, const BodyPoints& body, const PointRange& range, const std::string& plugin,
                         Work&& work) {
  try {
    work();
  } catch (const std::exception& error) {
    throw Error(plugin + " failed on material points " + std::to_string(d.first_point() + range.begin) + " to " +
                std::to_string(d.first_point() + range.end - 1) + " of body '" + body.name + "': " + error.what());
  }
}

// "<kind> <type> of material '<name>' (<pointer>)", the plugin as messages name it.
inline std::string plugin_of_material(const std::string& kind, const PluginNode& node, const std::string& material) {
  return kind + " " + node.type + " of material '" + material + "' (" + node.pointer + ")";
}

}  // namespace suffuse::detail
