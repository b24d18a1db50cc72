// The grid-face helpers of the SDK that boundary-condition plugins build on,
// and the load ramp they share.
#include <gtest/gtest.h>

#include <suffuse/boundary_condition.hpp>
#include <suffuse/grid_face.hpp>

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
