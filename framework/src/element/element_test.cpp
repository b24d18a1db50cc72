// Element tests: one material point of a phase driven along a path.
#include "suffuse/element_test.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>

#include "mpm/material_phase.hpp"
#include "scene/scene_reader.hpp"
#include "suffuse/error.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse {

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
  Sample(const ElementScene& scene, const Registry& registry)
      : points_(3), phase_(registry, scene.material, scene.material_base, 3) {
    // Fields of other parts a coupled phase (or its base) reads: zero unless
    // a stage's inputs drive them.
    first_reported_ = points_.field_count();
    for (const PluginNode* node : {&scene.material, scene.material_base ? &*scene.material_base : nullptr}) {
      const PluginInfo* info = node ? registry.find(node->type) : nullptr;
      if (info && info->required_fields)
        for (const std::string& f : info->required_fields(node->params, 3))
          if (!points_.find(f))
            points_.add_field({f, FieldKind::Scalar, "-", "provided by the element test", !f.ends_with("_increment")});
    }
    first_own_ = points_.field_count();
    phase_.add_fields(points_);
    points_.append(1);
    double* s = stress();
    for (int c = 0; c < 6; ++c) s[c] = c < 3 ? -scene.initial_pressure : 0.0;
    phase_.phase().initialise(points_, {0, 1});
  }

  double* stress() { return points_.data(points_.core().stress); }
  const tensor::Voigt& strain() const { return strain_; }
  double field(const std::string& name) const { return points_.data(points_.id(name))[0]; }

  // Zeroes the "_increment" fields the test provides: an increment without
  // inputs changes none of them.
  void clear_input_increments() {
    for (FieldId f = first_reported_; f < first_own_; ++f)
      if (points_.info(f).name.ends_with("_increment")) points_.data(f)[0] = 0;
  }
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
    const Phase& phase = phase_.phase();
    if (phase.writes_eigenstrain()) {
      phase.eigenstrain(StressBatch{points_, {0, 1}, 1.0, {}}, eigenstrain);
      imposed = eigenstrain;
    }
    // The total strain, in the sample and in the core's field, updated before
    // the stress as in a run.
    double* strain = points_.data(points_.core().strain);
    for (int c = 0; c < 6; ++c) strain_[c] += de[c], strain[c] += de[c];
    phase.update_stress(StressBatch{points_, {0, 1}, 1.0, imposed, 1.0, false});
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
  detail::MaterialPhase phase_;
  FieldId first_reported_ = 0, first_own_ = 0;  // the test's fields: [first_reported_, first_own_)
  tensor::Voigt strain_{};
};

// The values of a CSV row after `increment,stage`: eps_v, eps_s, p, q, eta,
// then the reported fields; and their names.
std::vector<std::string> row_names(const Sample& s, const std::vector<FieldId>& fields) {
  std::vector<std::string> names = {"eps_v", "eps_s", "p", "q", "eta"};
  for (FieldId f : fields) names.push_back(s.points().info(f).name);
  return names;
}

std::vector<double> row_values(const Sample& s, const std::vector<FieldId>& fields) {
  const PointSet& pts = s.points();
  const double* sigma = pts.data(pts.core().stress);
  std::vector<double> v = {tensor::volumetric_strain(s.strain().data()) + 0.0,
                           tensor::deviatoric_strain(s.strain().data()), tensor::mean_stress(sigma),
                           tensor::deviatoric_stress(sigma), tensor::stress_ratio(sigma)};
  for (FieldId f : fields) v.push_back(pts.data(f)[0]);
  return v;
}

void write_row(std::ostream& csv, int increment, int stage, const std::vector<double>& values) {
  csv << increment << ',' << stage;
  for (double v : values) csv << ',' << v;
  csv << '\n';
  csv.flush();
}

}  // namespace

std::string ElementEvent::message() const {
  std::ostringstream m;
  m.precision(6);
  if (failure)
    m << "path stage " << stage << ": failure at row " << increment << " (the CSV's increment): "
      << (reason.empty() ? "the stress cannot be held (the sample collapses)" : reason)
      << "; the last increment carried had";
  else
    m << "path stage " << stage << ": " << limit.field << " reached " << limit.value << " at row " << increment
      << " (the CSV's increment), with";
  for (const auto& [name, value] : at)
    if (name != limit.field &&
        (name == "eps_v" || name == "eps_s" || std::find(inputs.begin(), inputs.end(), name) != inputs.end()))
      m << ' ' << name << ' ' << value;
  return m.str();
}

ElementResult run_element_test(const ElementScene& scene, std::size_t index, const Registry& registry,
                               std::ostream& csv) {
  if (index >= scene.cases.size()) throw Error("element test: no case " + std::to_string(index));
  const std::vector<ElementStage>& stages = scene.cases[index].stages;
  Sample sample(scene, registry);
  const std::vector<FieldId> fields = sample.reported_fields();
  const std::vector<std::string> names = row_names(sample, fields);
  csv.precision(17);  // round-trips a double
  csv << "increment [-],stage [-],eps_v [-],eps_s [-],p [Pa],q [Pa],eta [-]";
  for (FieldId f : fields) csv << ',' << sample.points().info(f).name << " [" << sample.points().info(f).unit << ']';
  csv << '\n';
  ElementResult result;
  int& increment = result.increments;
  std::vector<double> previous = row_values(sample, fields);
  write_row(csv, increment, -1, previous);
  for (std::size_t k = 0; k < stages.size(); ++k) {
    const ElementStage& stage = stages[k];
    const double d = stage.strain / stage.increments;  // compression positive
    // The stage's start: lateral (xx = zz) and axial (yy) stress, inputs.
    const double lateral = sample.stress()[0], axial = sample.stress()[1];
    const double p0 = -(2 * lateral + axial) / 3, q0 = lateral - axial;
    // A target stress ratio along the drained path: p' = sigma_lateral + q/3.
    const double q_end = stage.eta ? *stage.eta * -lateral / (1 - *stage.eta / 3) : stage.q.value_or(q0);
    const double p_end = stage.eta ? -lateral + q_end / 3 : stage.p.value_or(p0);
    std::vector<double> input0;
    for (const ElementInput& in : stage.inputs) input0.push_back(sample.field(in.field));
    std::vector<std::size_t> limit_columns;
    for (const ElementLimit& l : stage.until)
      limit_columns.push_back(std::find(names.begin(), names.end(), l.field) - names.begin());
    for (int i = 0; i < stage.increments; ++i) {
      ++increment;
      auto where = [&] {
        return "path stage " + std::to_string(k) + " (" + element_path_names()[static_cast<std::size_t>(stage.path)] + "), increment " +
               std::to_string(i + 1) + " of " + std::to_string(stage.increments);
      };
      const double along = static_cast<double>(i + 1) / stage.increments;
      sample.clear_input_increments();
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
          const double p = p0 + along * (p_end - p0), q = q0 + along * (q_end - q0);
          control.stress = {-(p - q / 3), -(p + 2 * q / 3), -(p - q / 3)};
          break;
        }
      }
      bool carried = false;
      std::string why;
      try {
        carried = sample.apply(control);
      } catch (const Error& e) {  // the phase gave up (a return mapping, an inadmissible state)
        if (stage.until.empty()) throw Error(where() + ": failure: " + e.what());
        why = e.what();
      }
      if (!carried) {
        // A stage watching for a limit (a runaway) ends the case at a
        // collapse as well: the values of the last increment it carried.
        if (!stage.until.empty()) {
          ElementEvent event{k, increment, {"failure", 0.0}, {}, {}, false, {}};
          for (std::size_t n = 0; n < names.size(); ++n) event.at.emplace_back(names[n], previous[n]);
          for (const ElementInput& in : stage.inputs) event.inputs.push_back(in.field);
          event.failure = true;
          event.reason = why;
          result.events.push_back(std::move(event));
          return result;
        }
        if (stage.path == ElementPath::drained_triaxial)
          throw Error(where() + ": failure: the lateral stress " + detail::format(-lateral) +
                      " Pa cannot be held (the sample cannot carry the path)");
        throw Error(where() + ": failure: the stress p' = " +
                    detail::format(-(control.stress[0].value() * 2 + control.stress[1].value()) / 3) + " Pa, q = " +
                    detail::format(control.stress[0].value() - control.stress[1].value()) +
                    " Pa cannot be held (the sample cannot carry it)");
      }
      for (int c = 0; c < 6; ++c)
        if (!std::isfinite(sample.stress()[c])) throw Error(where() + ": failure: the stress is not finite");
      const std::vector<double> values = row_values(sample, fields);
      write_row(csv, increment, static_cast<int>(k), values);
      // A limit reached ends the stage: the values at the crossing, interpolated.
      bool reached = false;
      for (std::size_t l = 0; l < stage.until.size() && !reached; ++l) {
        const std::size_t c = limit_columns[l];
        const double limit = stage.until[l].value, before = previous[c], now = values[c];
        if ((before - limit) * (now - limit) > 0 || before == limit) continue;
        const double t = now == before ? 1.0 : (limit - before) / (now - before);
        ElementEvent event{k, increment, stage.until[l], {}, {}, false, {}};
        for (const ElementInput& in : stage.inputs) event.inputs.push_back(in.field);
        for (std::size_t n = 0; n < names.size(); ++n)
          event.at.emplace_back(names[n], previous[n] + t * (values[n] - previous[n]));
        result.events.push_back(std::move(event));
        reached = true;
      }
      previous = values;
      if (reached) break;
    }
  }
  return result;
}

}  // namespace suffuse
