// The grid, and the shape functions between it and the points.
#include <algorithm>
#include <cmath>

#include "scene/scene_reader.hpp"
#include "suffuse/grid_face.hpp"

namespace suffuse::detail {

namespace {

constexpr double max_cells_per_axis = 1e8;
constexpr double max_nodes = 2147483647.0;  // node ids stay within 31 bits

ParameterSchema grid_schema() {
  ParameterSchema s;
  s.vector("origin").with_unit("m").fallback(std::vector<double>{}).doc("Lower corner of the grid (default 0)");
  s.vector("cell_size").with_unit("m").above(0).doc("Cell edge length along each axis");
  s.vector("cells").with_unit("-").at_least(1).doc("Number of cells along each axis (integers)");
  s.string_list("periodic").fallback(std::vector<std::string>{}).doc(
      "Axes (\"x\", \"y\", \"z\") along which the grid wraps: its upper face's nodes are its lower face's, "
      "and a point leaving one face enters at the other (an infinite slope, a layer without ends; "
      "docs/boundaries.md, Periodic grids). Quasi-static runs and explicit runs of dry soil, without erosion, "
      "at least 3 cells along the axis, no boundary condition on its faces");
  return s;
}

void read_grid(SceneReader& r, Scene& scene) {
  if (!r.require("grid")) return;
  const std::size_t before = r.diags.size();
  Parameters g = validate_object(r.root["grid"], grid_schema(), "/grid", "core (grid)",
                                         r.dim, r.diags);
  r.grid_ok = r.diags.size() == before && r.dim != 0;
  if (g.has("origin")) scene.grid_origin = to_array(g.vector("origin"));
  if (g.has("cell_size")) scene.grid_cell_size = to_array(g.vector("cell_size"));
  if (g.has("cells")) {
    const auto& c = g.vector("cells");
    double nodes = 1;
    bool cells_ok = true;
    for (std::size_t a = 0; a < c.size() && a < 3; ++a) {
      const std::string ptr = "/grid/cells/" + std::to_string(a);
      if (c[a] != std::floor(c[a])) {
        r.error(ptr, "not an integer", "integer >= 1", show(r.root["grid"]["cells"][a]), "core (grid)");
        cells_ok = false;
      } else if (c[a] > max_cells_per_axis) {
        r.error(ptr, "value too large", "integer <= " + format(max_cells_per_axis),
                show(r.root["grid"]["cells"][a]), "core (grid)");
        cells_ok = false;
      } else {
        scene.grid_cells[a] = static_cast<int>(c[a]);
        nodes *= c[a] + 1;
      }
    }
    if (cells_ok && nodes > max_nodes) {
      r.error("/grid/cells", "grid too large", "at most " + format(max_nodes) + " nodes", format(nodes) + " nodes",
              "core (grid)");
      cells_ok = false;
    }
    r.grid_ok = r.grid_ok && cells_ok;
  }
  if (g.has("periodic")) {
    const auto& axes = g.string_list("periodic");
    for (std::size_t i = 0; i < axes.size(); ++i) {
      const std::string ptr = "/grid/periodic/" + std::to_string(i);
      const std::string names[3] = {"x", "y", "z"};
      const auto a = static_cast<int>(std::find(names, names + 3, axes[i]) - names);
      if (a >= r.dim) {
        r.error(ptr, "not an axis", r.dim == 3 ? "\"x\", \"y\" or \"z\"" : "\"x\" or \"y\"",
                show(r.root["grid"]["periodic"][i]), "core (grid)");
      } else if (scene.grid_periodic[a]) {
        r.error(ptr, "an axis named twice", "each axis once", show(r.root["grid"]["periodic"][i]), "core (grid)");
      } else if (scene.grid_cells[a] < 3) {
        r.error(ptr, "too few cells along a periodic axis", "at least 3 (a point's support spans 3 nodes)",
                std::to_string(scene.grid_cells[a]) + " cells", "core (grid)");
      } else {
        scene.grid_periodic[a] = true;
      }
    }
  }
}

void read_shape_function(SceneReader& r, Scene& scene) {
  if (r.require("shape_function"))
    scene.shape_function = r.plugin_node(r.root["shape_function"], "/shape_function", PluginKind::ShapeFunction);
}

}  // namespace

// What a periodic grid does not yet wrap is refused: the liquid's and the
// fines' transport over the grid's dual cells, which sees the faces as
// walls (explicit saturated runs, their collapses, erosion, suspended
// fines), and a condition on a face the grid wraps.
void check_periodic_grid(SceneReader& r, const Scene& scene) {
  if (std::none_of(scene.grid_periodic.begin(), scene.grid_periodic.end(), [](bool b) { return b; })) return;
  const std::string ptr = "/grid/periodic", who = "core (grid)";
  const bool explicit_steps = scene.integration != TimeIntegration::quasi_static;
  if (scene.saturated() && explicit_steps)
    r.error(ptr, "a periodic grid in an explicit run of saturated soil",
            "dry soil, or \"integration\": \"quasi_static\" in /time (the explicit liquid's transport over the "
            "grid's dual cells does not wrap yet)",
            "integration explicit", who);
  if (scene.saturated() && !explicit_steps && scene.failure && scene.failure->collapse)
    r.error("/failure/collapse", "a collapse on a periodic grid of saturated soil",
            "no collapse, or dry soil (the explicit liquid's transport over the grid's dual cells does not wrap yet)",
            show(r.root["failure"]["collapse"]), who);
  const bool suspended = std::any_of(scene.bodies.begin(), scene.bodies.end(),
                                     [](const BodySpec& b) { return b.concentration > 0; });
  if (scene.erodible() || suspended)
    r.error(ptr, "a periodic grid with fines that move",
            "no erosion law and no suspended fines (their transport over the grid's dual cells does not wrap yet)",
            scene.erodible() ? "an erosion law" : "suspended fines", who);
  if (!r.root.contains("boundary_conditions") || !r.root["boundary_conditions"].is_array()) return;
  const Json& bcs = r.root["boundary_conditions"];
  const std::vector<std::string> faces = grid_face_names();
  for (std::size_t i = 0; i < bcs.size(); ++i) {
    if (!bcs[i].is_object()) continue;
    if (bcs[i].contains("concentration") && bcs[i]["concentration"].is_number() &&
        bcs[i]["concentration"].get<double>() > 0)
      r.error("/boundary_conditions/" + std::to_string(i) + "/concentration",
              "fines carried in on a periodic grid",
              "0 (the fines' transport over the grid's dual cells does not wrap yet)", show(bcs[i]["concentration"]),
              who);
    if (!bcs[i].contains("face") || !bcs[i]["face"].is_string()) continue;
    const auto f = std::find(faces.begin(), faces.end(), bcs[i]["face"].get<std::string>());
    if (f != faces.end() && scene.grid_periodic[static_cast<std::size_t>(f - faces.begin()) / 2])
      r.error("/boundary_conditions/" + std::to_string(i) + "/face", "a condition on a face the grid wraps",
              "a face of an axis not in /grid/periodic", show(bcs[i]["face"]), who);
  }
}

SceneSection grid_section() { return {"grid", "grid", "Structured regular background grid", grid_schema, read_grid}; }

SceneSection shape_function_section() {
  return {"shape_function", "", "The shape functions between grid and points: a shape function plugin node", nullptr,
          read_shape_function};
}

}  // namespace suffuse::detail
