// The top level of a scene: dimension, gravity, damping, volumetric strain, point order, plugin paths.
#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

// The top level is validated before its own "dimension" is known, so the
// length of /gravity (one component per dimension) is checked here.
void check_gravity_length(SceneReader& r) {
  if (!r.root.contains("gravity")) return;  // the default, zero, fits any dimension
  const Json& gravity = r.root["gravity"];
  if (gravity.is_array() && static_cast<int>(gravity.size()) != r.dim)
    r.error("/gravity", "wrong number of components", "array of " + std::to_string(r.dim) + " numbers [m/s^2]",
            show(gravity), "core (scene)");
}

ParameterSchema top_level_schema() {
  ParameterSchema s;
  s.string("description").fallback(std::string()).doc("What the scene shows and how to read its results");
  s.integer("dimension").at_least(2).at_most(3).with_unit("-").doc(
      "Spatial dimension: 2 (plane strain) or 3. A 1D column is a 2D strip one cell wide");
  s.string_list("plugin_paths").fallback(std::vector<std::string>{}).doc(
      "Plugin libraries or directories searched first, relative to the scene file");
  s.vector("gravity").with_unit("m/s^2").fallback(std::vector<double>{}).doc(
      "Gravitational acceleration, one component per dimension (default zero)");
  s.number("damping").at_least(0).below(1).with_unit("-").fallback(0.0).doc(
      "Local non-viscous (Cundall) damping coefficient of explicit runs: a force opposing each node's motion, this "
      "fraction of its unbalanced force; brings a run to rest under its loads (0: none)");
  s.number("damping_until").with_unit("s").above(0).may_be_absent().doc(
      "The time at which the damping stops (absent: it acts for the whole run). A damped start: the run comes to "
      "rest at its own equilibrium under gravity and its first loads, then moves freely, undamped, under what "
      "changes later (docs/time-integration.md, A damped start)");
  s.choice("volumetric_strain", {"point", "cell_average"}).fallback(std::string("point")).doc(
      "point: each point's volumetric strain rate from its own velocity gradient; cell_average: the "
      "volume-weighted mean over the points of its cell, the deviatoric part kept (removes the volumetric locking "
      "of nearly incompressible or isochoric plastic flow, e.g. undrained clay or Tresca, on linear shape "
      "functions; a B-bar method)");
  s.number("sort_points_at_spread").at_least(0).with_unit("-").fallback(1.5).doc(
      "Sort the material points again into the grid's order (each body's by cell) when they have mixed: when the "
      "cells the scatter chunks of consecutive points span, summed, reach this factor of their sum after the last "
      "sort (or at the start). Keeps the scatters without buffers and, on many processes, each process's nodes a "
      "narrow slab, points moving between processes (docs/parallel.md). The order of the points in outputs changes "
      "at each sort; their point field id, their number at the start, does not. 0: never sort (no field id). "
      "Below 1 (but above 0): sort at every step");
  return s;
}

void read_top_level(SceneReader& r, Scene& scene) {
  // The other sections are read by their own readers.
  std::set<std::string> structured;
  for (const SceneSection& s : scene_sections())
    if (!s.key.empty()) structured.insert(s.key);
  Parameters top = validate_object(r.root, top_level_schema(), "", "core (scene)", 0, r.diags, structured);
  r.dim = top.has("dimension") ? static_cast<int>(top.integer("dimension")) : 0;
  scene.dim = r.dim ? r.dim : 2;
  // A value that failed validation is absent: read only what is there.
  if (top.has("description")) scene.description = top.string("description");
  if (top.has("damping")) scene.damping = top.number("damping");
  scene.damping_until = top.maybe_number("damping_until");
  // (A /damping that failed validation has its own error.)
  const bool given = r.root.contains("damping");
  if (scene.damping_until && (!given || (r.root["damping"].is_number() && r.root["damping"] == 0)))
    r.error("/damping_until", "an end of damping without damping", "a /damping above 0, or no /damping_until",
            given ? "/damping 0" : "no /damping", "core (scene)");
  if (top.has("sort_points_at_spread")) scene.sort_points_at_spread = top.number("sort_points_at_spread");
  if (top.has("volumetric_strain") && top.string("volumetric_strain") == "cell_average")
    scene.volumetric_strain = VolumetricStrain::cell_average;
  if (r.dim && top.has("gravity")) {
    check_gravity_length(r);
    scene.gravity = to_array(top.vector("gravity"));
  }
}

}  // namespace

SceneSection top_level_section() {
  return {"", "scene",
          "Top level of a scene file; also holds the sections grid, time, shape_function, materials, liquids, bodies, "
          "boundary_conditions, outputs, factor_of_safety and failure",
          top_level_schema, read_top_level};
}

}  // namespace suffuse::detail
