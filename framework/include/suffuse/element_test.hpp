#pragma once
// Element tests: one material point of any phase plugin driven along a
// stress-strain path, as a laboratory test drives a sample. Scene format and
// the paths: docs/soil-models.md ("Element tests").
//
// Signs: the scene and the output use soil mechanics, compression positive
// (p', q, eps_v, eps_s, axial strain, pressures); the phase works in the
// core's tension-positive stress.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "suffuse/plugin.hpp"
#include "suffuse/plugin_loader.hpp"
#include "suffuse/scene.hpp"

namespace suffuse {

enum class ElementPath { isotropic, oedometer, drained_triaxial, undrained_triaxial };

struct ElementStage {
  ElementPath path;
  double strain;   // volumetric (isotropic) or axial strain of the stage, compression positive [-]
  int increments;
};

struct ElementScene {
  std::string name;
  PluginNode material;
  double initial_pressure = 0;  // isotropic initial effective stress, compression positive [Pa]
  std::vector<ElementStage> stages;
};

// Reads and validates an element-test scene (plugins found as for a run);
// throws SceneError listing every problem, with JSON pointers.
ElementScene load_element_scene(const std::filesystem::path& file, Registry& registry, PluginLoader& loader);
ElementScene parse_element_scene(const std::string& text, const std::string& name,
                                 const std::filesystem::path& base_dir, Registry& registry, PluginLoader& loader);

// Runs the stages, writing one CSV row per increment (and the initial state)
// to `csv`, flushed as it goes: a path that cannot be followed (the lateral
// stress of a drained triaxial stage cannot be held, a value turns
// non-finite) throws Error naming the stage and the increment, and the rows
// written so far stay readable. Returns the number of increments run.
int run_element_test(const ElementScene& scene, const Registry& registry, std::ostream& csv);

// Schema of the element-test scene and of one stage, for `suffuse describe`.
ParameterSchema element_scene_schema();
ParameterSchema element_stage_schema();

}  // namespace suffuse
