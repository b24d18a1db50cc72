// bc/pore_pressure: prescribed pore pressure (or hydraulic head) on a grid
// face of a saturated body: a drained boundary or a seepage inlet/outlet.
// The pressure enters the weak form as the boundary traction -p n on the
// liquid and on the mixture; the liquid is left free to cross the face.
#include <optional>
#include <string>
#include <suffuse/grid_face.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

class PorePressureBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.choice("face", suffuse::grid_face_names()).doc("Grid face where the pressure acts");
    suffuse::FacePart::declare(s, "the pressure acts");
    s.time_series("pressure").with_unit("Pa").may_be_absent().doc(
        "Prescribed pore pressure p, compression positive: a number, or in time a table [[t, p], ...] or a CSV file "
        "(docs/boundaries.md)");
    s.time_series("head").with_unit("m").may_be_absent().doc(
        "Prescribed hydraulic head h instead of pressure: p = gamma_w (h - elevation), elevation the vertical "
        "coordinate (y in 2D, z in 3D); a number, or in time a table [[t, h], ...] or a CSV file (a hydrograph: "
        "\"time [h], head [m]\")");
    s.number("unit_weight").with_unit("N/m^3").above(0).fallback(9810.0).doc(
        "Unit weight of the liquid gamma_w, to convert head to pressure");
    s.number("ramp_time").with_unit("s").at_least(0).fallback(0.0).doc(
        "Time over which a constant pressure grows linearly from its initial value on the face (0: at once); a "
        "shorthand of the table [[0, initial], [ramp_time, value]]");
    s.number("initial_head").with_unit("m").may_be_absent().doc(
        "Head at the start of the ramp (default: the prescribed head, i.e. no ramp of the head)");
    s.number("concentration").with_unit("-").at_least(0).at_most(1).fallback(0.0).doc(
        "Concentration of suspended fines (volume / liquid volume) in the liquid entering through the face; the "
        "face is open to the liquid and its fines either way");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int dim) {
    std::vector<suffuse::ParameterIssue> issues;
    if (p.has("pressure") == p.has("head"))
      issues.push_back({"", "no unique boundary value", "either \"pressure\" or \"head\"",
                        p.has("pressure") ? "both" : "neither"});
    if (auto issue = suffuse::grid_face_issue("face", p.string("face"), dim)) issues.push_back(*issue);
    for (auto& issue : suffuse::face_part_issues(p, dim)) issues.push_back(std::move(issue));
    if (p.has("initial_head") && !p.has("head"))
      issues.push_back({"initial_head", "initial head without head", "\"head\" as well", "only initial_head"});
    const char* given = p.has("head") ? "head" : "pressure";
    if (p.has(given) && !p.time_series(given).constant() && (p.number("ramp_time") > 0 || p.has("initial_head")))
      issues.push_back({p.has("initial_head") ? "initial_head" : "ramp_time", "a ramp of a table",
                        "the ramp as the table's first rows", "a ramp and a table"});
    return issues;
  }

  explicit PorePressureBC(const suffuse::PluginArgs& a)
      : dim_(a.dim),
        face_(*suffuse::grid_face(a.params.string("face"))),
        part_(a.params, face_, a.instance, "bc/pore_pressure"),
        gamma_(a.params.number("unit_weight")),
        ramp_(a.params.number("ramp_time")),
        concentration_(a.params.number("concentration")) {
    if (a.params.has("pressure")) {
      pressure_ = a.params.time_series("pressure");
    } else {
      head_ = a.params.time_series("head");
      initial_head_ = a.params.has("initial_head") ? a.params.number("initial_head") : head_->initial();
    }
  }

  std::vector<suffuse::LiquidOpening> liquid_openings() const override { return {part_.opening(concentration_)}; }

  void setup(const suffuse::GridGeometry& grid) override {
    part_.setup(grid);
    areas_.clear();
    elevations_.clear();
    for (const std::int64_t I : part_.nodes()) {
      areas_.push_back(suffuse::face_node_area(grid, face_, I));
      elevations_.push_back(grid.node_position(I)[dim_ - 1]);
    }
  }

  void apply_forces(const suffuse::GridGeometry&, suffuse::NodeState& state, double time) const override {
    if (!state.has_liquid()) return;
    // A constant value ramps from its initial one; a table gives its own ramp.
    const double r = suffuse::ramp_factor(time, ramp_);
    double h = 0, p_face = 0;
    if (head_) {
      const double target = (*head_)(time);
      h = head_->constant() ? *initial_head_ + r * (target - *initial_head_) : target;
    } else {
      p_face = pressure_->constant() ? r * (*pressure_)(time) : (*pressure_)(time);
    }
    for (std::size_t k = 0; k < part_.nodes().size(); ++k) {
      const double p = head_ ? gamma_ * (h - elevations_[k]) : p_face;
      const double f = -p * face_.outward() * areas_[k];  // traction -p n
      state.force[part_.nodes()[k] * dim_ + face_.axis] += f;
      state.liquid_force[part_.nodes()[k] * dim_ + face_.axis] += f;
    }
  }

 private:
  int dim_;
  suffuse::GridFace face_;
  suffuse::FacePart part_;
  double gamma_, ramp_;
  std::optional<suffuse::TimeFunction> pressure_, head_;
  std::optional<double> initial_head_;
  double concentration_;
  std::vector<double> areas_, elevations_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, PorePressureBC>(
      "bc/pore_pressure", "Prescribed pore pressure or hydraulic head on a grid face (drained boundary, seepage inlet)");
}
