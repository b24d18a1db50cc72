#include "suffuse/scene.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <iomanip>
#include <sstream>

#include "point_fields.hpp"
#include "validation.hpp"

namespace suffuse {

namespace fs = std::filesystem;
using json = detail::Json;
using detail::pointer_append;
using detail::show;

std::vector<CoreSection> core_sections() {
  std::vector<CoreSection> sections;
  {
    ParameterSchema s;
    s.string("description").fallback(std::string()).doc("What the scene shows and how to read its results");
    s.integer("dimension").at_least(2).at_most(3).with_unit("-").doc(
        "Spatial dimension: 2 (plane strain) or 3. A 1D column is a 2D strip one cell wide");
    s.string_list("plugin_paths").fallback(std::vector<std::string>{}).doc(
        "Plugin libraries or directories searched first, relative to the scene file");
    s.vector("gravity").with_unit("m/s^2").fallback(std::vector<double>{}).doc(
        "Gravitational acceleration, one component per dimension (default zero)");
    s.number("damping").at_least(0).below(1).with_unit("-").fallback(0.0).doc(
        "Local non-viscous damping coefficient for quasi-static problems (0: none)");
    sections.push_back({"scene", "Top level of a scene file; also holds the sections grid, time, "
                        "shape_function, materials, liquids, bodies, boundary_conditions and outputs", s});
  }
  {
    ParameterSchema s;
    s.vector("origin").with_unit("m").fallback(std::vector<double>{}).doc("Lower corner of the grid (default 0)");
    s.vector("cell_size").with_unit("m").above(0).doc("Cell edge length along each axis");
    s.vector("cells").with_unit("-").at_least(1).doc("Number of cells along each axis (integers)");
    sections.push_back({"grid", "Structured regular background grid", s});
  }
  {
    ParameterSchema s;
    s.number("end").with_unit("s").above(0).doc("Simulation end time");
    s.number("dt").with_unit("s").above(0).may_be_absent().doc(
        "Fixed time step; absent: automatic, cfl * h / max wave speed");
    s.number("cfl").with_unit("-").above(0).at_most(1).fallback(0.5).doc(
        "Courant factor of the automatic time step");
    s.number("mass_scaling").with_unit("-").at_least(1).fallback(1.0).doc(
        "Multiplies every inertia (not the weight) for quasi-static runs: the automatic step grows by its square "
        "root; dynamics are no longer physical. Printed in the run log and stored in <name>.run.json");
    sections.push_back({"time", "Time control", s});
  }
  {
    ParameterSchema s;
    s.string("name").fallback(std::string()).doc("Name of the body, for messages");
    s.string("material").doc("Name of a material defined under /materials");
    s.vector("min").with_unit("m").doc("Lower corner of the box filled with material points");
    s.vector("max").with_unit("m").doc("Upper corner of the box filled with material points");
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
        "Adds the geostatic effective stress of the body's own weight below its top (buoyant weight if saturated), "
        "with horizontal stress k0 times the vertical");
    sections.push_back({"body", "A box of material points of one material (an entry of /bodies)", s});
  }
  {
    ParameterSchema s;
    s.number("interval").with_unit("s").above(0).may_be_absent().doc(
        "Simulation time between frames; absent: end time / 20. The initial and final states are always written");
    sections.push_back({"output", "Keys every writer node accepts besides its plugin's own (an entry of /outputs)", s});
  }
  return sections;
}

namespace {

const ParameterSchema& section(const std::vector<CoreSection>& all, const std::string& name) {
  for (const auto& s : all)
    if (s.name == name) return s.schema;
  throw Error("internal: no core section " + name);
}

std::array<double, 3> to_array(const std::vector<double>& v) {
  std::array<double, 3> a{0, 0, 0};
  for (std::size_t i = 0; i < v.size() && i < 3; ++i) a[i] = v[i];
  return a;
}

// Numbers in messages: as short as possible, as precise as needed.
std::string format(double v) {
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

std::string list(const std::vector<std::string>& names) {
  std::string s = "{";
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
  return s + "}";
}

// A plugin no library on the search path registers: say where to add one.
constexpr const char* kUnknownPlugin =
    "unknown plugin (no library found registers it; `suffuse plugins` lists what was found; add its library "
    "with the scene's \"plugin_paths\" or $SUFFUSE_PLUGIN_PATH)";

class SceneReader {
 public:
  SceneReader(const json& root, Registry& registry) : root_(root), registry_(registry), sections_(core_sections()) {}

  Scene read(const std::string& name, std::vector<Diagnostic> earlier) {
    diags_ = std::move(earlier);
    Scene scene;
    if (!root_.is_object()) {
      error("", "wrong type", "a JSON object", show(root_), "core");
      throw SceneError(name, diags_);
    }
    const std::set<std::string> structured = {"grid", "time", "shape_function", "materials", "liquids",
                                              "bodies", "boundary_conditions", "outputs"};
    Parameters top = detail::validate_object(root_, section(sections_, "scene"), "", "core (scene)", 0,
                                             diags_, structured);
    dim_ = top.has("dimension") ? static_cast<int>(top.integer("dimension")) : 0;
    scene.dim = dim_ ? dim_ : 2;
    // A value that failed validation is absent: read only what is there.
    if (top.has("description")) scene.description = top.string("description");
    if (top.has("damping")) scene.damping = top.number("damping");
    if (dim_ && top.has("gravity")) {
      check_gravity_length();
      scene.gravity = to_array(top.vector("gravity"));
    }

    read_grid(scene);
    read_time(scene);
    if (require("shape_function"))
      scene.shape_function = plugin_node(root_["shape_function"], "/shape_function", PluginKind::ShapeFunction, {});
    read_materials(scene);
    read_liquids(scene);
    read_bodies(scene);
    if (root_.contains("boundary_conditions")) {
      const json& bcs = root_["boundary_conditions"];
      if (!bcs.is_array()) {
        error("/boundary_conditions", "wrong type", "array of boundary condition nodes", show(bcs), "core (scene)");
      } else {
        for (std::size_t i = 0; i < bcs.size(); ++i)
          scene.boundary_conditions.push_back(plugin_node(bcs[i], "/boundary_conditions/" + std::to_string(i),
                                                          PluginKind::BoundaryCondition, {}));
      }
    }
    read_outputs(scene);
    if (diags_.empty()) check_required_fields(scene);
    if (!diags_.empty()) throw SceneError(name, diags_);
    return scene;
  }

 private:
  void error(std::string ptr, std::string problem, std::string expected, std::string found, std::string by) {
    diags_.push_back({std::move(ptr), std::move(problem), std::move(expected), std::move(found), std::move(by)});
  }

  bool require(const std::string& key) {
    if (root_.contains(key)) return true;
    error("/" + key, "missing required section", "an object", "nothing", "core (scene)");
    return false;
  }

  // The top level is validated before its own "dimension" is known, so the
  // length of /gravity (one component per dimension) is checked here.
  void check_gravity_length() {
    if (!root_.contains("gravity")) return;  // the default, zero, fits any dimension
    const json& gravity = root_["gravity"];
    if (gravity.is_array() && static_cast<int>(gravity.size()) != dim_)
      error("/gravity", "wrong number of components", "array of " + std::to_string(dim_) + " numbers [m/s^2]",
            show(gravity), "core (scene)");
  }

  PluginNode plugin_node(const json& node, const std::string& ptr, PluginKind kind,
                         const std::set<std::string>& core_keys) {
    PluginNode result;
    result.pointer = ptr;
    const std::vector<std::string> valid = registry_.names_of(kind);
    const std::string kind_name = to_string(kind);
    const std::string article = std::string("aeiou").find(kind_name.front()) != std::string::npos ? "an " : "a ";
    const std::string expected = article + kind_name + " plugin, one of " + list(valid);
    if (!node.is_object()) {
      error(ptr, "wrong type", "an object with a \"type\" key naming " + expected, show(node), "core");
      return result;
    }
    if (!node.contains("type")) {
      error(ptr + "/type", "missing plugin type", expected, "nothing", "core");
      return result;
    }
    const json& type = node["type"];
    if (!type.is_string()) {
      error(ptr + "/type", "wrong type", expected, show(type), "core");
      return result;
    }
    result.type = type.get<std::string>();
    const PluginInfo* info = registry_.find(result.type);
    if (!info) {
      error(ptr + "/type", std::string(kUnknownPlugin), expected, "\"" + result.type + "\"", "core");
      return result;
    }
    if (info->kind != kind) {
      error(ptr + "/type", "plugin of the wrong kind (" + to_string(info->kind) + ")", expected,
            "\"" + result.type + "\"", "core");
      return result;
    }
    std::set<std::string> reserved = core_keys;
    reserved.insert("type");
    const std::size_t before = diags_.size();
    result.params = detail::validate_object(node, info->schema(), ptr, result.type, dim_, diags_, reserved);
    if (info->check && diags_.size() == before && dim_ != 0) {
      std::vector<ParameterIssue> issues;
      try {
        issues = info->check(result.params, dim_);
      } catch (const std::exception& e) {
        issues.push_back({"", std::string("the plugin's check failed: ") + e.what(), "", ""});
      }
      for (const ParameterIssue& issue : issues)
        error(issue.key.empty() ? ptr : pointer_append(ptr, issue.key), issue.problem, issue.expected, issue.found,
              result.type);
    }
    return result;
  }

  void read_grid(Scene& scene) {
    if (!require("grid")) return;
    const std::size_t before = diags_.size();
    Parameters g = detail::validate_object(root_["grid"], section(sections_, "grid"), "/grid", "core (grid)",
                                           dim_, diags_);
    grid_ok_ = diags_.size() == before && dim_ != 0;
    if (g.has("origin")) scene.grid_origin = to_array(g.vector("origin"));
    if (g.has("cell_size")) scene.grid_cell_size = to_array(g.vector("cell_size"));
    if (g.has("cells")) {
      const auto& c = g.vector("cells");
      double nodes = 1;
      bool cells_ok = true;
      for (std::size_t a = 0; a < c.size() && a < 3; ++a) {
        const std::string ptr = "/grid/cells/" + std::to_string(a);
        if (c[a] != std::floor(c[a])) {
          error(ptr, "not an integer", "integer >= 1", show(root_["grid"]["cells"][a]), "core (grid)");
          cells_ok = false;
        } else if (c[a] > max_cells_per_axis) {
          error(ptr, "value too large", "integer <= " + format(max_cells_per_axis),
                show(root_["grid"]["cells"][a]), "core (grid)");
          cells_ok = false;
        } else {
          scene.grid_cells[a] = static_cast<int>(c[a]);
          nodes *= c[a] + 1;
        }
      }
      if (cells_ok && nodes > max_nodes) {
        error("/grid/cells", "grid too large", "at most " + format(max_nodes) + " nodes", format(nodes) + " nodes",
              "core (grid)");
        cells_ok = false;
      }
      grid_ok_ = grid_ok_ && cells_ok;
    }
  }

  void read_time(Scene& scene) {
    if (!require("time")) return;
    Parameters t = detail::validate_object(root_["time"], section(sections_, "time"), "/time", "core (time)",
                                           dim_, diags_);
    if (t.has("end")) scene.end_time = t.number("end");
    scene.dt = t.maybe_number("dt");
    if (t.has("cfl")) scene.cfl = t.number("cfl");
    if (t.has("mass_scaling")) scene.mass_scaling = t.number("mass_scaling");
  }

  void read_materials(Scene& scene) {
    if (!require("materials")) return;
    const json& materials = root_["materials"];
    if (!materials.is_object() || materials.empty()) {
      error("/materials", "wrong type", "an object naming at least one material", show(materials), "core (scene)");
      return;
    }
    for (const auto& [name, node] : materials.items()) {
      MaterialSpec m;
      m.name = name;
      const std::string ptr = pointer_append("/materials", name);
      m.phase = plugin_node(node, ptr, PluginKind::Phase, {"permeability", "erosion"});
      if (node.is_object() && node.contains("permeability"))
        m.permeability = plugin_node(node["permeability"], ptr + "/permeability", PluginKind::PermeabilityLaw, {});
      if (node.is_object() && node.contains("erosion"))
        m.erosion = plugin_node(node["erosion"], ptr + "/erosion", PluginKind::ErosionLaw, {});
      scene.materials.push_back(std::move(m));
    }
  }

  void read_liquids(Scene& scene) {
    if (!root_.contains("liquids")) return;
    const json& liquids = root_["liquids"];
    if (!liquids.is_object()) {
      error("/liquids", "wrong type", "an object naming liquids", show(liquids), "core (scene)");
      return;
    }
    for (const auto& [name, node] : liquids.items())
      scene.liquids.push_back({name, plugin_node(node, pointer_append("/liquids", name), PluginKind::Liquid, {})});
  }

  // Fines belong to saturated bodies: without a liquid there is nothing to carry them.
  void read_fines(const Parameters& b, const std::string& ptr, BodySpec& body) {
    auto value = [&](const char* key) { return b.has(key) ? b.number(key) : 0.0; };
    body.fines_content = value("fines_content");
    body.ultimate_fines_content = value("ultimate_fines_content");
    body.concentration = value("concentration");
    for (const char* key : {"fines_content", "ultimate_fines_content", "concentration"}) {
      const double v = value(key);
      if (v != 0 && !b.has("liquid"))
        error(ptr + "/" + key, "fines in a dry body", "0 without \"liquid\"", format(v), "core (body)");
    }
    if (body.ultimate_fines_content > body.fines_content)
      error(ptr + "/ultimate_fines_content", "ultimate fines content above the initial one",
            "at most fines_content = " + format(body.fines_content), format(body.ultimate_fines_content),
            "core (body)");
  }

  void read_bodies(Scene& scene) {
    if (!require("bodies")) return;
    const json& bodies = root_["bodies"];
    if (!bodies.is_array() || bodies.empty()) {
      error("/bodies", "wrong type", "a non-empty array of bodies", show(bodies), "core (scene)");
      return;
    }
    std::vector<std::string> material_names;
    for (const auto& m : scene.materials) material_names.push_back(m.name);
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      const std::string ptr = "/bodies/" + std::to_string(i);
      Parameters b = detail::validate_object(bodies[i], section(sections_, "body"), ptr, "core (body)", dim_, diags_);
      BodySpec body;
      if (b.has("name")) body.name = b.string("name");
      if (body.name.empty()) body.name = "body " + std::to_string(i);
      if (b.has("points_per_cell")) body.points_per_cell = static_cast<int>(b.integer("points_per_cell"));
      if (b.has("velocity")) body.velocity = to_array(b.vector("velocity"));
      if (b.has("material")) {
        const std::string& mat = b.string("material");
        bool found = false;
        for (std::size_t m = 0; m < scene.materials.size(); ++m)
          if (scene.materials[m].name == mat) body.material = m, found = true;
        if (!found)
          error(ptr + "/material", "undefined material", "one of " + list(material_names), "\"" + mat + "\"",
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
          error(ptr + "/liquid", "undefined liquid", "one of " + list(names), "\"" + liquid + "\"", "core (body)");
        if (!b.has("porosity") && bodies[i].is_object() && !bodies[i].contains("porosity"))
          error(ptr + "/porosity", "missing porosity of a saturated body", "number in (0, 1) [-]", "nothing",
                "core (body)");
        if (b.has("material") && body.material < scene.materials.size() &&
            !scene.materials[body.material].permeability &&
            root_["materials"].contains(scene.materials[body.material].name))
          error(pointer_append("/materials", scene.materials[body.material].name) + "/permeability",
                "missing permeability of a material in a saturated body",
                "a permeability law plugin node, e.g. {\"type\": \"permeability/constant\", ...}", "nothing",
                "core (material)");
      } else if (b.has("porosity")) {
        error(ptr + "/porosity", "porosity of a dry body", "no porosity without \"liquid\"",
              format(b.number("porosity")), "core (body)");
      }
      if (b.has("porosity")) body.porosity = b.number("porosity");
      if (b.has("water_table")) {
        body.water_table = b.number("water_table");
        if (!b.has("liquid"))
          error(ptr + "/water_table", "water table in a dry body", "no water_table without \"liquid\"",
                format(*body.water_table), "core (body)");
      }
      if (b.has("k0")) body.k0 = b.number("k0");
      read_fines(b, ptr, body);
      if (b.has("stress")) {
        const auto& s = b.vector("stress");
        for (std::size_t c = 0; c < s.size() && c < 6; ++c) body.stress[c] = s[c];
      }
      if (b.has("pore_pressure")) {
        body.pore_pressure = b.number("pore_pressure");
        if (body.pore_pressure != 0 && !b.has("liquid"))
          error(ptr + "/pore_pressure", "pore pressure of a dry body", "0 without \"liquid\"",
                format(body.pore_pressure), "core (body)");
      }
      if (b.has("min") && b.has("max")) {
        body.min = to_array(b.vector("min"));
        body.max = to_array(b.vector("max"));
        for (int a = 0; a < dim_; ++a) {
          if (!(body.min[a] < body.max[a]))
            error(ptr + "/max/" + std::to_string(a), "empty box",
                  "a value above min[" + std::to_string(a) + "] = " + format(body.min[a]), format(body.max[a]),
                  "core (body)");
          if (!grid_ok_) continue;
          const double lo = scene.grid_origin[a];
          const double hi = lo + scene.grid_cell_size[a] * scene.grid_cells[a];
          const double tol = 1e-9 * scene.grid_cell_size[a];  // round-off in origin + h * cells
          if (body.min[a] < lo - tol || body.max[a] > hi + tol)
            error(ptr + (body.min[a] < lo - tol ? "/min/" : "/max/") + std::to_string(a), "body outside the grid",
                  "a box within the grid [" + format(lo) + ", " + format(hi) + "]",
                  format(body.min[a] < lo - tol ? body.min[a] : body.max[a]), "core (body)");
        }
      }
      scene.bodies.push_back(body);
    }
  }

  void read_outputs(Scene& scene) {
    if (!root_.contains("outputs")) return;
    const json& outputs = root_["outputs"];
    if (!outputs.is_array()) {
      error("/outputs", "wrong type", "array of writer nodes", show(outputs), "core (scene)");
      return;
    }
    const ParameterSchema& core = section(sections_, "output");
    for (std::size_t i = 0; i < outputs.size(); ++i) {
      const std::string ptr = "/outputs/" + std::to_string(i);
      OutputSpec out;
      std::set<std::string> core_keys;
      for (const Param& p : core.params()) core_keys.insert(p.name);
      out.writer = plugin_node(outputs[i], ptr, PluginKind::Writer, core_keys);
      if (outputs[i].is_object()) {
        // Unknown keys are the plugin's to report: the core checks only its own.
        std::set<std::string> others;
        for (const auto& [k, v] : outputs[i].items())
          if (!core_keys.count(k)) others.insert(k);
        Parameters o = detail::validate_object(outputs[i], core, ptr, "core (output)", dim_, diags_, others);
        out.interval = o.maybe_number("interval");
      }
      scene.outputs.push_back(std::move(out));
    }
  }

  // Plugins that read point fields of other parts (a phase coupled to the
  // erosion): each field must be one this scene's run provides.
  void check_required_fields(const Scene& scene) {
    const std::vector<detail::ProvidedField> fields = detail::point_fields_of(scene, registry_);
    std::vector<const PluginNode*> nodes = {&scene.shape_function};
    for (const MaterialSpec& m : scene.materials) {
      nodes.push_back(&m.phase);
      if (m.permeability) nodes.push_back(&*m.permeability);
      if (m.erosion) nodes.push_back(&*m.erosion);
    }
    for (const LiquidSpec& l : scene.liquids) nodes.push_back(&l.liquid);
    for (const PluginNode& bc : scene.boundary_conditions) nodes.push_back(&bc);
    for (const OutputSpec& o : scene.outputs) nodes.push_back(&o.writer);
    for (const PluginNode* node : nodes) {
      const PluginInfo* info = registry_.find(node->type);
      if (!info || !info->required_fields) continue;
      for (const std::string& name : info->required_fields(node->params, dim_)) {
        auto f = std::find_if(fields.begin(), fields.end(), [&](const auto& p) { return p.name == name; });
        if (f == fields.end())
          error(node->pointer + "/type", "reads point field '" + name + "', which no part of the core provides",
                "a plugin reading fields of the core (see docs/plugins.md)", "\"" + node->type + "\"", node->type);
        else if (!f->provided)
          error(node->pointer + "/type", "reads point field '" + name + "', which this scene does not provide",
                "a scene where it exists: it comes from " + f->owner, "\"" + node->type + "\"", node->type);
      }
    }
  }

  const json& root_;
  Registry& registry_;
  std::vector<CoreSection> sections_;
  std::vector<Diagnostic> diags_;
  int dim_ = 0;
  bool grid_ok_ = false;  // the grid is valid, so bodies can be checked against it
  static constexpr double max_cells_per_axis = 1e8;
  static constexpr double max_nodes = 2147483647.0;  // node ids stay within 31 bits
};

}  // namespace

Scene parse_scene(const std::string& text, const std::string& name, const fs::path& base_dir, Registry& registry,
                  PluginLoader& loader) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    throw SceneError(name, {{"", "not valid JSON", "a JSON object", e.what(), "core"}});
  }
  // Plugins first: their schemas are needed to validate the rest.
  std::vector<Diagnostic> path_errors;
  if (root.is_object() && root.contains("plugin_paths") && root["plugin_paths"].is_array()) {
    const json& paths = root["plugin_paths"];
    for (std::size_t i = 0; i < paths.size(); ++i) {
      if (!paths[i].is_string()) continue;  // reported by validation
      fs::path path = paths[i].get<std::string>();
      if (path.is_relative()) path = base_dir / path;
      std::error_code ec;
      if (!fs::exists(path, ec)) {
        path_errors.push_back({"/plugin_paths/" + std::to_string(i), "no such file or directory",
                               "a plugin library or a directory of them", path.string(), "core (scene)"});
        continue;
      }
      loader.load_path(path);  // a library that exists but fails to load is fatal
    }
  }
  for (const auto& path : PluginLoader::default_search_path()) loader.load_path(path);

  Scene scene = SceneReader(root, registry).read(name, std::move(path_errors));
  scene.name = fs::path(name).stem().string();
  return scene;
}

Scene load_scene(const fs::path& file, Registry& registry, PluginLoader& loader) {
  std::ifstream in(file);
  if (!in) throw Error("cannot read scene file " + file.string());
  std::stringstream text;
  text << in.rdbuf();
  Scene scene = parse_scene(text.str(), file.string(), fs::absolute(file).parent_path(), registry, loader);
  scene.file = file;
  scene.name = file.stem().string();
  return scene;
}

}  // namespace suffuse
