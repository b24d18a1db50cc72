// The grid-face helpers of the SDK that boundary-condition plugins build on,
// and the load ramp they share.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <suffuse/boundary_condition.hpp>
#include <suffuse/grid_face.hpp>
#include <vector>

namespace {

using suffuse::GridFace;
using suffuse::GridGeometry;

// 3 x 2 cells of 0.5 x 0.25 m.
GridGeometry grid_2d() { return GridGeometry(2, {0, 0, 0}, {0.5, 0.25, 1}, {3, 2, 1}); }
// 2 x 3 x 4 cells of 1 x 2 x 3 m.
GridGeometry grid_3d() { return GridGeometry(3, {0, 0, 0}, {1, 2, 3}, {2, 3, 4}); }

double face_total(const GridGeometry& grid, GridFace face) {
  double total = 0;
  for (std::int64_t I : suffuse::face_nodes(grid, face)) total += suffuse::face_node_area(grid, face, I);
  return total;
}

// Names map to (axis, side) in schema order; another name is no face.
TEST(GridFace, NamesAndFaces) {
  const std::vector<std::string> names = suffuse::grid_face_names();
  ASSERT_EQ(names, (std::vector<std::string>{"left", "right", "bottom", "top", "front", "back"}));
  for (int f = 0; f < 6; ++f) {
    const auto face = suffuse::grid_face(names[f]);
    ASSERT_TRUE(face) << names[f];
    EXPECT_EQ(face->axis, f / 2) << names[f];
    EXPECT_EQ(face->upper, f % 2 == 1) << names[f];
    EXPECT_EQ(face->outward(), f % 2 == 1 ? 1.0 : -1.0) << names[f];
  }
  EXPECT_FALSE(suffuse::grid_face("middle"));
  EXPECT_FALSE(suffuse::grid_face("Left")) << "names are case sensitive";
}

// front and back exist in 3D only; the issue names the key and lists the faces.
TEST(GridFace, IssueForAFaceTheDimensionLacks) {
  EXPECT_FALSE(suffuse::grid_face_issue("face", "top", 2));
  EXPECT_FALSE(suffuse::grid_face_issue("face", "back", 3));
  const auto in_2d = suffuse::grid_face_issue("face", "front", 2);
  ASSERT_TRUE(in_2d);
  EXPECT_EQ(in_2d->key, "face");
  EXPECT_EQ(in_2d->problem, "no such face in 2D");
  EXPECT_EQ(in_2d->expected, "one of {left, right, bottom, top}");
  EXPECT_EQ(in_2d->found, "\"front\"");
  const auto in_3d = suffuse::grid_face_issue("inlet", "middle", 3);
  ASSERT_TRUE(in_3d);
  EXPECT_EQ(in_3d->key, "inlet");
  EXPECT_EQ(in_3d->problem, "no such face");
  EXPECT_EQ(in_3d->expected, "one of {left, right, bottom, top, front, back}");
}

// The nodes of a face, in increasing order: every node whose index along the
// face's axis is 0 (lower face) or the last (upper face).
TEST(GridFace, NodesOfEachFace) {
  const GridGeometry g2 = grid_2d();  // 4 x 3 nodes
  EXPECT_EQ(suffuse::face_nodes(g2, GridFace{0, false}), (std::vector<std::int64_t>{0, 4, 8}));
  EXPECT_EQ(suffuse::face_nodes(g2, GridFace{0, true}), (std::vector<std::int64_t>{3, 7, 11}));
  EXPECT_EQ(suffuse::face_nodes(g2, GridFace{1, false}), (std::vector<std::int64_t>{0, 1, 2, 3}));
  EXPECT_EQ(suffuse::face_nodes(g2, GridFace{1, true}), (std::vector<std::int64_t>{8, 9, 10, 11}));

  const GridGeometry g3 = grid_3d();  // 3 x 4 x 5 nodes
  const std::size_t expected_count[3] = {4 * 5, 3 * 5, 3 * 4};
  for (int axis = 0; axis < 3; ++axis) {
    for (bool upper : {false, true}) {
      const auto nodes = suffuse::face_nodes(g3, GridFace{axis, upper});
      EXPECT_EQ(nodes.size(), expected_count[axis]) << axis << upper;
      EXPECT_TRUE(std::is_sorted(nodes.begin(), nodes.end()));
      const int index = upper ? g3.nodes_per_axis()[axis] - 1 : 0;
      for (std::int64_t I : nodes) EXPECT_EQ(g3.node_ijk(I)[axis], index) << axis << upper << " node " << I;
    }
  }
  EXPECT_EQ(suffuse::face_nodes(g3, GridFace{2, true}).front(), g3.node_index(0, 0, 4));
}

// A node's tributary length in 2D: half a cell at the ends of the face, a
// whole cell between; together the length of the face.
TEST(GridFace, NodeAreaIn2D) {
  const GridGeometry g = grid_2d();
  const GridFace bottom{1, false}, left{0, false};
  const double along_bottom[4] = {0.25, 0.5, 0.5, 0.25};
  for (int i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(suffuse::face_node_area(g, bottom, g.node_index(i, 0, 0)), along_bottom[i]) << i;
  const double along_left[3] = {0.125, 0.25, 0.125};
  for (int j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(suffuse::face_node_area(g, left, g.node_index(0, j, 0)), along_left[j]) << j;
  EXPECT_DOUBLE_EQ(face_total(g, bottom), 1.5);
  EXPECT_DOUBLE_EQ(face_total(g, GridFace{1, true}), 1.5);
  EXPECT_DOUBLE_EQ(face_total(g, GridFace{0, true}), 0.5);
}

// In 3D: a quarter cell face at a corner, half at an edge, whole inside.
TEST(GridFace, NodeAreaIn3D) {
  const GridGeometry g = grid_3d();
  const GridFace front{2, false};
  EXPECT_DOUBLE_EQ(suffuse::face_node_area(g, front, g.node_index(0, 0, 0)), 0.5);  // corner: 0.5 x 1
  EXPECT_DOUBLE_EQ(suffuse::face_node_area(g, front, g.node_index(1, 0, 0)), 1.0);  // edge: 1 x 1
  EXPECT_DOUBLE_EQ(suffuse::face_node_area(g, front, g.node_index(1, 1, 0)), 2.0);  // inside: 1 x 2
  EXPECT_DOUBLE_EQ(suffuse::face_node_area(g, GridFace{0, true}, g.node_index(2, 1, 1)), 6.0);  // 2 x 3
  EXPECT_DOUBLE_EQ(face_total(g, front), 2.0 * 6.0);
  EXPECT_DOUBLE_EQ(face_total(g, GridFace{1, true}), 2.0 * 12.0);
  EXPECT_DOUBLE_EQ(face_total(g, GridFace{0, false}), 6.0 * 12.0);
}

TEST(BoundaryCondition, RampFactorGrowsLinearlyThenHolds) {
  EXPECT_EQ(suffuse::ramp_factor(0.0, 0.2), 0.0);
  EXPECT_DOUBLE_EQ(suffuse::ramp_factor(0.05, 0.2), 0.25);
  EXPECT_DOUBLE_EQ(suffuse::ramp_factor(0.2, 0.2), 1.0);
  EXPECT_EQ(suffuse::ramp_factor(7.0, 0.2), 1.0) << "held after the ramp";
  EXPECT_EQ(suffuse::ramp_factor(0.0, 0.0), 1.0) << "no ramp: full at once";
  EXPECT_EQ(suffuse::ramp_factor(3.0, 0.0), 1.0);
}

}  // namespace
