// Welding by exact position: the one rule the surface index, the harmonic fields and the tests
// weld by.
#include "cgamesh/mesh/weld.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

#include "mesh/position_welder.hpp"

namespace {

using namespace cgamesh;

TEST(Weld, SmallestIndexAtTheSamePositionAndMinusZeroIsZero) {
  mesh::RowMatrixXf<3> p(6, 3);
  p << 1, 2, 3,          //
      0, 0, 0,           //
      1, 2, 3,           //
      -0.0f, 0, -0.0f,   //
      1, 2, 3.0000002f,  //
      0, 0, 0;
  EXPECT_EQ(mesh::weld_by_position(p), (std::vector<int>{0, 1, 0, 1, 4, 1}));
}

TEST(Weld, OnDemandAgreesWithTheWholeMeshInIncreasingOrder) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coordinate(0, 3);
  mesh::RowMatrixXf<3> p(500, 3);
  for (Eigen::Index i = 0; i < p.rows(); ++i)
    for (int c = 0; c < 3; ++c) p(i, c) = static_cast<float>(coordinate(rng)) * 0.5f;
  const std::vector<int> all = mesh::weld_by_position(p);
  mesh::PositionWelder welder(p);
  for (int v = 0; v < 500; ++v) {
    EXPECT_EQ(welder(v), all[static_cast<std::size_t>(v)]);
    EXPECT_LE(all[static_cast<std::size_t>(v)], v);
    EXPECT_EQ(p.row(v), p.row(all[static_cast<std::size_t>(v)]));
  }
  // Asked out of order, the first vertex asked about represents its class.
  mesh::PositionWelder backwards(p);
  for (int v = 499; v >= 0; --v) EXPECT_GE(backwards(v), v);
}

TEST(Weld, ClassesNumberedDenselyInOrderOfTheirFirstVertex) {
  std::vector<int> ids{0, 1, 0, 3, 1, 3, 6};
  EXPECT_EQ(mesh::number_classes(ids), 4);
  EXPECT_EQ(ids, (std::vector<int>{0, 1, 0, 2, 1, 2, 3}));
  std::vector<int> bad{0, 2, 2};
  EXPECT_THROW(static_cast<void>(mesh::number_classes(bad)), InvalidInputError);
}

TEST(Weld, JoinsVerticesEqualInEveryAttributeAndKeepsSeams) {
  // A quad as a soup of two triangles: the copies of the diagonal's ends join, except where a
  // UV differs (a seam) or the weights differ.
  mesh::Mesh m;
  m.positions.resize(6, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0,  //
      -0.0f, 0, 0, 1, 1, 0, 0, 1, 0;
  m.uvs.resize(6, 2);
  m.uvs << 0, 0, 1, 0, 1, 1,  //
      0, 0, 1, 1, 0, 1;
  m.faces.resize(2, 3);
  m.faces << 0, 1, 2, 3, 4, 5;
  mesh::Mesh seam = m;
  seam.uvs(4, 0) = 0.5f;
  EXPECT_EQ(mesh::join_identical_vertices(m), 2);
  EXPECT_EQ(m.vertex_count(), 4);
  EXPECT_EQ(m.faces.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(m.uvs.row(3), Eigen::RowVector2f(0, 1));
  EXPECT_EQ(mesh::join_identical_vertices(seam), 1);
  EXPECT_EQ(seam.faces.row(1), Eigen::RowVector3i(0, 3, 4));

  mesh::Mesh skinned = m;
  skinned.positions.row(3) = skinned.positions.row(0);
  skinned.uvs.row(3) = skinned.uvs.row(0);
  skinned.skin.palette = {0, 1};
  skinned.skin.joints.setZero(4, 4);
  skinned.skin.weights.setZero(4, 4);
  skinned.skin.weights.col(0).setOnes();
  skinned.skin.joints(3, 0) = 1;  // vertex 3 sits on vertex 0 but on another joint
  EXPECT_EQ(mesh::join_identical_vertices(skinned), 0);
  skinned.skin.joints(3, 0) = 0;
  EXPECT_EQ(mesh::join_identical_vertices(skinned), 1);
  EXPECT_EQ(skinned.skin.joints.rows(), 3);
}

}  // namespace
