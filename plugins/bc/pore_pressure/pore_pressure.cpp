// bc/pore_pressure: prescribed pore pressure (or hydraulic head) on a grid
// face of a saturated body: a drained boundary or a seepage inlet/outlet.
// The pressure enters the weak form as the boundary traction -p n on the
// liquid and on the mixture; the liquid is left free to cross the face.
#include <optional>
#include <suffuse/error.hpp>
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
    s.vector("box_min").with_unit("m").may_be_absent().doc(
        "Lower corner of the part of the face where the pressure acts (a toe drain, a river bed beside a "
        "structure): the face's nodes within the box, each with its whole tributary length or area (default: the "
        "whole face)");
    s.vector("box_max").with_unit("m").may_be_absent().doc("Upper corner of that part of the face");
    s.string("name").may_be_absent().doc(
        "Name of this opening's account in the mass ledger (default: the face's name); needed where two "
        "conditions open parts of one face");
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
        where_(a.instance),
        face_(*suffuse::grid_face(a.params.string("face"))),
        gamma_(a.params.number("unit_weight")),
        ramp_(a.params.number("ramp_time")),
        concentration_(a.params.number("concentration")) {
    if (a.params.has("box_min")) box_min_ = a.params.vector("box_min"), box_max_ = a.params.vector("box_max");
    if (a.params.has("name")) name_ = a.params.string("name");
    if (a.params.has("pressure")) {
      pressure_ = a.params.time_series("pressure");
    } else {
      head_ = a.params.time_series("head");
      initial_head_ = a.params.has("initial_head") ? a.params.number("initial_head") : head_->initial();
    }
  }

  std::vector<suffuse::LiquidOpening> liquid_openings() const override {
    return {{face_, concentration_, box_min_.empty() ? std::vector<std::int64_t>{} : nodes_, name_}};
  }

  void setup(const suffuse::GridGeometry& grid) override {
    nodes_ = box_min_.empty() ? suffuse::face_nodes(grid, face_) : suffuse::face_nodes(grid, face_, box_min_, box_max_);
    if (nodes_.empty())
      throw suffuse::Error(where_ + ": the part of the " + suffuse::grid_face_names()[face_.axis * 2 + face_.upper] +
                           " face from box_min to box_max holds no grid node; expected a box that reaches a node of "
                           "the face (declared by bc/pore_pressure)");
    areas_.clear();
    elevations_.clear();
    for (const std::int64_t I : nodes_) {
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
    for (std::size_t k = 0; k < nodes_.size(); ++k) {
      const double p = head_ ? gamma_ * (h - elevations_[k]) : p_face;
      const double f = -p * face_.outward() * areas_[k];  // traction -p n
      state.force[nodes_[k] * dim_ + face_.axis] += f;
      state.liquid_force[nodes_[k] * dim_ + face_.axis] += f;
    }
  }

 private:
  int dim_;
  std::string where_;
  suffuse::GridFace face_;
  std::vector<double> box_min_, box_max_;  // a part of the face, or empty
  std::string name_;
  double gamma_, ramp_;
  std::optional<suffuse::TimeFunction> pressure_, head_;
  std::optional<double> initial_head_;
  double concentration_;
  std::vector<std::int64_t> nodes_;
  std::vector<double> areas_, elevations_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, PorePressureBC>(
      "bc/pore_pressure", "Prescribed pore pressure or hydraulic head on a grid face (drained boundary, seepage inlet)");
}
