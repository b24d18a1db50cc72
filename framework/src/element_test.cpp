// Element tests: one material point of a phase driven along a path.
#include "suffuse/element_test.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <ostream>
#include <sstream>

#include "scene_reader.hpp"
#include "suffuse/error.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse {

namespace fs = std::filesystem;
using detail::Json;

namespace {

const std::vector<std::string> path_names = {"isotropic", "oedometer", "drained_triaxial", "undrained_triaxial"};

}  // namespace

ParameterSchema element_scene_schema() {
  ParameterSchema s;
  s.string("description").fallback(std::string()).doc("What the test shows");
  s.string_list("plugin_paths").fallback(std::vector<std::string>{}).doc(
      "Plugin libraries or directories searched first, relative to the scene file");
  s.number("initial_pressure").with_unit("Pa").above(0).doc(
      "Isotropic initial effective stress p'_0, compression positive; the phase's initialise() then sets its state");
  return s;
}

ParameterSchema element_stage_schema() {
  ParameterSchema s;
  s.choice("type", path_names).doc(
      "isotropic: equal normal strains; oedometer: axial strain, no lateral strain; drained_triaxial: axial "
      "strain at the lateral stress of the stage's start; undrained_triaxial: axial strain at constant volume");
  s.number("strain").with_unit("-").doc(
      "Strain of the stage, compression positive (negative: unloading): volumetric for isotropic, axial otherwise");
  s.integer("increments").with_unit("-").at_least(1).at_most(10000000).fallback(100LL).doc(
      "Increments of the stage (equal strain steps)");
  return s;
}

ElementScene parse_element_scene(const std::string& text, const std::string& name, const fs::path& base_dir,
                                 Registry& registry, PluginLoader& loader) {
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw SceneError(name, {{"", "not valid JSON", "a JSON object", e.what(), "core"}});
  }
  detail::SceneReader r(root, registry, detail::load_plugins_of(root, base_dir, loader));
  r.skipped_libraries = loader.warnings();
  r.dim = 3;
  ElementScene scene;
  scene.name = fs::path(name).stem().string();
  if (!root.is_object()) {
    r.error("", "wrong type", "a JSON object", detail::show(root), "core (element)");
    throw SceneError(name, r.diags);
  }
  const Parameters top =
      detail::validate_object(root, element_scene_schema(), "", "core (element)", 3, r.diags, {"material", "path"});
  if (top.has("initial_pressure")) scene.initial_pressure = top.number("initial_pressure");
  if (r.require("material")) scene.material = r.plugin_node(root["material"], "/material", PluginKind::Phase);
  if (r.require("path")) {
    const Json& path = root["path"];
    if (!path.is_array() || path.empty()) {
      r.error("/path", "wrong type", "a non-empty array of stages", detail::show(path), "core (element)");
    } else {
      for (std::size_t i = 0; i < path.size(); ++i) {
        const std::string ptr = "/path/" + std::to_string(i);
        const Parameters s =
            detail::validate_object(path[i], element_stage_schema(), ptr, "core (element stage)", 3, r.diags);
        if (!s.has("type") || !s.has("strain")) continue;
        const std::string& type = s.string("type");
        const auto at = std::find(path_names.begin(), path_names.end(), type) - path_names.begin();
        scene.stages.push_back(
            {static_cast<ElementPath>(at), s.number("strain"), static_cast<int>(s.integer("increments"))});
      }
    }
  }
  if (!r.diags.empty()) throw SceneError(name, r.diags);
  return scene;
}

ElementScene load_element_scene(const fs::path& file, Registry& registry, PluginLoader& loader) {
  std::ifstream in(file);
  if (!in) throw Error("cannot read scene file " + file.string());
  std::stringstream text;
  text << in.rdbuf();
  return parse_element_scene(text.str(), file.string(), fs::absolute(file).parent_path(), registry, loader);
}

namespace {

// The sample: one point in 3D, the phase, and the fields it reads.
class Sample {
 public:
  Sample(const ElementScene& scene, const Registry& registry) : points_(3) {
    const PluginInfo* info = registry.find(scene.material.type);
    // Fields of other parts a coupled phase reads: here they stay zero.
    if (info && info->required_fields)
      for (const std::string& f : info->required_fields(scene.material.params, 3))
        points_.add_field({f, FieldKind::Scalar, "-", "provided by the element test (zero)", false});
    first_own_field_ = points_.field_count();
    phase_ = registry.create<Phase>(scene.material.type, {scene.material.params, 3, scene.material.pointer});
    phase_->add_fields(points_);
    points_.append(1);
    double* s = stress();
    for (int c = 0; c < 6; ++c) s[c] = c < 3 ? -scene.initial_pressure : 0.0;
    phase_->initialise(points_, {0, 1});
    if (phase_->writes_eigenstrain())
      throw Error(scene.material.pointer + ": element tests do not apply eigenstrains yet (" + scene.material.type +
                  " writes one)");
  }

  double* stress() { return points_.data(points_.core().stress); }
  const tensor::Voigt& strain() const { return strain_; }

  // The phase's scalar output fields, for the CSV.
  std::vector<FieldId> reported_fields() const {
    std::vector<FieldId> ids;
    for (FieldId f = first_own_field_; f < points_.field_count(); ++f)
      if (points_.info(f).kind == FieldKind::Scalar && points_.info(f).output) ids.push_back(f);
    return ids;
  }
  const PointSet& points() const { return points_; }

  // One strain increment (tension positive, no spin).
  void apply(const tensor::Voigt& de) {
    double* L = points_.data(points_.core().velocity_gradient);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) L[i * 3 + j] = de[tensor::voigt_index(i, j)];
    phase_->update_stress(StressBatch{points_, {0, 1}, 1.0, {}});
    for (int c = 0; c < 6; ++c) strain_[c] += de[c];
  }

  // Axial strain de_yy with the lateral stress (xx = zz) held at `lateral`:
  // the lateral strain by the secant method, every field restored between
  // trials. False if it cannot be held.
  bool apply_at_lateral_stress(double de_axial, double lateral) {
    std::vector<std::vector<double>> start;
    for (FieldId f = 0; f < points_.field_count(); ++f)
      start.emplace_back(points_.values(f).begin(), points_.values(f).end());
    const tensor::Voigt strain0 = strain_;
    auto residual = [&](double x) {
      for (FieldId f = 0; f < points_.field_count(); ++f)
        std::copy(start[f].begin(), start[f].end(), points_.values(f).begin());
      strain_ = strain0;
      apply({x, de_axial, x, 0, 0, 0});
      return stress()[0] - lateral;
    };
    const double scale = std::abs(lateral) + std::abs(stress()[1]) + 1.0;
    double x0 = -0.5 * de_axial, r0 = residual(x0);
    double x1 = 0, r1 = residual(x1);
    for (int k = 0; k < 100 && std::abs(r1) > 1e-11 * scale; ++k) {
      if (r1 == r0) return false;
      const double x2 = x1 - r1 * (x1 - x0) / (r1 - r0);
      x0 = x1, r0 = r1, x1 = x2, r1 = residual(x1);
      if (!std::isfinite(r1)) return false;
    }
    return std::abs(r1) <= 1e-9 * scale;
  }

 private:
  PointSet points_;
  std::unique_ptr<Phase> phase_;
  FieldId first_own_field_ = 0;
  tensor::Voigt strain_{};
};

void write_row(std::ostream& csv, int increment, int stage, const Sample& s, const std::vector<FieldId>& fields) {
  const PointSet& pts = s.points();
  const double* sigma = pts.data(pts.core().stress);
  csv << increment << ',' << stage << ',' << tensor::volumetric_strain(s.strain().data()) + 0.0 << ','
      << tensor::deviatoric_strain(s.strain().data()) << ',' << tensor::mean_stress(sigma) << ','
      << tensor::deviatoric_stress(sigma) << ',' << tensor::stress_ratio(sigma);
  for (FieldId f : fields) csv << ',' << pts.data(f)[0];
  csv << '\n';
  csv.flush();
}

}  // namespace

int run_element_test(const ElementScene& scene, const Registry& registry, std::ostream& csv) {
  Sample sample(scene, registry);
  const std::vector<FieldId> fields = sample.reported_fields();
  csv.precision(17);  // round-trips a double
  csv << "increment,stage,eps_v [-],eps_s [-],p [Pa],q [Pa],eta [-]";
  for (FieldId f : fields) csv << ',' << sample.points().info(f).name << " [" << sample.points().info(f).unit << ']';
  csv << '\n';
  int increment = 0;
  write_row(csv, increment, -1, sample, fields);
  for (std::size_t k = 0; k < scene.stages.size(); ++k) {
    const ElementStage& stage = scene.stages[k];
    const double d = stage.strain / stage.increments;  // compression positive
    const double lateral = sample.stress()[0];
    for (int i = 0; i < stage.increments; ++i) {
      ++increment;
      auto where = [&] {
        return "path stage " + std::to_string(k) + " (" + path_names[static_cast<int>(stage.path)] + "), increment " +
               std::to_string(i + 1) + " of " + std::to_string(stage.increments);
      };
      switch (stage.path) {
        case ElementPath::isotropic: sample.apply({-d / 3, -d / 3, -d / 3, 0, 0, 0}); break;
        case ElementPath::oedometer: sample.apply({0, -d, 0, 0, 0, 0}); break;
        case ElementPath::undrained_triaxial: sample.apply({d / 2, -d, d / 2, 0, 0, 0}); break;
        case ElementPath::drained_triaxial:
          if (!sample.apply_at_lateral_stress(-d, lateral))
            throw Error(where() + ": failure: the lateral stress " + std::to_string(-lateral) +
                        " Pa cannot be held (the sample cannot carry the path)");
          break;
      }
      for (int c = 0; c < 6; ++c)
        if (!std::isfinite(sample.stress()[c])) throw Error(where() + ": failure: the stress is not finite");
      write_row(csv, increment, static_cast<int>(k), sample, fields);
    }
  }
  return increment;
}

}  // namespace suffuse
