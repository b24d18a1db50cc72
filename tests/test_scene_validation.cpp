// Scene validation: every diagnostic names its JSON pointer, the problem, what
// was expected, what was found and who declared the parameter. Each test starts
// from a small valid scene (a 2D elastic column) and breaks one thing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "suffuse/diagnostics.hpp"
#include "suffuse/scene.hpp"
#include <suffuse/element_test.hpp>

#include "test_support.hpp"

namespace {

using nlohmann::json;
using suffuse::Diagnostic;
using suffuse::SceneError;
using suffuse::test::boundary_condition;
using suffuse::test::boundary_condition_pointer;

// A valid 2D elastic column 10 m high on a 1 x 42 grid of 0.25 m cells. The
// time step's cfl and the material's poisson_ratio are left to their defaults.
json base_scene() {
  return json::parse(R"({
    "description": "elastic column",
    "dimension": 2,
    "gravity": [0.0, -9.81],
    "damping": 0.1,
    "grid": { "origin": [0.0, 0.0], "cell_size": [0.25, 0.25], "cells": [1, 42] },
    "shape_function": { "type": "shape/linear" },
    "materials": {
      "soil": { "type": "phase/linear_elastic", "density": 2000.0, "youngs_modulus": 1.0e7 }
    },
    "bodies": [
      { "name": "column", "material": "soil", "min": [0.0, 0.0], "max": [0.25, 10.0], "points_per_cell": 2 }
    ],
    "boundary_conditions": [
      { "type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0 },
      { "type": "bc/velocity", "face": "left", "vx": 0.0 },
      { "type": "bc/velocity", "face": "right", "vx": 0.0 }
    ],
    "time": { "end": 8.0 },
    "outputs": [ { "type": "writer/vtk_particles", "interval": 0.4 } ]
  })");
}

suffuse::Scene parse_text(const std::string& text) {
  // Only the bundled plugins: the expected plugin lists below name exactly those.
  ::unsetenv("SUFFUSE_PLUGIN_PATH");
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  return suffuse::parse_scene(text, "test.json", SUFFUSE_SOURCE_DIR, registry, loader);
}

// Parses `text`, which must be rejected with a SceneError, and returns its
// diagnostics. Also checks that what() names every diagnostic's pointer.
std::vector<Diagnostic> diagnostics_of_text(const std::string& text) {
  try {
    parse_text(text);
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("scene test.json is invalid"), std::string::npos) << what;
    for (const Diagnostic& d : e.diagnostics()) {
      const std::string shown = (d.pointer.empty() ? "/" : d.pointer) + ": ";
      EXPECT_NE(what.find(shown), std::string::npos) << "what() does not name " << shown << "\n" << what;
      EXPECT_NE(what.find(d.message()), std::string::npos) << what;
    }
    return e.diagnostics();
  }
  ADD_FAILURE() << "the scene was accepted";
  return {};
}

std::vector<Diagnostic> diagnostics_of(const json& scene) { return diagnostics_of_text(scene.dump(2)); }

std::string describe(const std::vector<Diagnostic>& diags) {
  std::string s;
  for (const Diagnostic& d : diags) s += "\n  " + d.message();
  return s;
}

void expect_diagnostic(const Diagnostic& actual, const Diagnostic& expected) {
  EXPECT_EQ(actual.pointer, expected.pointer);
  EXPECT_EQ(actual.problem, expected.problem) << "at " << expected.pointer;
  EXPECT_EQ(actual.expected, expected.expected) << "at " << expected.pointer;
  EXPECT_EQ(actual.found, expected.found) << "at " << expected.pointer;
  EXPECT_EQ(actual.declared_by, expected.declared_by) << "at " << expected.pointer;
}

// The scene must be rejected with exactly these diagnostics, in this order.
void expect_diagnostics(const json& scene, const std::vector<Diagnostic>& expected) {
  const std::vector<Diagnostic> diags = diagnostics_of(scene);
  ASSERT_EQ(diags.size(), expected.size()) << describe(diags);
  for (std::size_t i = 0; i < diags.size(); ++i) expect_diagnostic(diags[i], expected[i]);
}

const char* const kPhaseExpected = "a phase plugin, one of {phase/linear_elastic, phase/modified_cam_clay, phase/mohr_coulomb, phase/suffosion}";
const char* const kUnknownPlugin =
    "unknown plugin (no library found registers it; `suffuse plugins` lists what was found; add its library "
    "with the scene's \"plugin_paths\" or $SUFFUSE_PLUGIN_PATH)";

TEST(SceneValidation, ValidBaseSceneParsesIntoTypedValues) {
  json j = base_scene();
  // A second material, sorted before "soil", so the body's index is not trivially 0.
  j["materials"]["clay"] = {{"type", "phase/linear_elastic"}, {"density", 1800.0}, {"youngs_modulus", 5.0e6},
                            {"poisson_ratio", 0.3}};
  const suffuse::Scene s = parse_text(j.dump());

  EXPECT_EQ(s.name, "test");
  EXPECT_EQ(s.description, "elastic column");
  EXPECT_EQ(s.dim, 2);
  EXPECT_DOUBLE_EQ(s.gravity[0], 0.0);
  EXPECT_DOUBLE_EQ(s.gravity[1], -9.81);
  EXPECT_DOUBLE_EQ(s.damping, 0.1);
  EXPECT_DOUBLE_EQ(s.grid_cell_size[0], 0.25);
  EXPECT_DOUBLE_EQ(s.grid_cell_size[1], 0.25);
  EXPECT_EQ(s.grid_cells[0], 1);
  EXPECT_EQ(s.grid_cells[1], 42);
  EXPECT_DOUBLE_EQ(s.end_time, 8.0);
  EXPECT_FALSE(s.dt.has_value());
  EXPECT_DOUBLE_EQ(s.cfl, 0.5);  // default
  EXPECT_EQ(s.shape_function.type, "shape/linear");
  EXPECT_EQ(s.shape_function.pointer, "/shape_function");

  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "clay");
  EXPECT_EQ(s.materials[1].name, "soil");
  EXPECT_EQ(s.materials[1].phase.type, "phase/linear_elastic");
  EXPECT_EQ(s.materials[1].phase.pointer, "/materials/soil");
  EXPECT_DOUBLE_EQ(s.materials[1].phase.params.number("density"), 2000.0);
  EXPECT_DOUBLE_EQ(s.materials[1].phase.params.number("youngs_modulus"), 1.0e7);
  EXPECT_DOUBLE_EQ(s.materials[1].phase.params.number("poisson_ratio"), 0.0);  // default
  EXPECT_DOUBLE_EQ(s.materials[0].phase.params.number("poisson_ratio"), 0.3);

  ASSERT_EQ(s.bodies.size(), 1u);
  EXPECT_EQ(s.bodies[0].name, "column");
  EXPECT_EQ(s.bodies[0].material, 1u);
  EXPECT_EQ(s.bodies[0].points_per_cell, 2);
  EXPECT_DOUBLE_EQ(s.bodies[0].max[1], 10.0);
  EXPECT_DOUBLE_EQ(s.bodies[0].velocity[0], 0.0);

  ASSERT_EQ(s.boundary_conditions.size(), 3u);
  EXPECT_EQ(s.boundary_conditions[1].pointer, "/boundary_conditions/1");
  EXPECT_EQ(s.boundary_conditions[1].params.string("face"), "left");
  EXPECT_FALSE(s.boundary_conditions[1].params.has("vy"));

  ASSERT_EQ(s.outputs.size(), 1u);
  EXPECT_EQ(s.outputs[0].writer.type, "writer/vtk_particles");
  ASSERT_TRUE(s.outputs[0].interval.has_value());
  EXPECT_DOUBLE_EQ(*s.outputs[0].interval, 0.4);
  EXPECT_TRUE(s.outputs[0].writer.params.boolean("compress"));  // default
}

TEST(SceneValidation, BundledExampleScenesAreValid) {
  for (const char* file : {"share/scenes/self_weight_column.json", "share/scenes/elastic_bar.json"}) {
    ::unsetenv("SUFFUSE_PLUGIN_PATH");
    suffuse::Registry registry;
    suffuse::PluginLoader loader(registry);
    EXPECT_NO_THROW(suffuse::load_scene(std::string(SUFFUSE_SOURCE_DIR) + "/" + file, registry, loader)) << file;
  }
}

TEST(SceneValidation, UnknownKeyInPluginNode) {
  json j = base_scene();
  j["materials"]["soil"]["youngs"] = 1.0e7;
  expect_diagnostics(j, {{"/materials/soil/youngs", "unknown key",
                          "one of {density, youngs_modulus, poisson_ratio, tension_cutoff, separation, erosion, permeability, phreatic, type}", "\"youngs\"",
                          "phase/linear_elastic"}});
}

TEST(SceneValidation, MisspelledRequiredKeyGivesUnknownAndMissing) {
  json j = base_scene();
  j["materials"]["soil"].erase("youngs_modulus");
  j["materials"]["soil"]["youngs"] = 1.0e7;
  expect_diagnostics(j, {{"/materials/soil/youngs", "unknown key",
                          "one of {density, youngs_modulus, poisson_ratio, tension_cutoff, separation, erosion, permeability, phreatic, type}", "\"youngs\"",
                          "phase/linear_elastic"},
                         {"/materials/soil/youngs_modulus", "missing required parameter", "number > 0 [Pa]",
                          "nothing", "phase/linear_elastic"}});
}

TEST(SceneValidation, StringWhereNumberExpected) {
  json j = base_scene();
  j["materials"]["soil"]["youngs_modulus"] = "1e7";
  expect_diagnostics(j, {{"/materials/soil/youngs_modulus", "wrong type", "number > 0 [Pa]", "string \"1e7\"",
                          "phase/linear_elastic"}});
}

TEST(SceneValidation, NegativeYoungsModulusIsOutOfRange) {
  json j = base_scene();
  j["materials"]["soil"]["youngs_modulus"] = -5;
  expect_diagnostics(j, {{"/materials/soil/youngs_modulus", "value out of range", "number > 0 [Pa]", "-5",
                          "phase/linear_elastic"}});
}

TEST(SceneValidation, PoissonRatioOfOneHalfIsOutOfRange) {
  json j = base_scene();
  j["materials"]["soil"]["poisson_ratio"] = 0.5;
  expect_diagnostics(j, {{"/materials/soil/poisson_ratio", "value out of range", "number in (-1, 0.5) [-]", "0.5",
                          "phase/linear_elastic"}});
}

TEST(SceneValidation, MissingRequiredParameter) {
  json j = base_scene();
  j["materials"]["soil"].erase("density");
  expect_diagnostics(j, {{"/materials/soil/density", "missing required parameter", "number > 0 [kg/m^3]",
                          "nothing", "phase/linear_elastic"}});
}

TEST(SceneValidation, MissingRequiredCoreParameter) {
  json j = base_scene();
  j["time"].erase("end");
  expect_diagnostics(j, {{"/time/end", "missing required parameter", "number > 0 [s]", "nothing", "core (time)"}});
}

TEST(SceneValidation, UnknownPluginTypeListsValidPluginsOfThatKind) {
  json j = base_scene();
  j["materials"]["soil"]["type"] = "phase/hardening_soil";
  expect_diagnostics(j, {{"/materials/soil/type", kUnknownPlugin, kPhaseExpected, "\"phase/hardening_soil\"",
                          "core"}});
}

// The test helper that finds a boundary condition by what it is: one match or
// a loud failure, never a silent edit of the wrong condition.
TEST(SceneValidation, TestHelperFindsExactlyOneBoundaryCondition) {
  json j = base_scene();
  EXPECT_EQ(boundary_condition_pointer(j, {{"type", "bc/velocity"}, {"face", "left"}}), "/boundary_conditions/1");
  boundary_condition(j, {{"type", "bc/velocity"}, {"face", "left"}})["vx"] = 1.0;
  EXPECT_EQ(j["boundary_conditions"][1]["vx"], 1.0);
  EXPECT_THROW(boundary_condition(j, {{"type", "bc/velocity"}, {"face", "top"}}), std::logic_error) << "none";
  EXPECT_THROW(boundary_condition(j, {{"type", "bc/velocity"}}), std::logic_error) << "three";
}

TEST(SceneValidation, UnknownBoundaryConditionPlugin) {
  json j = base_scene();
  const json right_roller = {{"type", "bc/velocity"}, {"face", "right"}};
  const std::string at = boundary_condition_pointer(j, right_roller);
  boundary_condition(j, right_roller)["type"] = "bc/pressure_head";
  expect_diagnostics(j, {{at + "/type", kUnknownPlugin,
                          "a boundary condition plugin, one of {bc/inflow_flux, bc/pore_pressure, bc/traction, bc/velocity, bc/water_level}", "\"bc/pressure_head\"",
                          "core"}});
}

TEST(SceneValidation, WriterUsedAsMaterial) {
  json j = base_scene();
  j["materials"]["soil"] = {{"type", "writer/vtk_particles"}};
  expect_diagnostics(j, {{"/materials/soil/type", "plugin of the wrong kind (writer)", kPhaseExpected,
                          "\"writer/vtk_particles\"", "core"}});
}

TEST(SceneValidation, MissingPluginType) {
  json j = base_scene();
  j["shape_function"].erase("type");
  expect_diagnostics(j, {{"/shape_function/type", "missing plugin type",
                          "a shape function plugin, one of {shape/gimp, shape/linear}", "nothing", "core"}});
}

TEST(SceneValidation, BodyReferencesUndefinedMaterial) {
  json j = base_scene();
  j["bodies"][0]["material"] = "clay";
  expect_diagnostics(j, {{"/bodies/0/material", "undefined material", "one of {soil}", "\"clay\"", "core (body)"}});
}

TEST(SceneValidation, GravityWithThreeComponentsIn2D) {
  json j = base_scene();
  j["gravity"] = {0.0, -9.81, 0.0};
  expect_diagnostics(j, {{"/gravity", "wrong number of components", "array of 2 numbers [m/s^2]",
                          "array [0.0,-9.81,0.0]", "core (scene)"}});
}

TEST(SceneValidation, GridCellSizeWithThreeComponentsIn2D) {
  json j = base_scene();
  j["grid"]["cell_size"] = {0.25, 0.25, 0.25};
  expect_diagnostics(j, {{"/grid/cell_size", "wrong number of components", "array of 2 numbers > 0 [m]",
                          "array [0.25,0.25,0.25]", "core (grid)"}});
}

TEST(SceneValidation, NegativeGridCellSizeComponent) {
  json j = base_scene();
  j["grid"]["cell_size"] = {0.25, -0.25};
  expect_diagnostics(j, {{"/grid/cell_size", "component out of range", "array of 2 numbers > 0 [m]",
                          "array [0.25,-0.25]", "core (grid)"}});
}

TEST(SceneValidation, NonIntegerGridCells) {
  json j = base_scene();
  j["grid"]["cells"] = {1.5, 42};
  expect_diagnostics(j, {{"/grid/cells/0", "not an integer", "integer >= 1", "1.5", "core (grid)"}});
}

TEST(SceneValidation, MissingTimeSection) {
  json j = base_scene();
  j.erase("time");
  expect_diagnostics(j, {{"/time", "missing required section", "an object", "nothing", "core (scene)"}});
}

TEST(SceneValidation, MissingSeveralSections) {
  json j = base_scene();
  j.erase("grid");
  j.erase("shape_function");
  j.erase("bodies");
  expect_diagnostics(j, {{"/grid", "missing required section", "an object", "nothing", "core (scene)"},
                         {"/shape_function", "missing required section", "an object", "nothing", "core (scene)"},
                         {"/bodies", "missing required section", "an object", "nothing", "core (scene)"}});
}

TEST(SceneValidation, BodyOutsideTheGrid) {
  json j = base_scene();
  j["bodies"][0]["max"] = {0.25, 11.0};  // the grid ends at y = 42 * 0.25 = 10.5
  expect_diagnostics(j, {{"/bodies/0/max/1", "body outside the grid", "a box within the grid [0, 10.5]",
                          "11", "core (body)"}});
}

TEST(SceneValidation, BodyBelowTheGridOrigin) {
  json j = base_scene();
  j["bodies"][0]["min"] = {-0.5, 0.0};
  expect_diagnostics(j, {{"/bodies/0/min/0", "body outside the grid", "a box within the grid [0, 0.25]",
                          "-0.5", "core (body)"}});
}

TEST(SceneValidation, UnknownTopLevelKey) {
  json j = base_scene();
  j["gravty"] = {0.0, -9.81};
  expect_diagnostics(j, {{"/gravty", "unknown key",
                          "one of {description, dimension, plugin_paths, gravity, damping, damping_until, volumetric_strain, sort_points_at_spread, bodies, "
                          "boundary_conditions, factor_of_safety, failure, grid, liquids, materials, outputs, shape_function, time}",
                          "\"gravty\"", "core (scene)"}});
}

TEST(SceneValidation, InvalidJsonText) {
  const std::string text = R"({ "dimension": 2, "grid": { )";
  std::string parser_message;
  try {
    const json parsed = json::parse(text);
    ADD_FAILURE() << "nlohmann::json accepted " << parsed.dump();
  } catch (const json::parse_error& e) {
    parser_message = e.what();
  }
  ASSERT_FALSE(parser_message.empty());
  // Shown without nlohmann's "[json.exception.parse_error.101] " tag.
  parser_message = parser_message.substr(parser_message.find("] ") + 2);
  const std::vector<Diagnostic> diags = diagnostics_of_text(text);
  ASSERT_EQ(diags.size(), 1u) << describe(diags);
  expect_diagnostic(diags[0], {"", "not valid JSON", "a JSON object", parser_message, "core"});
}

TEST(SceneValidation, JsonThatIsNotAnObject) {
  const std::vector<Diagnostic> diags = diagnostics_of_text("[1, 2]");
  ASSERT_EQ(diags.size(), 1u) << describe(diags);
  expect_diagnostic(diags[0], {"", "wrong type", "a JSON object", "array [1,2]", "core"});
}

TEST(SceneValidation, UnknownChoiceValue) {
  json j = base_scene();
  const json base = {{"type", "bc/velocity"}, {"face", "bottom"}};
  const std::string at = boundary_condition_pointer(j, base);
  boundary_condition(j, base)["face"] = "middle";
  expect_diagnostics(j, {{at + "/face", "unknown choice",
                          "one of {left, right, bottom, top, front, back}", "string \"middle\"", "bc/velocity"}});
}

TEST(SceneValidation, PointerEscapesSlashAndTildeInKeys) {
  json j = base_scene();
  j["materials"]["a/b"] = j["materials"]["soil"];
  j["materials"]["a/b"]["youngs_modulus"] = -5;
  j["materials"]["c~d"] = j["materials"]["soil"];
  j["materials"]["c~d"]["nu"] = 0.3;
  j["bodies"][0]["material"] = "a/b";
  expect_diagnostics(j, {{"/materials/a~1b/youngs_modulus", "value out of range", "number > 0 [Pa]", "-5",
                          "phase/linear_elastic"},
                         {"/materials/c~0d/nu", "unknown key", "one of {density, youngs_modulus, poisson_ratio, tension_cutoff, separation, erosion, permeability, phreatic, type}",
                          "\"nu\"", "phase/linear_elastic"}});
}

TEST(SceneValidation, AllErrorsAreReportedTogether) {
  json j = base_scene();
  j["gravty"] = 1;                                       // unknown top-level key
  j.erase("time");                                       // missing section
  j["materials"]["soil"]["youngs_modulus"] = -5;         // out of range
  j["bodies"][0]["material"] = "clay";                   // undefined material
  const json base = {{"type", "bc/velocity"}, {"face", "bottom"}};
  const std::string base_face = boundary_condition_pointer(j, base) + "/face";
  boundary_condition(j, base)["face"] = "middle";        // unknown choice
  j["outputs"][0]["type"] = "phase/linear_elastic";      // wrong kind
  const std::vector<Diagnostic> diags = diagnostics_of(j);
  ASSERT_EQ(diags.size(), 6u) << describe(diags);
  const std::vector<std::string> pointers = {"/gravty",
                                             "/time",
                                             "/materials/soil/youngs_modulus",
                                             "/bodies/0/material",
                                             base_face,
                                             "/outputs/0/type"};
  for (std::size_t i = 0; i < pointers.size(); ++i) EXPECT_EQ(diags[i].pointer, pointers[i]) << describe(diags);
  EXPECT_EQ(diags[5].problem, "plugin of the wrong kind (phase)");
  EXPECT_EQ(diags[5].expected, "a writer plugin, one of {writer/csv_probe, writer/vtk_grid, writer/vtk_particles}");
}

// ---------------------------------------------------------------------------
// Regressions: each case below once threw or reported twice instead of
// giving one diagnostic (the comments say where, and how it failed).

TEST(SceneValidation, OutOfRangeDampingIsADiagnostic) {
  // Was (framework/src/scene/scene.cpp, SceneReader::read): top.number("damping") was
  // read unconditionally; when validation rejected the value there was neither
  // a value nor a default, so Parameters::number threw suffuse::Error
  // ("parameter 'damping' was not declared in the schema or has no value")
  // instead of a SceneError carrying the diagnostic. Same for "description"
  // and "gravity" (when dimension is valid) and for /time/cfl in read_time.
  json j = base_scene();
  j["damping"] = 1.5;
  expect_diagnostics(j, {{"/damping", "value out of range", "number in [0, 1) [-]", "1.5", "core (scene)"}});
}

TEST(SceneValidation, OutOfRangeCflIsADiagnostic) {
  // Was (framework/src/scene/scene.cpp, read_time): t.number("cfl") threw
  // suffuse::Error when the given cfl failed validation.
  json j = base_scene();
  j["time"]["cfl"] = 2;
  expect_diagnostics(j, {{"/time/cfl", "value out of range", "number in (0, 1] [-]", "2", "core (time)"}});
}

TEST(SceneValidation, GravityOfWrongTypeIsADiagnostic) {
  // Was (framework/src/scene/scene.cpp, SceneReader::read): top.vector("gravity")
  // threw suffuse::Error when the given gravity failed validation.
  json j = base_scene();
  j["gravity"] = "down";
  const std::vector<Diagnostic> diags = diagnostics_of(j);
  ASSERT_EQ(diags.size(), 1u) << describe(diags);
  EXPECT_EQ(diags[0].pointer, "/gravity");
  EXPECT_EQ(diags[0].problem, "wrong type");
  // The wording depends on whether the dimension is applied at that point.
  EXPECT_EQ(diags[0].expected.rfind("array of ", 0), 0u) << diags[0].expected;
  EXPECT_EQ(diags[0].found, "string \"down\"");
  EXPECT_EQ(diags[0].declared_by, "core (scene)");
}

TEST(SceneValidation, WrongKindOfWriterIsReportedOnlyOnce) {
  // Was (framework/src/scene/scene.cpp, read_outputs): when /outputs/N/type names a
  // plugin of another kind, the keys of the node were checked by the core
  // "output" schema against that other plugin's keys, so a valid writer key
  // such as "compress" was also reported as an unknown key.
  json j = base_scene();
  j["outputs"][0] = {{"type", "phase/linear_elastic"}, {"compress", false}, {"interval", 0.4}};
  expect_diagnostics(j, {{"/outputs/0/type", "plugin of the wrong kind (phase)",
                          "a writer plugin, one of {writer/csv_probe, writer/vtk_grid, writer/vtk_particles}", "\"phase/linear_elastic\"", "core"}});
}

TEST(SceneValidation, DescriptionOfWrongTypeIsADiagnostic) {
  // Was (framework/src/scene/scene.cpp, SceneReader::read): top.string("description")
  // threw suffuse::Error when the given description failed validation.
  json j = base_scene();
  j["description"] = 5;
  expect_diagnostics(j, {{"/description", "wrong type", "string", "5", "core (scene)"}});
}

TEST(SceneValidation, UnknownKeyInOutputIsReportedOnce) {
  // Was (framework/src/scene/scene.cpp, read_outputs): an unknown key of a writer
  // node was reported twice, once by the writer plugin's schema (in
  // plugin_node) and once by the core "output" schema.
  json j = base_scene();
  j["outputs"][0]["intervall"] = 0.4;
  expect_diagnostics(j, {{"/outputs/0/intervall", "unknown key", "one of {compress, interval, name, type}",
                          "\"intervall\"", "writer/vtk_particles"}});
}

}  // namespace

// Problems that involve several parameters come from the plugin's check(),
// reported with the other diagnostics, before anything is constructed.
namespace {

TEST(SceneValidation, BoundaryConditionCrossChecks) {
  json j = base_scene();
  j["boundary_conditions"] = {
      {{"type", "bc/velocity"}, {"face", "bottom"}},
      {{"type", "bc/velocity"}, {"face", "left"}, {"box_min", {0, 0}}, {"box_max", {1, 1}}, {"vx", 0.0}},
      {{"type", "bc/velocity"}, {"face", "front"}, {"vz", 0.0}}};
  expect_diagnostics(j, {
      {"/boundary_conditions/0", "no velocity component given", "at least one of vx, vy", "none", "bc/velocity"},
      {"/boundary_conditions/1", "no unique node set", "either \"face\" or \"box_min\" and \"box_max\"", "both",
       "bc/velocity"},
      {"/boundary_conditions/2/vz", "no z axis in a 2D scene", "one of vx, vy", "vz", "bc/velocity"},
      {"/boundary_conditions/2/face", "no such face in 2D", "one of {left, right, bottom, top}", "\"front\"",
       "bc/velocity"},
  });
}

TEST(SceneValidation, BoundaryConditionBoxChecks) {
  json j = base_scene();
  j["boundary_conditions"] = {
      {{"type", "bc/velocity"}, {"box_min", {0, 0}}, {"vy", 0.0}},
      {{"type", "bc/velocity"}, {"box_min", {0, 2}}, {"box_max", {1, 1}}, {"vx", 0.0}},
      {{"type", "bc/velocity"}, {"face", "right"}, {"vx", 0.0}}};
  expect_diagnostics(j, {
      {"/boundary_conditions/0/box_max", "missing box corner", "both box_min and box_max", "only one",
       "bc/velocity"},
      {"/boundary_conditions/1/box_max", "empty box", "box_max >= box_min in every component",
       "box_max[1] < box_min[1]", "bc/velocity"},
  });
}

}  // namespace

// Findings of the first code review, kept as regression tests.
namespace {

TEST(SceneValidation, MaterialsKeepTheFileOrder) {
  // "soil" comes before "clay" in the file: material_id follows the file.
  std::string text = base_scene().dump();
  const std::string soil = "\"soil\":";
  text.replace(text.find(soil), soil.size(),
               "\"soil2\": {\"type\": \"phase/linear_elastic\", \"density\": 1.0, \"youngs_modulus\": 1.0}, \"clay\": "
               "{\"type\": \"phase/linear_elastic\", \"density\": 1.0, \"youngs_modulus\": 1.0}, " + soil);
  const suffuse::Scene s = parse_text(text);
  ASSERT_EQ(s.materials.size(), 3u);
  EXPECT_EQ(s.materials[0].name, "soil2");
  EXPECT_EQ(s.materials[1].name, "clay");
  EXPECT_EQ(s.materials[2].name, "soil");
  EXPECT_EQ(s.bodies[0].material, 2u);
}

TEST(SceneValidation, GridTooLargeIsRejected) {
  json j = base_scene();
  j["dimension"] = 3;
  j["gravity"] = {0.0, 0.0, -9.81};
  j["grid"] = {{"cell_size", {1.0, 1.0, 1.0}}, {"cells", {4194303, 4194303, 4194303}}};
  j["bodies"][0]["min"] = {0.0, 0.0, 0.0};
  j["bodies"][0]["max"] = {1.0, 1.0, 1.0};
  j["boundary_conditions"] = json::array();
  const auto diags = diagnostics_of(j);
  ASSERT_EQ(diags.size(), 1u) << describe(diags);
  expect_diagnostic(diags[0], {"/grid/cells", "grid too large", "at most 2147483647 nodes", "7.37869762948e+19 nodes",
                               "core (grid)"});
}

TEST(SceneValidation, HugeCellCountIsOneError) {
  json j = base_scene();
  j["grid"]["cells"] = {1e10, 1};
  const auto diags = diagnostics_of(j);
  ASSERT_EQ(diags.size(), 1u) << describe(diags);  // no follow-up "outside the grid"
  expect_diagnostic(diags[0], {"/grid/cells/0", "value too large", "integer <= 100000000", "10000000000.0",
                               "core (grid)"});
}

TEST(SceneValidation, BodyFlushWithTheGridEndDespiteRoundOff) {
  json j = base_scene();
  j["grid"] = {{"cell_size", {0.29, 0.29}}, {"cells", {100, 100}}};  // 0.29 * 100 = 28.999999999999996
  j["bodies"][0]["max"] = {29.0, 29.0};
  EXPECT_NO_THROW(parse_text(j.dump()));
}

TEST(SceneValidation, MissingPluginPathIsADiagnostic) {
  json j = base_scene();
  j["plugin_paths"] = {"no/such/dir"};
  j["time"]["end"] = -1.0;
  const auto diags = diagnostics_of(j);
  ASSERT_EQ(diags.size(), 2u) << describe(diags);
  expect_diagnostic(diags[0], {"/plugin_paths/0", "no such file or directory", "a plugin library or a directory of them",
                               std::string(SUFFUSE_SOURCE_DIR) + "/no/such/dir", "core (scene)"});
  EXPECT_EQ(diags[1].pointer, "/time/end");
}

}  // namespace

namespace {

// Deeply nested JSON is refused before it is parsed (200,000 nested arrays
// crashed `suffuse validate` with a segmentation fault); brackets inside
// strings do not count.
TEST(SceneValidation, DeepNestingIsRefusedBeforeParsing) {
  const std::string deep = std::string(200000, '[') + std::string(200000, ']');
  for (const bool element : {false, true}) {
    suffuse::Registry registry;
    suffuse::PluginLoader loader(registry);
    try {
      if (element)
        suffuse::parse_element_scene(deep, "deep.json", ".", registry, loader);
      else
        suffuse::parse_scene(deep, "deep.json", ".", registry, loader);
      ADD_FAILURE() << "accepted";
    } catch (const suffuse::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("nested too deeply"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("at most 64 levels"), std::string::npos) << e.what();
    }
  }
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  j["description"] = std::string(1000, '[') + " brackets in a string " + std::string(1000, '{');
  suffuse::Registry registry;
  EXPECT_NO_THROW(suffuse::test::scene_from(j, registry));
}

}  // namespace
