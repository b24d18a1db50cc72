#pragma once
// The momentum balance of a run without pore liquid: single-phase MUSL.
#include <array>
#include <vector>

#include "mpm/domain.hpp"
#include "mpm/momentum_balance.hpp"

namespace suffuse::detail {

class DryMomentum final : public MomentumBalance {
 public:
  DryMomentum(Domain& domain, const std::array<double, 3>& gravity, double mass_scaling)
      : d_(domain), gravity_(gravity), mass_scaling_(mass_scaling) {}

  void points_to_grid() override;
  void integrate_grid(double dt, double damping) override;
  void accelerations(double dt) override;
  void grid_to_points(double dt) override;
  void remap() override;

 private:
  Domain& d_;
  std::array<double, 3> gravity_;
  double mass_scaling_;
  std::vector<double> block_;  // the scatter's per-node sums (dry_block), unpacked into the node state
};

}  // namespace suffuse::detail
