#include "suffuse/grid_face.hpp"

#include <utility>

#include "suffuse/error.hpp"

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

std::vector<std::int64_t> face_nodes(const GridGeometry& grid, GridFace face, std::span<const double> box_min,
                                     std::span<const double> box_max) {
  const double tol = 1e-9 * grid.min_cell_size();
  std::vector<std::int64_t> part;
  for (const std::int64_t I : face_nodes(grid, face)) {
    const auto x = grid.node_position(I);
    bool in = true;
    for (int a = 0; a < grid.dim(); ++a)
      if (a != face.axis) in = in && x[a] >= box_min[a] - tol && x[a] <= box_max[a] + tol;
    if (in) part.push_back(I);
  }
  return part;
}

std::vector<ParameterIssue> face_part_issues(const Parameters& p, int dim) {
  if (p.has("box_min") != p.has("box_max"))
    return {{p.has("box_min") ? "box_max" : "box_min", "missing box corner", "both box_min and box_max", "only one"}};
  if (!p.has("box_min")) return {};
  const auto& lo = p.vector("box_min");
  const auto& hi = p.vector("box_max");
  const auto face = p.has("face") ? grid_face(p.string("face")) : std::nullopt;
  for (int a = 0; a < dim; ++a)
    if (lo[a] > hi[a] && !(face && face->axis == a))  // the normal's component is not read
      return {{"box_max", "empty box", "box_max >= box_min in every component",
               "box_max[" + std::to_string(a) + "] < box_min[" + std::to_string(a) + "]"}};
  return {};
}

void FacePart::declare(ParameterSchema& s, const std::string& acts) {
  s.vector("box_min").with_unit("m").may_be_absent().doc(
      "Lower corner of the part of the face where " + acts + " (a toe drain, a river bed beside a structure): the "
      "face's nodes within the box, each with its whole tributary length or area (default: the whole face)");
  s.vector("box_max").with_unit("m").may_be_absent().doc("Upper corner of that part of the face");
  s.string("name").may_be_absent().doc(
      "Name of this opening's account in the mass ledger (default: the face's name); needed where two conditions "
      "open parts of one face");
}

FacePart::FacePart(const Parameters& p, GridFace face, std::string where, std::string plugin)
    : face_(face), where_(std::move(where)), plugin_(std::move(plugin)) {
  if (p.has("box_min")) box_min_ = p.vector("box_min"), box_max_ = p.vector("box_max");
  if (p.has("name")) name_ = p.string("name");
}

const std::vector<std::int64_t>& FacePart::setup(const GridGeometry& grid) {
  nodes_ = box_min_.empty() ? face_nodes(grid, face_) : face_nodes(grid, face_, box_min_, box_max_);
  if (nodes_.empty())
    throw Error(where_ + ": the part of the " + grid_face_names()[face_.axis * 2 + face_.upper] +
                " face from box_min to box_max holds no grid node; expected a box that reaches a node of the face "
                "(declared by " + plugin_ + ")");
  return nodes_;
}

LiquidOpening FacePart::opening(double concentration) const {
  return {face_, concentration, box_min_.empty() ? std::vector<std::int64_t>{} : nodes_, name_};
}

double face_node_area(const GridGeometry& grid, GridFace face, std::int64_t node) {
  return dual_face_area(grid.nodes_per_axis(), grid.cell_size(), grid.node_ijk(node), face.axis, grid.dim());
}

}  // namespace suffuse
