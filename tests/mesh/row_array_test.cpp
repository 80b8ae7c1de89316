#include "cgamesh/mesh/row_array.hpp"

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "cgamesh/mesh/mesh.hpp"

namespace {

using cgamesh::mesh::Mesh;
using cgamesh::mesh::PlainRows;
using cgamesh::mesh::RowArray;
using Rows3 = RowArray<float, 3>;

Rows3 counting(Eigen::Index rows) {
  Rows3 a(rows, 3);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = static_cast<float>(i);
  return a;
}

TEST(RowArray, GrowsWithinItsCapacityWithoutMovingItsRows) {
  Rows3 a = counting(1000);
  a.reserve(1200);
  const float* before = a.data();
  a.conservativeResize(1100, Eigen::NoChange);
  EXPECT_EQ(a.data(), before);
  EXPECT_EQ(a.rows(), 1100);
  EXPECT_EQ(a(999, 2), 2999.0f);
  EXPECT_EQ(a.row(1099), Eigen::RowVector3f::Zero());
  a.conservativeResize(10, Eigen::NoChange);  // shrinking keeps the capacity
  EXPECT_EQ(a.data(), before);
  EXPECT_GE(a.capacity(), 1200);
  a.conservativeResize(1200, Eigen::NoChange);
  EXPECT_EQ(a.data(), before);
}

TEST(RowArray, GrowsByHalfWhenFullSoThatGrowingRowByRowCopiesRarely) {
  Rows3 a = counting(1000);
  EXPECT_EQ(a.capacity(), 1000);
  int moves = 0;
  for (Eigen::Index n = 1001; n <= 100000; ++n) {
    const float* before = a.data();
    a.conservativeResize(n, Eigen::NoChange);
    moves += a.data() != before ? 1 : 0;
  }
  EXPECT_LE(moves, 12);  // 1000 · 1.5^12 > 100 000
  EXPECT_EQ(a(999, 0), 2997.0f);
  EXPECT_EQ(a.rows(), 100000);
}

TEST(RowArray, CopiesAreDeepAndMovesTakeTheBuffer) {
  Rows3 a = counting(4);
  Rows3 b = a;
  b(0, 0) = -1.0f;
  EXPECT_EQ(a(0, 0), 0.0f);
  EXPECT_NE(a.data(), b.data());
  const float* buffer = a.data();
  Rows3 c = std::move(a);
  EXPECT_EQ(c.data(), buffer);
  EXPECT_EQ(c(3, 2), 11.0f);
  EXPECT_EQ(a.rows(), 0);  // NOLINT(bugprone-use-after-move): a moved-from array is empty
  b = std::move(c);
  EXPECT_EQ(b.data(), buffer);
  EXPECT_EQ(c.rows(), 0);  // NOLINT(bugprone-use-after-move)
  a = b;
  EXPECT_EQ(a, b);
  EXPECT_NE(a.data(), b.data());
  std::vector<Rows3> many(3, counting(2));  // copies in a vector stay views of their own buffers
  many.push_back(counting(5));
  for (const Rows3& m : many) EXPECT_EQ(m(1, 1), 4.0f);
}

TEST(RowArray, AssignmentTakesTheRowCountOfAnyExpression) {
  Rows3 a = counting(5);
  a = PlainRows<float, 3>::Ones(7, 3) * 2.0f;
  EXPECT_EQ(a.rows(), 7);
  EXPECT_EQ(a.sum(), 42.0f);
  a = a.topRows(2).eval();
  EXPECT_EQ(a.rows(), 2);
  a = a.topRows(1);  // the kept rows stay where they are
  EXPECT_EQ(a.row(0), Eigen::RowVector3f::Constant(2.0f));
  const Eigen::MatrixXf dynamic = Eigen::MatrixXf::Constant(3, 3, 5.0f);
  a = dynamic;
  EXPECT_EQ(a.rows(), 3);
  EXPECT_EQ(a.minCoeff(), 5.0f);
  const PlainRows<float, 3> plain = a;  // and converts back to a matrix
  EXPECT_EQ(plain, a);
}

TEST(RowArray, ColumnsSetAndResizeAsOnAVector) {
  RowArray<int, 1> v(3);
  v.setConstant(5, 7);
  EXPECT_EQ(v.rows(), 5);
  EXPECT_EQ(v[4], 7);
  v.resize(6);
  EXPECT_EQ(v[0], 7);
  EXPECT_EQ(v[5], 0);
  v.setZero(2);
  EXPECT_EQ(v, Eigen::Vector2i::Zero());
  RowArray<std::uint8_t, 1> empty;
  empty.reserve(100);
  EXPECT_EQ(empty.rows(), 0);
  EXPECT_GE(empty.capacity(), 100);
}

TEST(RowArray, MeshReserveMakesRoomInEveryArrayItHas) {
  Mesh m;
  m.positions = counting(3);
  m.normals = counting(3);
  m.faces.resize(1, 3);
  m.faces << 0, 1, 2;
  m.reserve(1000, 500);
  EXPECT_GE(m.positions.capacity(), 1000);
  EXPECT_GE(m.normals.capacity(), 1000);
  EXPECT_GE(m.generated.capacity(), 1000);  // operations add it
  EXPECT_EQ(m.uvs.capacity(), 0);           // absent, stays absent
  EXPECT_GE(m.faces.capacity(), 500);
  EXPECT_GE(m.face_materials.capacity(), 500);
  EXPECT_EQ(m.vertex_count(), 3);
  EXPECT_EQ(m.face_count(), 1);
  EXPECT_EQ(m.positions(2, 2), 8.0f);
}

}  // namespace
