// Bodies: boxes and polygons of material points, dry or saturated, with
// their initial state.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <optional>

#include "geometry/polygon.hpp"
#include "common/unit_table.hpp"
#include "geometry/surface.hpp"
#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema body_schema() {
  ParameterSchema s;
  s.string("name").fallback(std::string()).doc("Name of the body, for messages");
  s.string("material").doc("Name of a material defined under /materials");
  s.vector("min").with_unit("m").may_be_absent().doc(
      "Lower corner of the box filled with material points (a box body); in 3D with a polygon, only the "
      "component along extrusion_axis counts: where the extrusion starts");
  s.vector("max").with_unit("m").may_be_absent().doc(
      "Upper corner of the box filled with material points; in 3D with a polygon, where the extrusion ends");
  s.table("polygon", 2).with_unit("m").may_be_absent().doc(
      "A polygon body instead of a box: its outer ring, vertices in order (either way round, the last joined to "
      "the first). 2D: x, y; 3D: the two axes but extrusion_axis, in increasing order (docs/geometry.md)");
  s.string("polygon_file").may_be_absent().doc(
      "The polygon from a CSV file instead, relative to the scene: a header with units (\"x [m], y [m]\"; m, cm "
      "or mm) and a row per vertex; an optional third column \"ring\" numbers the rings: 0 the outer, 1, 2, ... "
      "the holes");
  s.tables("holes", 2).with_unit("m").may_be_absent().doc(
      "Holes of an inline polygon: rings of vertices inside its outer ring, apart from each other");
  s.string("points_file").may_be_absent().doc(
      "A body of points generated elsewhere, instead of a shape: a CSV file relative to the scene, a header with "
      "units (\"x [m], y [m], volume [m^2]\" in 2D, \"x [m], y [m], z [m], volume [m^3]\" in 3D; lengths in m, cm or "
      "mm) and a row per point, optionally followed by columns of initial fields per point (stress_xx ... "
      "stress_xy [Pa], pore_pressure [Pa], porosity [-], velocity_x ... [m/s], fines_content [-], "
      "liquid_velocity_x ... [m/s], saturation [-]) that replace the body's keys there; or a VTK .vtp file, its "
      "points (in metres; z = 0 in 2D) with a point-data array \"volume\" and, if present, the arrays of those "
      "fields as a run writes them (docs/geometry.md)");
  s.string("surface_file").may_be_absent().doc(
      "3D: a body inside a closed triangulated surface, instead of a shape: an STL or VTK .vtp file relative to "
      "the scene, lengths in metres; the points of the grid's lattice (points_per_cell per cell and axis) inside "
      "it, as a body of points: no k0, no shape for later bodies (docs/geometry.md)");
  s.choice("extrusion_axis", {"x", "y", "z"}).may_be_absent().doc(
      "3D polygon bodies: the axis the polygon is extruded along, between min and max of that axis");
  s.integer("points_per_cell").with_unit("-").at_least(1).at_most(8).fallback(2LL).doc(
      "Material points per cell along each axis");
  s.vector("velocity").with_unit("m/s").fallback(std::vector<double>{}).doc("Initial velocity (default 0)");
  s.string("liquid").may_be_absent().doc(
      "Name of a liquid under /liquids that saturates the body (two-phase); its material's density is then "
      "the density of the solid grains");
  s.number("porosity").with_unit("-").above(0).below(1).may_be_absent().doc(
      "Initial porosity n of a saturated body (required with liquid)");
  s.vector("stress").of_length(6).with_unit("Pa").fallback(std::vector<double>{}).doc(
      "Initial uniform (effective) stress xx, yy, zz, yz, xz, xy, tension positive (default zero)");
  s.number("pore_pressure").with_unit("Pa").fallback(0.0).doc(
      "Initial uniform pore pressure of a saturated body, compression positive");
  s.number("water_table").with_unit("m").may_be_absent().doc(
      "Elevation of the water table (y in 2D, z in 3D): adds the hydrostatic pore pressure rho_L g (water_table - "
      "elevation) below it, for saturated bodies");
  s.number("fines_content").with_unit("-").at_least(0).below(1).fallback(0.0).doc(
      "Initial erodible fines content f_c of a saturated body: volume of fines / volume of solid. Part of the "
      "solid, so the porosity counts them as solid");
  s.number("ultimate_fines_content").with_unit("-").at_least(0).below(1).fallback(0.0).doc(
      "Fines content f_c_inf below which no erosion law can go (at most fines_content)");
  s.number("concentration").with_unit("-").at_least(0).at_most(1).fallback(0.0).doc(
      "Initial concentration c of suspended fines in the pore liquid: volume of fines / volume of liquid");
  s.number("k0").with_unit("-").at_least(0).may_be_absent().doc(
      "Adds the geostatic effective stress: the total weight above each point (the body's soil and pore liquid, "
      "the bodies stacked on it, water ponded above its water table) less the hydrostatic pore pressure, with "
      "horizontal stress k0 times the vertical");
  s.string("gradation").may_be_absent().doc(
      "The soil's particle-size distribution: a PSD file, CSV with the units in its header (\"size [mm], "
      "passing [%]\") or JSON, relative to the scene file. validate reports the internal-stability criteria on it "
      "(docs/gradation.md)");
  s.table("gradation_points", 2).with_unit("mm, %").may_be_absent().doc(
      "The particle-size distribution inline, instead of \"gradation\": [[size, percent passing], ...], smallest "
      "size first, 100 % at the largest");
  s.boolean("fines_content_from_gradation").fallback(false).doc(
      "Take fines_content from the gradation: the erodible fines the criteria identify (finer than the gap of a "
      "gap-graded soil, else the shape curve's unstable part; 0 if no criterion finds it unstable; "
      "docs/gradation.md). Instead of fines_content");

  return s;
}

// Fines belong to saturated bodies: without a liquid there is nothing to carry them.
void read_fines(SceneReader& r, const Parameters& b, const std::string& ptr, BodySpec& body) {
  auto value = [&](const char* key) { return b.has(key) ? b.number(key) : 0.0; };
  if (!body.fines_content_from_gradation) body.fines_content = value("fines_content");
  body.ultimate_fines_content = value("ultimate_fines_content");
  body.concentration = value("concentration");
  for (const char* key : {"fines_content", "ultimate_fines_content", "concentration"}) {
    const double v = std::string(key) == "fines_content" ? body.fines_content : value(key);
    if (v != 0 && !b.has("liquid"))
      r.error(ptr + "/" + key, "fines in a dry body", "0 without \"liquid\"", format(v), "core (body)");
  }
  // Compared only when both are valid: a rejected value is reported once.
  const bool both_valid = (b.has("fines_content") || body.fines_content_from_gradation) && b.has("ultimate_fines_content");
  if (both_valid && body.ultimate_fines_content > body.fines_content)
    r.error(ptr + "/ultimate_fines_content", "ultimate fines content above the initial one",
            "at most fines_content = " + format(body.fines_content), format(body.ultimate_fines_content),
            "core (body)");
}

// A polygon's rings from the scene (inline) or its file; problems reported
// at the key that gives them.
std::optional<Polygon> read_polygon(SceneReader& r, const Parameters& b, const std::string& ptr) {
  Polygon polygon;
  auto ring_of = [](const std::vector<double>& flat) {
    Polygon::Ring ring;
    for (std::size_t k = 0; k + 1 < flat.size(); k += 2) ring.push_back({flat[k], flat[k + 1]});
    return ring;
  };
  std::string at = ptr + "/polygon";
  if (b.has("polygon_file")) {
    at = ptr + "/polygon_file";
    std::filesystem::path file = b.string("polygon_file");
    if (file.is_relative()) file = r.base_dir / file;
    try {
      const std::vector<UnitColumn> columns = {
          {"x", Quantity::length, false, ""}, {"y", Quantity::length, false, ""}, {"ring", Quantity::count, true, ""}};
      const UnitTable t = read_unit_table(file, columns, 1 << 20);  // 10,000 vertices are 200 to 500 KiB
      for (std::size_t k = 0; k < t.rows.size(); ++k) {
        const double ring = t.columns > 2 ? t.rows[k][2] : 0;
        const auto rings = polygon.holes.size() + 1;
        const std::string where = file.string() + ":" + std::to_string(t.lines[k]);
        if (ring < 0 || ring > static_cast<double>(rings) || (ring + 1 < static_cast<double>(rings)))
          throw Error(where + ": rings out of order: expected ring " + std::to_string(rings - 1) + " or " +
                      std::to_string(rings) + " (0 the outer ring, then the holes, each ring's rows together), found " +
                      format(ring));
        if (ring == static_cast<double>(rings)) polygon.holes.emplace_back();
        (ring == 0 ? polygon.outer : polygon.holes.back()).push_back({t.rows[k][0], t.rows[k][1]});
      }
    } catch (const Error& e) {
      r.error(at, "unreadable polygon file", "a CSV file as docs/geometry.md describes", e.what(), "core (body)");
      return std::nullopt;
    }
  } else {
    polygon.outer = ring_of(b.vector("polygon"));
    if (b.has("holes"))
      for (const std::vector<double>& hole : b.tables("holes")) polygon.holes.push_back(ring_of(hole));
  }
  if (auto p = check_polygon(polygon)) {
    std::string where = p->ring < 0 ? at : b.has("polygon_file") ? at : ptr + "/holes/" + std::to_string(p->ring);
    if (p->vertex >= 0 && !b.has("polygon_file")) where += "/" + std::to_string(p->vertex);
    r.error(where, p->problem, p->expected, p->found, "core (body)");
    return std::nullopt;
  }
  return polygon;
}

// A body given by `own` (points_file, surface_file) takes no other shape
// key and no k0 (its points have no shape to weigh down): the first such
// key is refused, at its path. Returns whether one was.
bool refused_with_another_shape(SceneReader& r, const Parameters& b, const std::string& ptr, const std::string& own,
                                const char* k0_problem, const char* shape_problem, const std::string& body_kind,
                                const char* expected) {
  for (const char* key : {"min", "max", "polygon", "polygon_file", "holes", "extrusion_axis", "points_file",
                          "surface_file", "k0"}) {
    if (key == own || !b.has(key)) continue;
    const bool k0 = std::string(key) == "k0";
    r.error(ptr + "/" + key, k0 ? k0_problem : shape_problem,
            k0 ? "no k0: the initial stress of " + body_kind + " is its \"stress\"" : std::string(expected), key,
            "core (body)");
    return true;
  }
  return false;
}

// The initial fields a points file may give each point (docs/geometry.md):
// a CSV column per component, named as suffuse's outputs name them.
struct PointColumn {
  const char* field;
  int component;  // of the field's values per point
  const char* unit;
};

std::optional<PointColumn> point_column(const std::string& name, int dim) {
  static const char* voigt[6] = {"xx", "yy", "zz", "yz", "xz", "xy"};
  for (int c = 0; c < 6; ++c)
    if (name == std::string("stress_") + voigt[c]) return PointColumn{"stress", c, "Pa"};
  for (int a = 0; a < dim; ++a) {
    if (name == std::string("velocity_") + char('x' + a)) return PointColumn{"velocity", a, "m/s"};
    if (name == std::string("liquid_velocity_") + char('x' + a)) return PointColumn{"liquid_velocity", a, "m/s"};
  }
  for (const char* f : {"pore_pressure", "porosity", "fines_content", "saturation"})
    if (name == f) return PointColumn{f, 0, name == "pore_pressure" ? "Pa" : "-"};
  return std::nullopt;
}

std::string point_column_names(int dim) {
  const std::string v = dim == 2 ? "velocity_x, velocity_y" : "velocity_x, velocity_y, velocity_z";
  return "stress_xx, stress_yy, stress_zz, stress_yz, stress_xz, stress_xy [Pa], pore_pressure [Pa], porosity [-], " +
         v + " [m/s], fines_content [-], liquid_" + (dim == 2 ? "velocity_x, liquid_velocity_y" :
         "velocity_x, liquid_velocity_y, liquid_velocity_z") + " [m/s], saturation [-]";
}

// A CSV file's header cells, names without their units.
std::vector<std::string> header_names(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    std::vector<std::string> names;
    for (const std::string& cell : split_cells(t)) names.push_back(trim(cell.substr(0, cell.find_first_of("[("))));
    return names;
  }
  return {};
}

// The point values of a field, `components` per point, from the body's key
// where the file gives only some of its components.
std::vector<double>& field_values(BodySpec& body, const std::string& field) {
  auto& v = body.point_values;
  return field == "stress" ? v.stress : field == "velocity" ? v.velocity : field == "porosity" ? v.porosity
         : field == "pore_pressure" ? v.pore_pressure : field == "liquid_velocity" ? v.liquid_velocity
         : field == "saturation" ? v.saturation : v.fines_content;
}

std::size_t components_of(const std::string& field, int dim) {
  return field == "stress" ? 6 : field == "velocity" || field == "liquid_velocity" ? static_cast<std::size_t>(dim) : 1;
}

void fill_from_keys(BodySpec& body, const std::string& field, std::size_t count, int dim) {
  std::vector<double>& v = field_values(body, field);
  if (field == "stress") {
    for (std::size_t p = 0; p < count; ++p) v.insert(v.end(), body.stress.begin(), body.stress.end());
  } else if (field == "velocity" || field == "liquid_velocity") {
    // A liquid velocity the file gives in part: the rest the skeleton's (the body's key; read_points
    // puts the file's in where it gives them).
    for (std::size_t p = 0; p < count; ++p) v.insert(v.end(), body.velocity.begin(), body.velocity.begin() + dim);
  } else if (field == "saturation") {
    v.assign(count, 1.0);
  } else {
    v.assign(count, 0.0);
  }
}

// Each point's initial values in range, and the body's keys they replace.
void check_point_values(const BodySpec& body, const Parameters& b, bool drains, const std::string& file,
                        const std::vector<std::string>& where) {
  const auto& v = body.point_values;
  const bool wet = body.liquid.has_value();
  for (const auto& [name, values] :
       {std::pair{"pore_pressure", &v.pore_pressure}, std::pair{"porosity", &v.porosity},
        std::pair{"fines_content", &v.fines_content}, std::pair{"liquid_velocity", &v.liquid_velocity},
        std::pair{"saturation", &v.saturation}})
    if (!values->empty() && !wet)
      throw Error(file + ": a dry body's points with " + name + ": expected " + name +
                  " only for a body with \"liquid\", found it in the file");
  if (!v.saturation.empty() && !drains)
    throw Error(file + ": saturation for a material whose pores do not drain: expected saturation only for a "
                "material with \"phreatic\", found it in the file");
  if (!v.pore_pressure.empty() && b.has("water_table"))
    throw Error(file + ": pore_pressure both per point and by the body's water_table: expected one of them, found both");
  for (std::size_t k = 0; k < where.size(); ++k) {
    if (!v.porosity.empty() && !(v.porosity[k] > 0 && v.porosity[k] < 1))
      throw Error(where[k] + ": porosity out of range: expected a porosity in (0, 1), found " + format(v.porosity[k]));
    if (!v.fines_content.empty() &&
        !(v.fines_content[k] >= body.ultimate_fines_content && v.fines_content[k] < 1))
      throw Error(where[k] + ": fines_content out of range: expected fines_content in [ultimate_fines_content = " +
                  format(body.ultimate_fines_content) + ", 1), found " + format(v.fines_content[k]));
    if (!v.saturation.empty() && !(v.saturation[k] > 0 && v.saturation[k] <= 1))
      throw Error(where[k] + ": saturation out of range: expected a saturation in (0, 1], found " +
                  format(v.saturation[k]));
    for (const auto& [name, values] : {std::pair{"stress", &v.stress}, std::pair{"pore_pressure", &v.pore_pressure},
                                       std::pair{"velocity", &v.velocity},
                                       std::pair{"liquid_velocity", &v.liquid_velocity}})
      if (!values->empty()) {
        const std::size_t per = values->size() / where.size();
        for (std::size_t c = 0; c < per; ++c)
          if (!std::isfinite((*values)[k * per + c]))
            throw Error(where[k] + ": " + name + " not a number: expected finite initial values, found " +
                        format((*values)[k * per + c]));
      }
  }
}

// A body of points from a file (CSV, or VTK .vtp through the surface
// module): positions in the grid, volumes above zero, and the initial
// fields the file gives each point.
void read_points(SceneReader& r, const Scene& scene, const Parameters& b, const std::string& ptr, BodySpec& body) {
  const std::string at = ptr + "/points_file";
  if (refused_with_another_shape(r, b, ptr, "points_file", "k0 on a body of points", "a points file and a shape",
                                 "a body without a shape", "either points_file or a box or polygon"))
    return;
  std::filesystem::path file = b.string("points_file");
  if (file.is_relative()) file = r.base_dir / file;
  const int D = r.dim;
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  try {
    // Rows of D coordinates and a volume, and where each is in the file.
    std::vector<std::vector<double>> rows;
    std::vector<std::string> where;
    if (ext == ".vtp") {
      VtpPoints read = read_vtp_points(file, D);
      const std::vector<double>& flat = read.rows;
      for (std::size_t k = 0; (k + 1) * static_cast<std::size_t>(D + 1) <= flat.size(); ++k) {
        rows.emplace_back(flat.begin() + static_cast<std::ptrdiff_t>(k * (D + 1)),
                          flat.begin() + static_cast<std::ptrdiff_t>((k + 1) * (D + 1)));
        where.push_back(file.string() + ", point " + std::to_string(k));
      }
      // A dry body reads only stress and velocity: a saturated run's files
      // hold its pores' fields too; the saturation only a material whose
      // pores drain.
      const bool drains = scene.materials.size() > body.material && scene.materials[body.material].phreatic;
      for (auto& [field, values] : read.fields)
        if ((body.liquid || field == "stress" || field == "velocity") && (field != "saturation" || drains))
          field_values(body, field) = std::move(values);
    } else {
      std::vector<UnitColumn> columns;
      for (int a = 0; a < D; ++a) columns.push_back({std::string(1, char('x' + a)), Quantity::length, false, ""});
      columns.push_back({"volume", Quantity::named, false, D == 2 ? "m^2" : "m^3"});
      // Columns after the volume: initial fields, by name.
      std::vector<PointColumn> given;
      const std::vector<std::string> names = header_names(file);
      for (std::size_t c = columns.size(); c < names.size(); ++c) {
        const std::optional<PointColumn> column = point_column(names[c], D);
        if (!column)
          throw Error(file.string() + ": unknown column \"" + names[c] + "\": expected after the volume any of " +
                      point_column_names(D));
        for (const PointColumn& g : given)
          if (std::string(g.field) == column->field && g.component == column->component)
            throw Error(file.string() + ": column \"" + names[c] + "\" twice: expected each column once");
        given.push_back(*column);
        columns.push_back({names[c], Quantity::named, false, column->unit});
      }
      // 64 MiB: about a million points (a flat reader would take more; say so if you need it).
      UnitTable t = read_unit_table(file, columns, std::size_t{64} << 20);
      if (t.rows.empty()) throw Error(file.string() + ": no point: expected a row per point, found none");
      for (const PointColumn& g : given)
        if (field_values(body, g.field).empty()) fill_from_keys(body, g.field, t.rows.size(), D);
      for (std::size_t k = 0; k < t.rows.size(); ++k)
        for (std::size_t c = 0; c < given.size(); ++c) {
          const std::string field = given[c].field;
          const std::size_t per = components_of(field, D);
          field_values(body, field)[k * per + static_cast<std::size_t>(given[c].component)] =
              t.rows[k][static_cast<std::size_t>(D + 1) + c];
        }
      // A liquid velocity the file gives in part: its other components the
      // skeleton's, the file's where it gives them (else the body's key).
      std::vector<double>& liquid = body.point_values.liquid_velocity;
      const std::vector<double>& skeleton = body.point_values.velocity;
      if (!liquid.empty() && !skeleton.empty())
        for (int a = 0; a < D; ++a)
          if (std::none_of(given.begin(), given.end(), [&](const PointColumn& g) {
                return std::string(g.field) == "liquid_velocity" && g.component == a;
              }))
            for (std::size_t k = 0; k < t.rows.size(); ++k) liquid[k * D + a] = skeleton[k * D + a];
      for (auto& row : t.rows) row.resize(static_cast<std::size_t>(D + 1));
      rows = std::move(t.rows);
      for (const auto line : t.lines) where.push_back(file.string() + ":" + std::to_string(line));
    }
    check_point_values(body, b, scene.materials.size() > body.material && scene.materials[body.material].phreatic,
                       file.string(), where);
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (!(rows[k][D] > 0)) throw Error(where[k] + ": volume not positive: expected a volume > 0, found " + format(rows[k][D]));
      if (r.grid_ok)
        for (int a = 0; a < D; ++a) {
          const double lo = scene.grid_origin[a], hi = lo + scene.grid_cell_size[a] * scene.grid_cells[a];
          if (!(rows[k][a] >= lo && rows[k][a] <= hi))
            throw Error(where[k] + ": point outside the grid: expected " + std::string(1, char('x' + a)) + " within [" +
                        format(lo) + ", " + format(hi) + "], found " + format(rows[k][a]));
        }
      body.points.insert(body.points.end(), rows[k].begin(), rows[k].end());
      for (int a = 0; a < D; ++a) {
        body.min[a] = k == 0 ? rows[k][a] : std::min(body.min[a], rows[k][a]);
        body.max[a] = k == 0 ? rows[k][a] : std::max(body.max[a], rows[k][a]);
      }
    }
  } catch (const Error& e) {
    body.points.clear();
    body.point_values = {};
    r.error(at, "unreadable points file", "a CSV or VTK .vtp file as docs/geometry.md describes", e.what(),
            "core (body)");
  }
}

// A 3D body inside a closed surface: its points seeded now on the grid's
// lattice (the surface module, geometry/surface.hpp), then a body of points.
void read_surface(SceneReader& r, const Scene& scene, const Parameters& b, const std::string& ptr, BodySpec& body) {
  const std::string at = ptr + "/surface_file";
  if (r.dim != 3) {
    r.error(at, "a surface in 2D", "surface_file in 3D scenes (in 2D: a polygon)", b.string("surface_file"), "core (body)");
    return;
  }
  if (refused_with_another_shape(r, b, ptr, "surface_file", "k0 on a body inside a surface",
                                 "a surface and another shape", "a body inside a surface",
                                 "either surface_file or a box, polygon or points_file"))
    return;
  if (!r.grid_ok) return;
  std::filesystem::path file = b.string("surface_file");
  if (file.is_relative()) file = r.base_dir / file;
  SurfaceLattice lattice;
  for (int a = 0; a < 3; ++a)
    lattice.origin[a] = scene.grid_origin[a], lattice.cell_size[a] = scene.grid_cell_size[a],
    lattice.cells[a] = scene.grid_cells[a];
  lattice.per_cell = static_cast<int>(b.integer("points_per_cell"));
  try {
    SurfaceSeeds seeds = seed_surface(file, lattice);
    body.points = std::move(seeds.points);
    body.min = seeds.min, body.max = seeds.max;
  } catch (const Error& e) {
    body.points.clear();
    r.error(at, "unusable surface", "a closed surface of triangles within the grid, in an STL or .vtp file",
            e.what(), "core (body)");
  }
}

// The body's shape: a box (min, max) or a polygon; either within the grid.
void read_shape(SceneReader& r, const Scene& scene, const Parameters& b, const std::string& ptr, BodySpec& body) {
  if (b.has("points_file")) {
    read_points(r, scene, b, ptr, body);
    return;
  }
  if (b.has("surface_file")) {
    read_surface(r, scene, b, ptr, body);
    return;
  }
  const bool polygon = b.has("polygon") || b.has("polygon_file");
  if (b.has("polygon") && b.has("polygon_file")) {
    r.error(ptr + "/polygon_file", "two polygons", "either \"polygon\" or \"polygon_file\"", "both", "core (body)");
    return;
  }
  if (b.has("holes") && !b.has("polygon")) {
    r.error(ptr + "/holes", "holes without an inline polygon",
            "holes with \"polygon\" (a polygon file gives its holes as rings)", "holes", "core (body)");
    return;
  }
  const bool extruded = polygon && r.dim == 3;
  if (!polygon && !(b.has("min") && b.has("max"))) {
    r.error(ptr + (b.has("min") ? "/max" : "/min"), "missing shape",
            "a box (min and max), a polygon (polygon or polygon_file), points_file or surface_file", "nothing", "core (body)");
    return;
  }
  if (polygon && r.dim == 2 && (b.has("min") || b.has("max"))) {
    r.error(ptr + (b.has("min") ? "/min" : "/max"), "a box and a polygon", "either min and max or a polygon",
            "both", "core (body)");
    return;
  }
  if (extruded && !(b.has("min") && b.has("max") && b.has("extrusion_axis"))) {
    r.error(ptr + (b.has("extrusion_axis") ? (b.has("min") ? "/max" : "/min") : "/extrusion_axis"),
            "a 3D polygon body without its extrusion",
            "extrusion_axis and min and max (the extrusion's ends along that axis)", "nothing", "core (body)");
    return;
  }
  if (!extruded && b.has("extrusion_axis")) {
    r.error(ptr + "/extrusion_axis", "extrusion without a 3D polygon", "extrusion_axis with a polygon in 3D",
            b.string("extrusion_axis"), "core (body)");
    return;
  }
  if (b.has("min")) body.min = to_array(b.vector("min"));
  if (b.has("max")) body.max = to_array(b.vector("max"));
  std::vector<int> box_axes;  // the axes whose extent min and max give
  for (int a = 0; a < r.dim; ++a) box_axes.push_back(a);
  if (polygon) {
    const std::optional<Polygon> read = read_polygon(r, b, ptr);
    if (!read) return;
    body.polygon = read;
    body.extrusion_axis = extruded ? b.string("extrusion_axis")[0] - 'x' : 2;
    box_axes = extruded ? std::vector<int>{body.extrusion_axis} : std::vector<int>{};
    const std::array<double, 4> bounds = polygon_bounds(*read);
    int plane = 0;
    for (int a = 0; a < r.dim; ++a) {
      if (a == body.extrusion_axis) continue;
      body.min[a] = bounds[plane];
      body.max[a] = bounds[plane + 2];
      ++plane;
    }
  }
  for (int a : box_axes)
    if (!(body.min[a] < body.max[a]))
      r.error(ptr + "/max/" + std::to_string(a), "empty box",
              "a value above min[" + std::to_string(a) + "] = " + format(body.min[a]), format(body.max[a]),
              "core (body)");
  if (!r.grid_ok) return;
  for (int a = 0; a < r.dim; ++a) {
    const double lo = scene.grid_origin[a];
    const double hi = lo + scene.grid_cell_size[a] * scene.grid_cells[a];
    const double tol = 1e-9 * scene.grid_cell_size[a];  // round-off in origin + h * cells
    if (body.min[a] >= lo - tol && body.max[a] <= hi + tol) continue;
    const bool below = body.min[a] < lo - tol;
    const bool from_box = std::find(box_axes.begin(), box_axes.end(), a) != box_axes.end();
    r.error(from_box ? ptr + (below ? "/min/" : "/max/") + std::to_string(a)
                     : ptr + (b.has("polygon_file") ? "/polygon_file" : "/polygon"),
            "body outside the grid",
            (from_box ? "a box within the grid [" : "a polygon within the grid along " + std::string(1, char('x' + a)) + " [") +
                format(lo) + ", " + format(hi) + "]",
            format(below ? body.min[a] : body.max[a]), "core (body)");
    return;
  }
}

void read_bodies(SceneReader& r, Scene& scene) {
  if (!r.require("bodies")) return;
  const Json& bodies = r.root["bodies"];
  if (!bodies.is_array() || bodies.empty()) {
    r.error("/bodies", "wrong type", "a non-empty array of bodies", show(bodies), "core (scene)");
    return;
  }
  std::vector<std::string> material_names;
  for (const auto& m : scene.materials) material_names.push_back(m.name);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string ptr = "/bodies/" + std::to_string(i);
    Parameters b = validate_object(bodies[i], body_schema(), ptr, "core (body)", r.dim, r.diags);
    BodySpec body;
    if (b.has("name")) body.name = b.string("name");
    // Messages name bodies: two of one name would be ambiguous.
    for (std::size_t k = 0; k < scene.bodies.size() && !body.name.empty(); ++k)
      if (scene.bodies[k].name == body.name)
        r.error(ptr + "/name", "duplicate body name", "a name no other body has", "\"" + body.name + "\", as /bodies/" +
                std::to_string(k) + "/name", "core (body)");
    if (body.name.empty()) body.name = "body " + std::to_string(i);
    if (b.has("points_per_cell")) body.points_per_cell = static_cast<int>(b.integer("points_per_cell"));
    if (b.has("velocity")) body.velocity = to_array(b.vector("velocity"));
    if (b.has("material")) {
      const std::string& mat = b.string("material");
      bool found = false;
      for (std::size_t m = 0; m < scene.materials.size(); ++m)
        if (scene.materials[m].name == mat) body.material = m, found = true;
      if (!found)
        r.error(ptr + "/material", "undefined material", "one of " + list(material_names), "\"" + mat + "\"",
                "core (body)");
    }
    if (b.has("liquid")) {
      const std::string& liquid = b.string("liquid");
      std::vector<std::string> names;
      for (std::size_t l = 0; l < scene.liquids.size(); ++l) {
        names.push_back(scene.liquids[l].name);
        if (scene.liquids[l].name == liquid) body.liquid = l;
      }
      if (!body.liquid)
        r.error(ptr + "/liquid", "undefined liquid", "one of " + list(names), "\"" + liquid + "\"", "core (body)");
      if (!b.has("porosity") && bodies[i].is_object() && !bodies[i].contains("porosity"))
        r.error(ptr + "/porosity", "missing porosity of a saturated body", "number in (0, 1) [-]", "nothing",
                "core (body)");
      if (b.has("material") && body.material < scene.materials.size() &&
          !scene.materials[body.material].permeability &&
          r.root["materials"].contains(scene.materials[body.material].name))
        r.error(pointer_append("/materials", scene.materials[body.material].name) + "/permeability",
                "missing permeability of a material in a saturated body",
                "a permeability law plugin node, e.g. {\"type\": \"permeability/constant\", ...}", "nothing",
                "core (material)");
    } else if (b.has("porosity")) {
      r.error(ptr + "/porosity", "porosity of a dry body", "no porosity without \"liquid\"",
              format(b.number("porosity")), "core (body)");
    }
    if (b.has("porosity")) body.porosity = b.number("porosity");
    if (b.has("water_table")) {
      body.water_table = b.number("water_table");
      if (!b.has("liquid"))
        r.error(ptr + "/water_table", "water table in a dry body", "no water_table without \"liquid\"",
                format(*body.water_table), "core (body)");
    }
    if (b.has("k0")) body.k0 = b.number("k0");
    read_gradation(r, bodies[i], b, ptr, body);
    read_fines(r, b, ptr, body);
    if (b.has("stress")) {
      const auto& s = b.vector("stress");
      for (std::size_t c = 0; c < s.size() && c < 6; ++c) body.stress[c] = s[c];
    }
    if (b.has("pore_pressure")) {
      body.pore_pressure = b.number("pore_pressure");
      if (body.pore_pressure != 0 && !b.has("liquid"))
        r.error(ptr + "/pore_pressure", "pore pressure of a dry body", "0 without \"liquid\"",
                format(body.pore_pressure), "core (body)");
    }
    read_shape(r, scene, b, ptr, body);
    scene.bodies.push_back(body);
  }
}

}  // namespace

SceneSection bodies_section() {
  return {"bodies", "body", "A box or polygon of material points of one material (an entry of /bodies)", body_schema,
          read_bodies};
}

}  // namespace suffuse::detail
