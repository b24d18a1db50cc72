#include "suffuse/grid.hpp"

#include <algorithm>

#include "suffuse/error.hpp"

namespace suffuse {

GridGeometry::GridGeometry(int dim, std::array<double, 3> origin, std::array<double, 3> cell_size,
                           std::array<int, 3> cells)
    : dim_(dim), origin_(origin), h_(cell_size), cells_(cells), nodes_{1, 1, 1} {
  if (dim != 2 && dim != 3) throw Error("grid dimension must be 2 or 3");
  node_count_ = 1;
  for (int a = 0; a < dim; ++a) {
    if (cells_[a] < 1 || !(h_[a] > 0)) throw Error("grid needs at least one cell of positive size per axis");
    nodes_[a] = cells_[a] + 1;
    node_count_ *= static_cast<std::size_t>(nodes_[a]);
  }
  for (int a = dim; a < 3; ++a) {
    origin_[a] = 0;
    h_[a] = 1;
    cells_[a] = 0;
  }
}

double GridGeometry::min_cell_size() const {
  double h = h_[0];
  for (int a = 1; a < dim_; ++a) h = std::min(h, h_[a]);
  return h;
}

std::array<int, 3> GridGeometry::node_ijk(std::int64_t index) const {
  std::array<int, 3> ijk{0, 0, 0};
  ijk[0] = static_cast<int>(index % nodes_[0]);
  index /= nodes_[0];
  ijk[1] = static_cast<int>(index % nodes_[1]);
  ijk[2] = static_cast<int>(index / nodes_[1]);
  return ijk;
}

std::array<double, 3> GridGeometry::node_position(std::int64_t index) const {
  const auto ijk = node_ijk(index);
  std::array<double, 3> x{0, 0, 0};
  for (int a = 0; a < dim_; ++a) x[a] = origin_[a] + h_[a] * ijk[a];
  return x;
}

bool GridGeometry::contains(const double* x) const {
  for (int a = 0; a < dim_; ++a)
    if (!(x[a] >= origin_[a] && x[a] <= upper(a))) return false;  // also false for NaN
  return true;
}

void NodeState::resize(std::size_t nodes, int dim, bool with_liquid) {
  const std::size_t nl = with_liquid ? nodes : 0;
  liquid_mass.assign(nl, 0.0);
  liquid_inertia.assign(nl, 0.0);
  liquid_momentum.assign(nl * dim, 0.0);
  liquid_force.assign(nl * dim, 0.0);
  liquid_velocity.assign(nl * dim, 0.0);
  liquid_acceleration.assign(nl * dim, 0.0);
  mass.assign(nodes, 0.0);
  momentum.assign(nodes * dim, 0.0);
  force.assign(nodes * dim, 0.0);
  velocity.assign(nodes * dim, 0.0);
  acceleration.assign(nodes * dim, 0.0);
}

}  // namespace suffuse
