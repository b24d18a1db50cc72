// bc/velocity: prescribed velocity components on a grid face or a box of
// nodes. A roller is a fixed normal component, a clamp fixes all components.
#include <cmath>
#include <optional>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

class VelocityBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.choice("face", {"left", "right", "bottom", "top", "front", "back"}).may_be_absent().doc(
        "Grid face whose nodes are constrained: left/right x = min/max, bottom/top y, front/back z (3D)");
    s.vector("box_min").with_unit("m").may_be_absent().doc("Lower corner of a box of constrained nodes (instead of face)");
    s.vector("box_max").with_unit("m").may_be_absent().doc("Upper corner of a box of constrained nodes");
    s.number("vx").with_unit("m/s").may_be_absent().doc("Prescribed x velocity (absent: free)");
    s.number("vy").with_unit("m/s").may_be_absent().doc("Prescribed y velocity (absent: free)");
    s.number("vz").with_unit("m/s").may_be_absent().doc("Prescribed z velocity, 3D only (absent: free)");
    return s;
  }

  explicit VelocityBC(const suffuse::PluginArgs& args) : dim_(args.dim), where_(args.instance) {
    const auto& p = args.params;
    const char* names[3] = {"vx", "vy", "vz"};
    for (int c = 0; c < 3; ++c) {
      if (!p.has(names[c])) continue;
      if (c >= dim_) throw suffuse::Error(where_ + "/vz: a z velocity needs a 3D scene (declared by bc/velocity)");
      components_.push_back({c, p.number(names[c])});
    }
    if (components_.empty())
      throw suffuse::Error(where_ + ": no velocity component given; expected at least one of vx, vy" +
                           std::string(dim_ == 3 ? ", vz" : "") + " (declared by bc/velocity)");
    const bool has_box = p.has("box_min") || p.has("box_max");
    if (p.has("face") == has_box)
      throw suffuse::Error(where_ + ": expected either \"face\" or \"box_min\" and \"box_max\", found " +
                           (has_box ? "both" : "neither") + " (declared by bc/velocity)");
    if (p.has("face")) {
      face_ = p.string("face");
      if (dim_ == 2 && (face_ == "front" || face_ == "back"))
        throw suffuse::Error(where_ + "/face: expected left, right, bottom or top in 2D, found \"" + face_ +
                             "\" (declared by bc/velocity)");
    } else {
      if (!p.has("box_min") || !p.has("box_max"))
        throw suffuse::Error(where_ + ": a box needs both box_min and box_max (declared by bc/velocity)");
      box_min_ = p.vector("box_min");
      box_max_ = p.vector("box_max");
    }
  }

  void setup(const suffuse::GridGeometry& grid) override {
    nodes_.clear();
    const auto& n = grid.nodes_per_axis();
    int axis = -1, index = 0;
    if (!face_.empty()) {
      const std::string faces[6] = {"left", "right", "bottom", "top", "front", "back"};
      for (int f = 0; f < 6; ++f)
        if (faces[f] == face_) axis = f / 2, index = (f % 2) ? n[f / 2] - 1 : 0;
    }
    const double tol = 1e-9 * grid.min_cell_size();
    for (std::size_t I = 0; I < grid.node_count(); ++I) {
      bool in = true;
      if (axis >= 0) {
        in = grid.node_ijk(static_cast<std::int64_t>(I))[axis] == index;
      } else {
        const auto x = grid.node_position(static_cast<std::int64_t>(I));
        for (int a = 0; a < dim_; ++a) in = in && x[a] >= box_min_[a] - tol && x[a] <= box_max_[a] + tol;
      }
      if (in) nodes_.push_back(static_cast<std::int64_t>(I));
    }
    if (nodes_.empty()) throw suffuse::Error(where_ + ": the box contains no grid node (declared by bc/velocity)");
  }

  void constrain_velocity(const suffuse::GridGeometry&, suffuse::NodeState& state, double) const override {
    double* v = state.velocity.data();
    for (const auto& [c, value] : components_)
      for (std::int64_t I : nodes_) v[I * dim_ + c] = value;
  }

 private:
  struct Component {
    int axis;
    double value;
  };
  int dim_;
  std::string where_;
  std::vector<Component> components_;
  std::string face_;
  std::vector<double> box_min_, box_max_;
  std::vector<std::int64_t> nodes_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, VelocityBC>(
      "bc/velocity", "Prescribed nodal velocity components on a grid face or a box of nodes (rollers, clamps)");
}
