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
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "suffuse/plugin.hpp"
#include "suffuse/plugin_loader.hpp"
#include "suffuse/scene.hpp"

namespace suffuse {

enum class ElementPath { isotropic, oedometer, drained_triaxial, undrained_triaxial, stress_controlled };
// The stage types' names in scenes, in the order of ElementPath.
const std::vector<std::string>& element_path_names();

// A field the phase reads (a coupling field such as the eroded fraction),
// ramped linearly over a stage from its value at the stage's start to
// `end_value`. Its "_increment" field, if the phase reads it, gets the
// change of each increment.
struct ElementInput {
  std::string field;
  double end_value;
};

// A limit on a reported field that ends a stage when the field reaches it
// (for example the erosion-induced shear strain of a suffosion test passing
// 10%: "runaway"); the run goes on with the next stage.
struct ElementLimit {
  std::string field;
  double value;
};

struct ElementStage {
  ElementPath path;
  double strain = 0;  // volumetric (isotropic) or axial strain of the stage, compression positive [-]
  int increments = 1;
  // stress_controlled: p' and q at the stage's end, reached linearly in
  // equal increments (compression positive) [Pa]; absent: held at the
  // stage's start (a hold). Or eta: q/p' at the end along the drained
  // triaxial stress path (the lateral stress held).
  std::optional<double> p, q, eta;
  std::vector<ElementInput> inputs;
  std::vector<ElementLimit> until;
};

// One path from the initial state: a scene without "cases" has one, unnamed.
struct ElementCase {
  std::string name;
  std::vector<ElementStage> stages;
};

struct ElementScene {
  std::string name;
  PluginNode material;
  std::optional<PluginNode> material_base;  // the phase `material` wraps, if it wraps one
  double initial_pressure = 0;  // isotropic initial effective stress, compression positive [Pa]
  std::vector<ElementCase> cases;
};

// A stage ended by one of its limits: where, and every reported value
// (inputs, p, q, the phase's fields) interpolated linearly to the crossing.
// Or, in a stage that has limits, a collapse (failure): the sample could not
// carry the stage's stress at `increment`; `at` holds the values of the
// increment before, and the case ends there.
struct ElementEvent {
  std::size_t stage;
  int increment;  // the CSV's increment (counted over all stages) at or past the limit, or the one that failed
  ElementLimit limit;
  std::vector<std::pair<std::string, double>> at;
  std::vector<std::string> inputs;  // the stage's input fields, named in message()
  bool failure = false;
  std::string reason;  // of a failure: the phase's error, if it raised one
  std::string message() const;
};

struct ElementResult {
  int increments = 0;
  std::vector<ElementEvent> events;
};

// Reads and validates an element-test scene (plugins found as for a run);
// throws SceneError listing every problem, with JSON pointers.
ElementScene load_element_scene(const std::filesystem::path& file, Registry& registry, PluginLoader& loader);
ElementScene parse_element_scene(const std::string& text, const std::string& name,
                                 const std::filesystem::path& base_dir, Registry& registry, PluginLoader& loader);

// Runs the stages of case `index`, writing one CSV row per increment (and
// the initial state) to `csv`, flushed as it goes: a path that cannot be
// followed (the lateral stress of a drained triaxial stage or the stress of
// a stress-controlled stage cannot be held, a value turns non-finite) throws
// Error naming the stage and the increment and saying "failure", and the
// rows written so far stay readable.
ElementResult run_element_test(const ElementScene& scene, std::size_t index, const Registry& registry,
                               std::ostream& csv);

// Schema of the element-test scene and of one stage, for `suffuse describe`.
ParameterSchema element_scene_schema();
ParameterSchema element_stage_schema();

}  // namespace suffuse
