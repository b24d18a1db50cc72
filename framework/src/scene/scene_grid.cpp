// The grid, and the shape functions between it and the points.
#include <cmath>

#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

constexpr double max_cells_per_axis = 1e8;
constexpr double max_nodes = 2147483647.0;  // node ids stay within 31 bits

ParameterSchema grid_schema() {
  ParameterSchema s;
  s.vector("origin").with_unit("m").fallback(std::vector<double>{}).doc("Lower corner of the grid (default 0)");
  s.vector("cell_size").with_unit("m").above(0).doc("Cell edge length along each axis");
  s.vector("cells").with_unit("-").at_least(1).doc("Number of cells along each axis (integers)");
  
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
}

void read_shape_function(SceneReader& r, Scene& scene) {
  if (r.require("shape_function"))
    scene.shape_function = r.plugin_node(r.root["shape_function"], "/shape_function", PluginKind::ShapeFunction);
}

}  // namespace

SceneSection grid_section() { return {"grid", "grid", "Structured regular background grid", grid_schema, read_grid}; }

SceneSection shape_function_section() {
  return {"shape_function", "", "The shape functions between grid and points: a shape function plugin node", nullptr,
          read_shape_function};
}

}  // namespace suffuse::detail
