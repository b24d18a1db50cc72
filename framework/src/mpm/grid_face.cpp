#include "suffuse/grid_face.hpp"

namespace suffuse {

std::vector<std::string> grid_face_names() { return {"left", "right", "bottom", "top", "front", "back"}; }

std::optional<GridFace> grid_face(const std::string& name) {
  const auto names = grid_face_names();
  for (int f = 0; f < 6; ++f)
    if (names[f] == name) return GridFace{f / 2, f % 2 == 1};
  return std::nullopt;
}

std::optional<ParameterIssue> grid_face_issue(const std::string& key, const std::string& name, int dim) {
  const auto face = grid_face(name);
  if (face && face->axis < dim) return std::nullopt;
  return ParameterIssue{key, dim == 2 ? "no such face in 2D" : "no such face",
                        dim == 2 ? "one of {left, right, bottom, top}" : "one of {left, right, bottom, top, front, back}",
                        "\"" + name + "\""};
}

std::vector<std::int64_t> face_nodes(const GridGeometry& grid, GridFace face) {
  const int index = face.upper ? grid.nodes_per_axis()[face.axis] - 1 : 0;
  std::vector<std::int64_t> nodes;
  for (std::size_t I = 0; I < grid.node_count(); ++I)
    if (grid.node_ijk(static_cast<std::int64_t>(I))[face.axis] == index) nodes.push_back(static_cast<std::int64_t>(I));
  return nodes;
}

double face_node_area(const GridGeometry& grid, GridFace face, std::int64_t node) {
  return dual_face_area(grid.nodes_per_axis(), grid.cell_size(), grid.node_ijk(node), face.axis, grid.dim());
}

}  // namespace suffuse
