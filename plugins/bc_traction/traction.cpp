// bc/traction: a distributed load (surcharge) on a line (2D) or plane (3D) of
// grid nodes, optionally ramped linearly in time. Each node receives the
// traction times its tributary length/area; the load acts on the soil
// skeleton (the mixture in saturated bodies).
#include <algorithm>
#include <cmath>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

class TractionBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.vector("box_min").with_unit("m").doc("Lower corner of the loaded nodes; one component equals box_max's");
    s.vector("box_max").with_unit("m").doc("Upper corner of the loaded nodes");
    s.vector("traction").with_unit("Pa").doc("Traction vector, e.g. [0, -10e3] for a 10 kPa surcharge on a top surface");
    s.number("ramp_time").with_unit("s").at_least(0).fallback(0.0).doc(
        "Time over which the load grows linearly from zero (0: applied at once)");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int dim) {
    const auto& lo = p.vector("box_min");
    const auto& hi = p.vector("box_max");
    int flat = 0;
    for (int a = 0; a < dim; ++a) {
      if (lo[a] > hi[a]) return {{"box_max", "empty box", "box_max >= box_min in every component", "box_max < box_min"}};
      flat += lo[a] == hi[a];
    }
    if (flat != 1)
      return {{"box_max", "not a surface", "box_min and box_max equal in exactly one component (the normal)",
               std::to_string(flat) + " equal components"}};
    return {};
  }

  explicit TractionBC(const suffuse::PluginArgs& args)
      : dim_(args.dim),
        where_(args.instance),
        lo_(args.params.vector("box_min")),
        hi_(args.params.vector("box_max")),
        traction_(args.params.vector("traction")),
        ramp_(args.params.number("ramp_time")) {}

  void setup(const suffuse::GridGeometry& grid) override {
    const double tol = 1e-9 * grid.min_cell_size();
    nodes_.clear();
    areas_.clear();
    for (std::size_t I = 0; I < grid.node_count(); ++I) {
      const auto x = grid.node_position(static_cast<std::int64_t>(I));
      bool in = true;
      for (int a = 0; a < dim_; ++a) in = in && x[a] >= lo_[a] - tol && x[a] <= hi_[a] + tol;
      if (!in) continue;
      double area = 1;
      for (int a = 0; a < dim_; ++a) {
        if (lo_[a] == hi_[a]) continue;  // the normal axis
        const double h = grid.cell_size()[a];
        const double left = std::max(0.0, std::min(h / 2, x[a] - lo_[a]));
        const double right = std::max(0.0, std::min(h / 2, hi_[a] - x[a]));
        area *= left + right;
      }
      nodes_.push_back(static_cast<std::int64_t>(I));
      areas_.push_back(area);
    }
    if (nodes_.empty())
      throw suffuse::Error(where_ + ": no grid node lies between box_min and box_max (declared by bc/traction)");
  }

  void apply_forces(const suffuse::GridGeometry&, suffuse::NodeState& state, double time) const override {
    const double factor = suffuse::ramp_factor(time, ramp_);
    for (std::size_t k = 0; k < nodes_.size(); ++k)
      for (int a = 0; a < dim_; ++a) state.force[nodes_[k] * dim_ + a] += factor * traction_[a] * areas_[k];
  }

 private:
  int dim_;
  std::string where_;
  std::vector<double> lo_, hi_, traction_;
  double ramp_;
  std::vector<std::int64_t> nodes_;
  std::vector<double> areas_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, TractionBC>(
      "bc/traction", "Distributed load on a line or plane of nodes (surcharge), optionally ramped in time");
}
