// Element tests: one material point of a phase driven along a path.
#include "suffuse/element_test.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>

#include "scene_reader.hpp"
#include "suffuse/error.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse {

namespace fs = std::filesystem;
using detail::Json;

namespace {

const std::vector<std::string> path_names = {"isotropic", "oedometer", "drained_triaxial", "undrained_triaxial",
                                             "stress_controlled"};

// A stage's "inputs": {"field": end value, ...}, each a field the phase reads.
std::vector<ElementInput> read_inputs(const Json& node, const std::string& ptr, const std::vector<std::string>& fields,
                                      detail::SceneReader& r) {
  std::vector<ElementInput> inputs;
  const std::string by = "core (element stage)";
  if (!node.is_object()) {
    r.error(ptr, "wrong type", "an object of field names and their values at the stage's end", detail::show(node), by);
    return inputs;
  }
  for (const auto& [name, value] : node.items()) {
    if (std::find(fields.begin(), fields.end(), name) == fields.end())
      r.error(ptr + "/" + name, "not a field the material reads",
              fields.empty() ? std::string("no inputs (the material reads no other part's field)")
                             : "one of " + detail::list(fields),
              name, by);
    else if (!value.is_number() || !std::isfinite(value.get<double>()))
      r.error(ptr + "/" + name, "wrong type", "a finite number (the field's value at the stage's end)",
              detail::show(value), by);
    else
      inputs.push_back({name, value.get<double>()});
  }
  return inputs;
}

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
      "strain at the lateral stress of the stage's start; undrained_triaxial: axial strain at constant volume; "
      "stress_controlled: axial and lateral stresses driven to p and q (held where absent: a hold), the strains "
      "follow");
  s.number("strain").with_unit("-").may_be_absent().doc(
      "Strain of the stage, compression positive (negative: unloading): volumetric for isotropic, axial otherwise; "
      "required by every type but stress_controlled");
  s.integer("increments").with_unit("-").at_least(1).at_most(10000000).fallback(100LL).doc(
      "Increments of the stage (equal strain, stress and input steps)");
  s.number("p").with_unit("Pa").above(0).may_be_absent().doc(
      "stress_controlled: mean effective stress p' at the stage's end, compression positive (absent: held)");
  s.number("q").with_unit("Pa").may_be_absent().doc(
      "stress_controlled: deviator stress q = sigma_axial - sigma_lateral at the stage's end, compression positive, "
      "negative in extension (absent: held)");
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
  std::vector<std::string> inputs;  // the coupling fields the phase reads, which stages may drive
  if (r.require("material")) {
    scene.material = r.plugin_node(root["material"], "/material", PluginKind::Phase);
    const PluginInfo* info = registry.find(scene.material.type);
    if (info && info->required_fields && r.diags.empty())
      for (const std::string& f : info->required_fields(scene.material.params, 3))
        if (!f.ends_with("_increment")) inputs.push_back(f);
  }
  if (r.require("path")) {
    const Json& path = root["path"];
    if (!path.is_array() || path.empty()) {
      r.error("/path", "wrong type", "a non-empty array of stages", detail::show(path), "core (element)");
    } else {
      for (std::size_t i = 0; i < path.size(); ++i) {
        const std::string ptr = "/path/" + std::to_string(i);
        const Parameters s = detail::validate_object(path[i], element_stage_schema(), ptr, "core (element stage)", 3,
                                                     r.diags, {"inputs"});
        if (!s.has("type")) continue;
        ElementStage stage;
        const std::string& type = s.string("type");
        stage.path = static_cast<ElementPath>(std::find(path_names.begin(), path_names.end(), type) - path_names.begin());
        stage.increments = static_cast<int>(s.integer("increments"));
        const bool stress_controlled = stage.path == ElementPath::stress_controlled;
        if (s.has("strain") && !stress_controlled) stage.strain = s.number("strain");
        if (!s.has("strain") && !stress_controlled)
          r.error(ptr + "/strain", "missing key", "the stage's strain (number, compression positive)", "absent",
                  "core (element stage)");
        if (stress_controlled && s.has("strain"))
          r.error(ptr + "/strain", "not a key of this stage", "p and q (a stress_controlled stage's strains follow)",
                  detail::format(s.number("strain")), "core (element stage)");
        for (const char* key : {"p", "q"})
          if (s.has(key) && !stress_controlled)
            r.error(ptr + "/" + key, "not a key of this stage", "strain (" + type + " is strain-controlled)",
                    detail::format(s.number(key)), "core (element stage)");
        if (stress_controlled) stage.p = s.maybe_number("p"), stage.q = s.maybe_number("q");
        if (path[i].is_object() && path[i].contains("inputs"))
          stage.inputs = read_inputs(path[i]["inputs"], ptr + "/inputs", inputs, r);
        scene.stages.push_back(std::move(stage));
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

// Control of one increment of a triaxial-type path: each normal component
// (xx, yy, zz; y is the axial direction) has either a strain increment or a
// target stress (tension positive); shear strains stay zero.
// With equal_lateral, xx and zz share one strain (a cylindrical sample under
// a cell pressure) and the mean of their stresses is controlled.
struct NormalControl {
  std::array<std::optional<double>, 3> strain, stress;
  bool equal_lateral = false;
};

// The sample: one point in 3D, the phase, and the fields it reads.
class Sample {
 public:
  Sample(const ElementScene& scene, const Registry& registry) : points_(3) {
    const PluginInfo* info = registry.find(scene.material.type);
    // Fields of other parts a coupled phase reads: zero unless a stage's
    // inputs drive them.
    first_reported_ = points_.field_count();
    if (info && info->required_fields)
      for (const std::string& f : info->required_fields(scene.material.params, 3))
        points_.add_field({f, FieldKind::Scalar, "-", "provided by the element test", !f.ends_with("_increment")});
    phase_ = registry.create<Phase>(scene.material.type, {scene.material.params, 3, scene.material.pointer});
    phase_->add_fields(points_);
    points_.append(1);
    double* s = stress();
    for (int c = 0; c < 6; ++c) s[c] = c < 3 ? -scene.initial_pressure : 0.0;
    phase_->initialise(points_, {0, 1});
  }

  double* stress() { return points_.data(points_.core().stress); }
  const tensor::Voigt& strain() const { return strain_; }
  double field(const std::string& name) const { return points_.data(points_.id(name))[0]; }

  // Sets an input field for the next increment and its "_increment" field
  // (if the phase reads it) to the change.
  void set_input(const std::string& name, double value) {
    double& v = points_.data(points_.id(name))[0];
    if (const auto inc = points_.find(name + "_increment")) points_.data(*inc)[0] = value - v;
    v = value;
  }

  // The scalar fields of the CSV: the inputs a coupled phase reads, then the
  // phase's own outputs.
  std::vector<FieldId> reported_fields() const {
    std::vector<FieldId> ids;
    for (FieldId f = first_reported_; f < points_.field_count(); ++f)
      if (points_.info(f).kind == FieldKind::Scalar && points_.info(f).output) ids.push_back(f);
    return ids;
  }
  const PointSet& points() const { return points_; }

  // One strain increment (tension positive, no spin). A phase that writes an
  // eigenstrain writes it first; `de` is the total strain increment.
  void apply(const tensor::Voigt& de) {
    double* L = points_.data(points_.core().velocity_gradient);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) L[i * 3 + j] = de[tensor::voigt_index(i, j)];
    std::array<double, 6> eigenstrain{};
    std::span<const double> imposed;
    if (phase_->writes_eigenstrain()) {
      phase_->eigenstrain(StressBatch{points_, {0, 1}, 1.0, {}}, eigenstrain);
      imposed = eigenstrain;
    }
    phase_->update_stress(StressBatch{points_, {0, 1}, 1.0, imposed});
    for (int c = 0; c < 6; ++c) strain_[c] += de[c];
  }

  // One increment under mixed control: the unknown normal strains by Newton
  // with a central-difference Jacobian and a backtracking line search, every
  // field restored between trials, until the stresses match their targets to
  // 1e-11 of the stress scale. False if they cannot be reached (the sample
  // cannot carry the stress).
  bool apply(const NormalControl& control) {
    // The unknowns, each a group of normal components with one strain.
    std::vector<std::vector<int>> free;
    for (int c = 0; c < 3; ++c)
      if (!control.strain[c]) {
        if (c == 2 && control.equal_lateral && !control.strain[0])
          free.front().push_back(2);
        else
          free.push_back({c});
      }
    if (free.empty()) {
      apply(tensor::Voigt{*control.strain[0], *control.strain[1], *control.strain[2], 0, 0, 0});
      return true;
    }
    const std::size_t n = free.size();
    std::vector<std::vector<double>> start;
    for (FieldId f = 0; f < points_.field_count(); ++f)
      start.emplace_back(points_.values(f).begin(), points_.values(f).end());
    const tensor::Voigt strain0 = strain_;
    double scale = 1;
    for (int c = 0; c < 3; ++c) scale += std::abs(stress()[c]) + std::abs(control.stress[c].value_or(0));
    using Vec = Eigen::VectorXd;
    auto residual = [&](const Vec& x) {
      for (FieldId f = 0; f < points_.field_count(); ++f)
        std::copy(start[f].begin(), start[f].end(), points_.values(f).begin());
      strain_ = strain0;
      tensor::Voigt de{};
      for (int c = 0; c < 3; ++c) de[c] = control.strain[c].value_or(0);
      for (std::size_t k = 0; k < n; ++k)
        for (int c : free[k]) de[c] = x[static_cast<Eigen::Index>(k)];
      apply(de);
      Vec r = Vec::Zero(static_cast<Eigen::Index>(n));
      for (std::size_t k = 0; k < n; ++k)
        for (int c : free[k])
          r[static_cast<Eigen::Index>(k)] += (stress()[c] - *control.stress[c]) / (scale * static_cast<double>(free[k].size()));
      return r;
    };
    Vec x = Vec::Zero(static_cast<Eigen::Index>(n)), r = residual(x);
    for (int it = 0; it < 60 && r.norm() > 1e-11; ++it) {
      const double h = 1e-9 + 1e-6 * x.lpNorm<Eigen::Infinity>();
      Eigen::MatrixXd J(n, n);
      for (std::size_t k = 0; k < n; ++k) {
        Vec xp = x, xm = x;
        xp[static_cast<Eigen::Index>(k)] += h;
        xm[static_cast<Eigen::Index>(k)] -= h;
        J.col(static_cast<Eigen::Index>(k)) = (residual(xp) - residual(xm)) / (2 * h);
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(J);
      if (!lu.isInvertible() || !J.allFinite()) return false;
      const Vec dx = lu.solve(-r);
      double step = 1;
      Vec trial = residual(x + dx);
      for (int k = 0; k < 20 && !(trial.norm() < r.norm()); ++k) trial = residual(x + (step *= 0.5) * dx);
      if (!(trial.norm() < r.norm())) return false;
      x += step * dx;
      r = trial;
    }
    if (!(r.norm() <= 1e-9)) return false;
    residual(x);  // leave the sample in the converged state
    return true;
  }

 private:
  PointSet points_;
  std::unique_ptr<Phase> phase_;
  FieldId first_reported_ = 0;
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
    // The stage's start: lateral (xx = zz) and axial (yy) stress, inputs.
    const double lateral = sample.stress()[0], axial = sample.stress()[1];
    const double p0 = -(2 * lateral + axial) / 3, q0 = lateral - axial;
    std::vector<double> input0;
    for (const ElementInput& in : stage.inputs) input0.push_back(sample.field(in.field));
    for (int i = 0; i < stage.increments; ++i) {
      ++increment;
      auto where = [&] {
        return "path stage " + std::to_string(k) + " (" + path_names[static_cast<int>(stage.path)] + "), increment " +
               std::to_string(i + 1) + " of " + std::to_string(stage.increments);
      };
      const double along = static_cast<double>(i + 1) / stage.increments;
      for (std::size_t j = 0; j < stage.inputs.size(); ++j)
        sample.set_input(stage.inputs[j].field, input0[j] + along * (stage.inputs[j].end_value - input0[j]));
      NormalControl control;
      switch (stage.path) {
        case ElementPath::isotropic: control.strain = {-d / 3, -d / 3, -d / 3}; break;
        case ElementPath::oedometer: control.strain = {0.0, -d, 0.0}; break;
        case ElementPath::undrained_triaxial: control.strain = {d / 2, -d, d / 2}; break;
        case ElementPath::drained_triaxial:
          control.strain[1] = -d;
          control.stress[0] = control.stress[2] = lateral;
          control.equal_lateral = true;
          break;
        case ElementPath::stress_controlled: {
          const double p = p0 + along * (stage.p.value_or(p0) - p0), q = q0 + along * (stage.q.value_or(q0) - q0);
          control.stress = {-(p - q / 3), -(p + 2 * q / 3), -(p - q / 3)};
          break;
        }
      }
      if (!sample.apply(control)) {
        if (stage.path == ElementPath::drained_triaxial)
          throw Error(where() + ": failure: the lateral stress " + detail::format(-lateral) +
                      " Pa cannot be held (the sample cannot carry the path)");
        throw Error(where() + ": failure: the stress p' = " + detail::format(-(control.stress[0].value() * 2 + control.stress[1].value()) / 3) +
                    " Pa, q = " + detail::format(control.stress[0].value() - control.stress[1].value()) +
                    " Pa cannot be held (the sample cannot carry it)");
      }
      for (int c = 0; c < 6; ++c)
        if (!std::isfinite(sample.stress()[c])) throw Error(where() + ": failure: the stress is not finite");
      write_row(csv, increment, static_cast<int>(k), sample, fields);
    }
  }
  return increment;
}

}  // namespace suffuse
