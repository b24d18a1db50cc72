#include "mpm/dry_momentum.hpp"

#include "mpm/solid_kernels.hpp"

namespace suffuse::detail {

void DryMomentum::points_to_grid() {
  NodeState& n = d_.nodes;
  d_.clear_nodal(block_, static_cast<std::size_t>(dry_block));
  const auto& f = d_.points.core();
  const Interpolation& s = d_.shape;
  ScatterTargets targets = s.targets(d_.grid.node_count());
  targets.add(block_);
  d_.exec.scatter(d_.points.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      p2g_kernel<D, L>(b, e, s.view(), d_.points.data(f.mass),
                       d_.points.data(f.volume), d_.points.data(f.velocity), d_.points.data(f.stress),
                       gravity_.data(), mass_scaling_, out[0]);
    });
  });
  auto unpack = d_.dim() == 2 ? &unpack_dry_block<2> : &unpack_dry_block<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    unpack(b, e, block_.data(), n.mass.data(), n.momentum.data(), n.force.data());
  });
  d_.periodic.fold(n.mass, 1);  // (a periodic grid's images: mpm/periodic_grid.hpp)
  d_.periodic.fold(n.momentum, d_.dim());
  d_.periodic.fold(n.force, d_.dim());
}

void DryMomentum::integrate_grid(double dt, double damping) {
  NodeState& n = d_.nodes;
  auto update = d_.dim() == 2 ? &grid_update_kernel<2> : &grid_update_kernel<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    update(b, e, dt, damping, n.mass.data(), n.momentum.data(), n.force.data(), n.velocity.data());
  });
}

void DryMomentum::accelerations(double dt) {
  NodeState& n = d_.nodes;
  auto acc = d_.dim() == 2 ? &acceleration_kernel<2> : &acceleration_kernel<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    acc(b, e, dt, n.mass.data(), n.momentum.data(), n.velocity.data(), n.acceleration.data());
  });
  d_.periodic.copy_to_images(n.velocity, d_.dim());
  d_.periodic.copy_to_images(n.acceleration, d_.dim());
}

void DryMomentum::grid_to_points(double dt) {
  const auto& f = d_.points.core();
  const Interpolation& s = d_.shape;
  d_.exec.for_chunks(d_.points.size(), [&](int, std::size_t b, std::size_t e) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      g2p_kernel<D, false, L>(b, e, dt, s.view(), d_.nodes.velocity.data(),
                              d_.nodes.acceleration.data(), d_.points.data(f.position),
                              d_.points.data(f.displacement), d_.points.data(f.velocity), nullptr, nullptr);
    });
  });
  d_.periodic.wrap(d_.points.data(f.position), d_.points.size());
}

void DryMomentum::remap() {
  NodeState& n = d_.nodes;
  d_.clear_nodal(n.momentum, static_cast<std::size_t>(d_.dim()));
  const auto& f = d_.points.core();
  const Interpolation& s = d_.shape;
  ScatterTargets targets = s.targets(d_.grid.node_count());
  targets.add(n.momentum);
  d_.exec.scatter(d_.points.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      remap_kernel<D, L>(b, e, s.view(), d_.points.data(f.mass), mass_scaling_,
                         d_.points.data(f.velocity), out[0]);
    });
  });
  d_.periodic.fold(n.momentum, d_.dim());
  auto velocity = d_.dim() == 2 ? &velocity_from_momentum<2> : &velocity_from_momentum<3>;
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    velocity(b, e, n.mass.data(), n.momentum.data(), n.velocity.data());
  });
}

}  // namespace suffuse::detail
