// Normals of a reshaped mesh keep its smoothing: hard edges hard, seam copies one normal.
#include "cgamesh/mesh/normals.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

namespace {

using namespace cgamesh;

/// A unit cube with one quad of 4 vertices per side (24 vertices, normals of their side): every
/// edge hard.
mesh::Mesh hard_cube() {
  mesh::Mesh m;
  m.positions.resize(24, 3);
  m.normals.resize(24, 3);
  m.faces.resize(12, 3);
  int v = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (const float side : {-1.0f, 1.0f}) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = side;
      const Eigen::Vector3f u = Eigen::Vector3f::Unit((axis + 1) % 3), w = Eigen::Vector3f::Unit((axis + 2) % 3);
      const Eigen::Vector3f s = side > 0 ? u : w, t = side > 0 ? w : u;  // s × t = n
      const Eigen::Vector3f c = 0.5f * n;
      for (const auto& [a, b] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        m.positions.row(v) = (c + 0.5f * (a * s + b * t)).transpose();
        m.normals.row(v) = n.transpose();
        ++v;
      }
      const int f = v / 4 - 1, base = v - 4;
      m.faces.row(2 * f) << base, base + 1, base + 2;
      m.faces.row(2 * f + 1) << base, base + 2, base + 3;
    }
  return m;
}

/// A latitude–longitude sphere whose seam meridian is split (copies with the same normal, as
/// a UV seam makes them); poles are single vertices.
mesh::Mesh seamed_sphere(int rings, int segments) {
  mesh::Mesh m;
  const int count = 2 + (rings - 1) * (segments + 1);
  m.positions.resize(count, 3);
  m.normals.resize(count, 3);
  m.positions.row(0) << 0, 0, 1;
  m.positions.row(count - 1) << 0, 0, -1;
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s <= segments; ++s) {
      const double theta = std::numbers::pi * r / rings, phi = 2 * std::numbers::pi * (s % segments) / segments;
      m.positions.row(1 + (r - 1) * (segments + 1) + s) << static_cast<float>(std::sin(theta) * std::cos(phi)),
          static_cast<float>(std::sin(theta) * std::sin(phi)), static_cast<float>(std::cos(theta));
    }
  m.normals = m.positions;
  std::vector<std::array<int, 3>> faces;
  const auto at = [&](int r, int s) { return 1 + (r - 1) * (segments + 1) + s; };
  for (int s = 0; s < segments; ++s) {
    faces.push_back({0, at(1, s), at(1, s + 1)});
    faces.push_back({count - 1, at(rings - 1, s + 1), at(rings - 1, s)});
    for (int r = 1; r + 1 < rings; ++r) {
      faces.push_back({at(r, s), at(r + 1, s), at(r + 1, s + 1)});
      faces.push_back({at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    }
  }
  m.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    m.faces.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  return m;
}

TEST(ReshapedNormals, ASimilarityTurnsEveryNormalOfAHardCube) {
  const mesh::Mesh cube = hard_cube();
  EXPECT_LT((mesh::reshaped_normals(cube, cube.positions) - cube.normals).cwiseAbs().maxCoeff(), 1e-6f);
  const Eigen::Matrix3f r = Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1, 2, 3).normalized()).toRotationMatrix();
  mesh::RowMatrixXf<3> moved = (2.5f * cube.positions * r.transpose()).rowwise() + Eigen::RowVector3f(1, -2, 3);
  EXPECT_LT((mesh::reshaped_normals(cube, moved) - cube.normals * r.transpose()).cwiseAbs().maxCoeff(), 1e-6f);
}

TEST(ReshapedNormals, SeamCopiesShareOneNormalThatFollowsTheShape) {
  const mesh::Mesh sphere = seamed_sphere(24, 48);
  // Stretched to an ellipsoid x²/a² + y²/b² + z²/c² = 1, whose normal is (x/a², y/b², z/c²).
  const Eigen::RowVector3f axes(2.0f, 1.0f, 0.5f);
  const mesh::RowMatrixXf<3> ellipsoid = sphere.positions.array().rowwise() * axes.array();
  const mesh::RowMatrixXf<3> n = mesh::reshaped_normals(sphere, ellipsoid);
  double worst = 0;
  for (Eigen::Index v = 0; v < n.rows(); ++v) {
    EXPECT_NEAR(n.row(v).norm(), 1.0f, 1e-6f);
    const Eigen::RowVector3f exact = (ellipsoid.row(v).array() / (axes.array() * axes.array())).matrix().normalized();
    worst = std::max(worst, std::acos(std::min(1.0, static_cast<double>(n.row(v).dot(exact)))));
  }
  EXPECT_LT(worst, 4.0 * std::numbers::pi / 180) << "an area-weighted normal on a 24 × 48 grid";
  for (int r = 1; r < 24; ++r) {
    const int first = 1 + (r - 1) * 49;
    EXPECT_EQ(n.row(first), n.row(first + 48)) << "ring " << r << ": the seam shows";
  }
}

TEST(ReshapedNormals, NoNormalsGiveNoneAndDegenerateFacesKeepTheRestNormal) {
  mesh::Mesh cube = hard_cube();
  EXPECT_EQ(mesh::reshaped_normals(cube, mesh::RowMatrixXf<3>::Zero(24, 3)), cube.normals);
  EXPECT_THROW((void)mesh::reshaped_normals(cube, mesh::RowMatrixXf<3>::Zero(23, 3)), InvalidInputError);
  cube.normals.resize(0, 3);
  EXPECT_EQ(mesh::reshaped_normals(cube, cube.positions).rows(), 0);
}

// A square pyramid: the apex's normal is the axis, a base corner's weighs its two triangular
// faces and the base by their areas (twice the cross products); a vertex on no face gets zero.
TEST(AreaWeightedNormals, EachVertexSumsItsFacesCrossProducts) {
  mesh::RowMatrixXf<3> x(6, 3);
  x << -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 2, 5, 5, 5;
  mesh::Faces f(6, 3);
  f << 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 2, 1, 0, 3, 2;
  const mesh::RowMatrixXf<3> n = mesh::area_weighted_normals(x, f);
  EXPECT_LT((n.row(4) - Eigen::RowVector3f(0, 0, 1)).norm(), 1e-6f);
  // Corner 0: faces 0 (normal (0, -4, 2)), 3 ((-4, 0, 2)), and both base triangles ((0, 0, -4) each).
  const Eigen::RowVector3f corner = Eigen::RowVector3f(-4, -4, -4).normalized();
  EXPECT_LT((n.row(0) - corner).norm(), 1e-6f);
  EXPECT_EQ(n.row(5), Eigen::RowVector3f::Zero());
}
}  // namespace
