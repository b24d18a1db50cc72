#pragma once
// The phase of one material, and the base phase it wraps if its plugin wraps
// one (phase/suffosion around phase/modified_cam_clay). The core owns both:
// it builds the base first and hands it to the wrapper (PluginArgs::base),
// and registers the base's fields before the wrapper's. Everything else
// (initialise, eigenstrain, update_stress) goes to the wrapper, which calls
// its base.
#include <memory>
#include <optional>

#include "suffuse/plugin.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

class MaterialPhase {
 public:
  MaterialPhase(const Registry& registry, const PluginNode& phase, const std::optional<PluginNode>& base, int dim) {
    if (base) base_ = registry.create<Phase>(base->type, {base->params, dim, base->pointer});
    phase_ = registry.create<Phase>(phase.type, {phase.params, dim, phase.pointer, base_.get()});
  }

  Phase& phase() { return *phase_; }
  const Phase& phase() const { return *phase_; }
  void add_fields(PointSet& points) {
    if (base_) base_->add_fields(points);
    phase_->add_fields(points);
  }

 private:
  std::unique_ptr<Phase> base_;  // declared first: destroyed after the wrapper that holds it
  std::unique_ptr<Phase> phase_;
};

}  // namespace suffuse::detail
