// bc/velocity: prescribed velocity components on a grid face or a box of
// nodes. A roller is a fixed normal component, a clamp fixes all components.
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/grid_face.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

class VelocityBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.choice("face", suffuse::grid_face_names()).may_be_absent().doc(
        "Grid face whose nodes are constrained: left/right x = min/max, bottom/top y, front/back z (3D)");
    s.vector("box_min").with_unit("m").may_be_absent().doc("Lower corner of a box of constrained nodes (instead of face)");
    s.vector("box_max").with_unit("m").may_be_absent().doc("Upper corner of a box of constrained nodes");
    s.time_series("vx").with_unit("m/s").may_be_absent().doc(
        "Prescribed x velocity (absent: free): a number, or in time a table [[t, v], ...] or a CSV file");
    s.time_series("vy").with_unit("m/s").may_be_absent().doc("Prescribed y velocity (absent: free), as vx");
    s.time_series("vz").with_unit("m/s").may_be_absent().doc("Prescribed z velocity, 3D only (absent: free), as vx");
    s.choice("phase", {"both", "solid", "liquid"}).fallback(std::string("both")).doc(
        "In saturated bodies, which phase is constrained: both (an impermeable wall), solid (a drained, "
        "permeable wall) or liquid");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int dim) {
    std::vector<suffuse::ParameterIssue> issues;
    const std::string components = dim == 3 ? "vx, vy, vz" : "vx, vy";
    if (dim < 3 && p.has("vz")) issues.push_back({"vz", "no z axis in a 2D scene", "one of " + components, "vz"});
    if (!p.has("vx") && !p.has("vy") && !p.has("vz"))
      issues.push_back({"", "no velocity component given", "at least one of " + components, "none"});
    const bool box = p.has("box_min") || p.has("box_max");
    if (p.has("face") == box)
      issues.push_back({"", "no unique node set", "either \"face\" or \"box_min\" and \"box_max\"",
                        box ? "both" : "neither"});
    else if (box && !(p.has("box_min") && p.has("box_max")))
      issues.push_back({p.has("box_min") ? "box_max" : "box_min", "missing box corner", "both box_min and box_max",
                        "only one"});
    if (p.has("face"))
      if (auto issue = suffuse::grid_face_issue("face", p.string("face"), dim)) issues.push_back(*issue);
    if (box && p.has("box_min") && p.has("box_max")) {
      const auto& lo = p.vector("box_min");
      const auto& hi = p.vector("box_max");
      for (int a = 0; a < dim; ++a)
        if (lo[a] > hi[a])
          issues.push_back({"box_max", "empty box", "box_max >= box_min in every component",
                            "box_max[" + std::to_string(a) + "] < box_min[" + std::to_string(a) + "]"});
    }
    return issues;
  }

  // The parameters have passed schema() and check().
  explicit VelocityBC(const suffuse::PluginArgs& args) : dim_(args.dim), where_(args.instance) {
    const auto& p = args.params;
    const char* names[3] = {"vx", "vy", "vz"};
    for (int c = 0; c < dim_; ++c)
      if (p.has(names[c])) components_.push_back({c, p.time_series(names[c])});
    const std::string& phase = p.string("phase");
    solid_ = phase != "liquid";
    liquid_ = phase != "solid";
    if (p.has("face")) {
      face_ = p.string("face");
    } else {
      box_min_ = p.vector("box_min");
      box_max_ = p.vector("box_max");
    }
  }

  void setup(const suffuse::GridGeometry& grid) override {
    if (!face_.empty()) {
      nodes_ = suffuse::face_nodes(grid, *suffuse::grid_face(face_));
      return;
    }
    nodes_.clear();
    const double tol = 1e-9 * grid.min_cell_size();
    for (std::size_t I = 0; I < grid.node_count(); ++I) {
      const auto x = grid.node_position(static_cast<std::int64_t>(I));
      bool in = true;
      for (int a = 0; a < dim_; ++a) in = in && x[a] >= box_min_[a] - tol && x[a] <= box_max_[a] + tol;
      if (in) nodes_.push_back(static_cast<std::int64_t>(I));
    }
    if (nodes_.empty()) throw suffuse::Error(where_ + ": the box from box_min to box_max contains no grid node (declared by bc/velocity)");
  }

  void constrain_velocity(const suffuse::GridGeometry&, suffuse::NodeState& state, double time) const override {
    for (const auto& [c, velocity] : components_) {
      const double value = velocity(time);
      if (solid_)
        for (std::int64_t I : nodes_) state.velocity[I * dim_ + c] = value;
      if (liquid_ && state.has_liquid())
        for (std::int64_t I : nodes_) state.liquid_velocity[I * dim_ + c] = value;
    }
  }

 private:
  struct Component {
    int axis;
    suffuse::TimeFunction value;
  };
  int dim_;
  std::string where_;
  std::vector<Component> components_;
  std::string face_;
  std::vector<double> box_min_, box_max_;
  std::vector<std::int64_t> nodes_;
  bool solid_ = true, liquid_ = true;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, VelocityBC>(
      "bc/velocity", "Prescribed nodal velocity components on a grid face or a box of nodes (rollers, clamps)");
}
