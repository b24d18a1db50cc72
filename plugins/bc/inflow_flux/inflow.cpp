// bc/inflow_flux: a prescribed Darcy flux q entering a saturated body through
// a grid face (seepage inlet). At each face node the liquid's normal velocity
// is set to v_s + q / n, n the nodal porosity (sum N n rho_L V / sum N rho_L V),
// so list it after the constraints of the skeleton on the same face.
#include <string>
#include <suffuse/grid_face.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

class InflowFluxBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.choice("face", suffuse::grid_face_names()).doc("Grid face the liquid enters through");
    suffuse::FacePart::declare(s, "the liquid enters");
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
        concentration_(a.params.number("concentration")), part_(a.params, face_, a.instance, "bc/inflow_flux") {}

  std::vector<suffuse::LiquidOpening> liquid_openings() const override { return {part_.opening(concentration_)}; }

  void setup(const suffuse::GridGeometry& grid) override { part_.setup(grid); }

  void constrain_velocity(const suffuse::GridGeometry&, suffuse::NodeState& state, double time) const override {
    if (!state.has_liquid()) return;
    const double q = flux_.constant() ? flux_(time) * suffuse::ramp_factor(time, ramp_) : flux_(time);
    for (std::int64_t I : part_.nodes()) {
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
  suffuse::FacePart part_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, InflowFluxBC>(
      "bc/inflow_flux", "Prescribed Darcy flux of the liquid through a grid face (seepage inlet)");
}
