// bc/inflow_flux: a prescribed Darcy flux q entering a saturated body through
// a grid face (seepage inlet). At each face node the liquid's normal velocity
// is set to v_s + q / n, n the nodal porosity (sum N n rho_L V / sum N rho_L V),
// so list it after the constraints of the skeleton on the same face.
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/grid_face.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

class InflowFluxBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.choice("face", suffuse::grid_face_names()).doc("Grid face the liquid enters through");
    s.vector("box_min").with_unit("m").may_be_absent().doc(
        "Lower corner of the part of the face the liquid enters through: the face's nodes within the box "
        "(default: the whole face)");
    s.vector("box_max").with_unit("m").may_be_absent().doc("Upper corner of that part of the face");
    s.string("name").may_be_absent().doc(
        "Name of this opening's account in the mass ledger (default: the face's name); needed where two "
        "conditions open parts of one face");
    s.time_series("flux").with_unit("m/s").doc(
        "Darcy flux q entering the body (negative: leaving): a number, or in time a table [[t, q], ...] or a CSV "
        "file (docs/boundaries.md)");
    s.number("ramp_time").with_unit("s").at_least(0).fallback(0.0).doc(
        "Time over which a constant flux grows linearly from zero (0: at once); a table gives its own ramp");
    s.number("concentration").with_unit("-").at_least(0).at_most(1).fallback(0.0).doc(
        "Concentration of suspended fines (volume / liquid volume) in the liquid entering through the face; the "
        "face is open to the liquid and its fines either way");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int dim) {
    if (auto issue = suffuse::grid_face_issue("face", p.string("face"), dim)) return {*issue};
    if (auto issues = suffuse::face_part_issues(p, dim); !issues.empty()) return issues;
    if (!p.time_series("flux").constant() && p.number("ramp_time") > 0)
      return {{"ramp_time", "a ramp of a table", "the ramp as the table's first rows", "a ramp and a table"}};
    return {};
  }

  explicit InflowFluxBC(const suffuse::PluginArgs& a)
      : dim_(a.dim), face_(*suffuse::grid_face(a.params.string("face"))), flux_(a.params.time_series("flux")),
        ramp_(a.params.number("ramp_time")),
        concentration_(a.params.number("concentration")), where_(a.instance) {
    if (a.params.has("box_min")) box_min_ = a.params.vector("box_min"), box_max_ = a.params.vector("box_max");
    if (a.params.has("name")) name_ = a.params.string("name");
  }

  std::vector<suffuse::LiquidOpening> liquid_openings() const override {
    return {{face_, concentration_, box_min_.empty() ? std::vector<std::int64_t>{} : nodes_, name_}};
  }

  void setup(const suffuse::GridGeometry& grid) override {
    nodes_ = box_min_.empty() ? suffuse::face_nodes(grid, face_) : suffuse::face_nodes(grid, face_, box_min_, box_max_);
    if (nodes_.empty())
      throw suffuse::Error(where_ + ": the part of the " + suffuse::grid_face_names()[face_.axis * 2 + face_.upper] +
                           " face from box_min to box_max holds no grid node; expected a box that reaches a node of "
                           "the face (declared by bc/inflow_flux)");
  }

  void constrain_velocity(const suffuse::GridGeometry&, suffuse::NodeState& state, double time) const override {
    if (!state.has_liquid()) return;
    const double q = flux_.constant() ? flux_(time) * suffuse::ramp_factor(time, ramp_) : flux_(time);
    for (std::int64_t I : nodes_) {
      if (state.liquid_inertia[I] <= 0) continue;
      const double n = state.liquid_mass[I] / state.liquid_inertia[I];
      const std::size_t k = static_cast<std::size_t>(I) * dim_ + face_.axis;
      state.liquid_velocity[k] = state.velocity[k] - face_.outward() * q / n;  // q enters: against the outward normal
    }
  }

 private:
  int dim_;
  suffuse::GridFace face_;
  suffuse::TimeFunction flux_;
  double ramp_;
  double concentration_;
  std::string where_;
  std::vector<double> box_min_, box_max_;  // a part of the face, or empty
  std::string name_;
  std::vector<std::int64_t> nodes_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, InflowFluxBC>(
      "bc/inflow_flux", "Prescribed Darcy flux of the liquid through a grid face (seepage inlet)");
}
