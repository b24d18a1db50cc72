#pragma once
// A boundary condition as the run holds it: the plugin's condition, whose
// failures during a step name the condition ("boundary condition
// bc/traction (/boundary_conditions/2) failed: ..."); the step and the
// stage are added by the step (Simulation::timed). A condition acts on
// node sets it chose itself, so the node is named only if the plugin's own
// message names it. Set-up calls are not wrapped: their errors are the
// scene's, already named by the plugin's pointer.
#include <exception>
#include <memory>
#include <string>

#include "suffuse/boundary_condition.hpp"
#include "suffuse/error.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

class NamedCondition final : public BoundaryCondition {
 public:
  NamedCondition(std::unique_ptr<BoundaryCondition> condition, const PluginNode& node)
      : condition_(std::move(condition)), name_("boundary condition " + node.type + " (" + node.pointer + ")") {}

  void setup(const GridGeometry& grid) override { condition_->setup(grid); }
  void apply_forces(const GridGeometry& grid, NodeState& nodes, double time) const override {
    named([&] { condition_->apply_forces(grid, nodes, time); });
  }
  void constrain_velocity(const GridGeometry& grid, NodeState& nodes, double time) const override {
    named([&] { condition_->constrain_velocity(grid, nodes, time); });
  }
  std::optional<StandingWater> standing_water(double time) const override {
    std::optional<StandingWater> water;
    named([&] { water = condition_->standing_water(time); });
    return water;
  }
  std::vector<LiquidOpening> liquid_openings() const override { return condition_->liquid_openings(); }
  void setup_points(const GridGeometry& grid, const PointSet& points) override {
    condition_->setup_points(grid, points);
  }
  void apply_point_forces(const GridGeometry& grid, const PointSet& points, NodeState& nodes,
                          double time) const override {
    named([&] { condition_->apply_point_forces(grid, points, nodes, time); });
  }
  bool loads_points() const override { return condition_->loads_points(); }
  std::vector<std::size_t> loaded_points() const override { return condition_->loaded_points(); }
  bool follows_renumbering() const override { return condition_->follows_renumbering(); }
  void renumber_loaded_points(std::span<const std::size_t> new_numbers) override {
    named([&] { condition_->renumber_loaded_points(new_numbers); });
  }

 private:
  template <class Call>
  void named(Call&& call) const {
    try {
      call();
    } catch (const std::exception& e) {
      throw Error(name_ + " failed: " + e.what());
    }
  }

  std::unique_ptr<BoundaryCondition> condition_;
  std::string name_;
};

}  // namespace suffuse::detail
