#include "mpm/periodic_grid.hpp"

#include "suffuse/grid_face.hpp"

namespace suffuse::detail {

PeriodicGrid::PeriodicGrid(const GridGeometry& grid, const std::array<bool, 3>& axes)
    : axes_(axes), dim_(grid.dim()), nodes_(grid.nodes_per_axis()) {
  for (int a = 0; a < dim_; ++a) lower_[a] = grid.origin()[a], upper_[a] = grid.upper(a);
  if (!any()) return;
  const auto nn = static_cast<std::int64_t>(grid.node_count());
  for (std::int64_t I = 0; I < nn; ++I)
    if (const std::int64_t to = node(I); to != I) images_.emplace_back(I, to);
}

std::int64_t PeriodicGrid::node(std::int64_t node) const {
  std::int64_t stride = 1;
  for (int a = 0; a < dim_; ++a) {
    if (axes_[a] && (node / stride) % nodes_[a] == nodes_[a] - 1) node -= (nodes_[a] - 1) * stride;
    stride *= nodes_[a];
  }
  return node;
}

void PeriodicGrid::fold(std::vector<double>& nodal, int components) const {
  for (const auto& [image, to] : images_)
    for (int i = 0; i < components; ++i) {
      nodal[to * components + i] += nodal[image * components + i];
      nodal[image * components + i] = 0;
    }
}

void PeriodicGrid::copy_to_images(std::vector<double>& nodal, int components) const {
  for (const auto& [image, from] : images_)
    for (int i = 0; i < components; ++i) nodal[image * components + i] = nodal[from * components + i];
}

void PeriodicGrid::wrap(double* x, std::size_t points) const {
  if (!any()) return;
  for (std::size_t p = 0; p < points; ++p)
    for (int a = 0; a < dim_; ++a) {
      if (!axes_[a]) continue;
      double& xa = x[p * dim_ + a];
      if (xa < lower_[a])
        xa += upper_[a] - lower_[a];
      else if (xa >= upper_[a])
        xa -= upper_[a] - lower_[a];
    }
}

double PeriodicGrid::face_area(const GridGeometry& grid, GridFace face, std::int64_t node) const {
  double area = face_node_area(grid, face, node);
  if (!any()) return area;
  if (this->node(node) != node) return 0.0;  // an image: its node has the area
  const auto ijk = grid.node_ijk(node);
  for (int b = 0; b < dim_; ++b)
    if (b != face.axis && axes_[b] && ijk[b] == 0) area *= 2;
  return area;
}

int PeriodicGrid::cell(int axis, int index) const {
  const int cells = nodes_[axis] - 1;
  if (!axes_[axis]) return index;
  return ((index % cells) + cells) % cells;
}

}  // namespace suffuse::detail
