// posed_frame: one posed frame's positions and skinned normals, from one palette per mesh; the
// normals are unit, equal anim::skin_normals, and fit the posed surface where the rest normals fit
// the rest surface.

#include "cgamesh/io/text_values.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"

namespace {

using namespace cgamesh;
using anim::SkinningMode;

constexpr SkinningMode kModes[] = {SkinningMode::cga, SkinningMode::versor, SkinningMode::matrix, SkinningMode::dqs};

const anim::RiggedModel& cesium() {
  static const anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  return model;
}

anim::Pose walking(const anim::RiggedModel& model) {
  return anim::sample(model.skeleton, model.clips.at(0), 0.5, anim::BlendMode::format);
}

/// Area-weighted normals of the faces around each vertex of `x` (unit; 0 where no face).
mesh::RowMatrixXf<3> face_normals_at_vertices(const mesh::RowMatrixXf<3>& x, const mesh::Mesh& m) {
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
  Rows sum = Rows::Zero(x.rows(), 3);
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3d a = x.row(m.faces(f, 0)).transpose().cast<double>();
    const Eigen::Vector3d b = x.row(m.faces(f, 1)).transpose().cast<double>();
    const Eigen::Vector3d c = x.row(m.faces(f, 2)).transpose().cast<double>();
    const Eigen::RowVector3d n = (b - a).cross(c - a).transpose();  // twice the area, along the normal
    for (int k = 0; k < 3; ++k) sum.row(m.faces(f, k)) += n;
  }
  for (Eigen::Index v = 0; v < sum.rows(); ++v)
    if (sum.row(v).norm() > 0) sum.row(v).normalize();
  return sum.cast<float>();
}

/// The fraction of `vertices` where rows of `a` and `b` are within `degrees` of each other.
double fraction_within(const mesh::RowMatrixXf<3>& a, const mesh::RowMatrixXf<3>& b,
                       const std::vector<Eigen::Index>& vertices, double degrees) {
  const double cos_max = std::cos(degrees * std::numbers::pi / 180);
  int within = 0;
  for (const Eigen::Index v : vertices)
    if (static_cast<double>(a.row(v).dot(b.row(v))) >= cos_max) ++within;
  return static_cast<double>(within) / static_cast<double>(vertices.size());
}

TEST(PosedFrame, PositionsAndNormalsComeFromOnePalette) {
  const anim::RiggedModel& model = cesium();
  const anim::Pose pose = walking(model);
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  for (const SkinningMode mode : kModes) {
    SCOPED_TRACE(static_cast<int>(mode));
    const io::PosedFrame frame = io::posed_frame(model, pose, mode);
    const std::vector<mesh::RowMatrixXf<3>> positions = io::posed_positions(model, pose, mode);
    ASSERT_EQ(frame.positions.size(), model.meshes.size());
    ASSERT_EQ(frame.normals.size(), model.meshes.size());
    for (std::size_t i = 0; i < model.meshes.size(); ++i) {
      const mesh::Mesh& m = model.meshes[i];
      ASSERT_EQ(m.normals.rows(), m.vertex_count());
      EXPECT_TRUE(frame.positions[i] == positions[i]);
      const mesh::RowMatrixXf<3> expected = anim::skin_normals(m, anim::make_palette(m, gv, gm, mode));
      ASSERT_EQ(frame.normals[i].rows(), m.vertex_count());
      EXPECT_TRUE(frame.normals[i] == expected);
      const Eigen::ArrayXf length = frame.normals[i].rowwise().norm();
      EXPECT_LT((length - 1).abs().maxCoeff(), 1e-5f);
      EXPECT_GT((frame.normals[i] - m.normals).rowwise().norm().maxCoeff(), 0.5f) << "the rest normals, not posed";
    }
  }
}

TEST(PosedFrame, NormalsFitThePosedSurface) {
  // Where a rest normal agrees with the normals of the faces around its vertex (smooth surface,
  // not a seam or crease), the posed normal must agree with the posed faces around it; the rest
  // normals, which a posed file used to carry, do not.
  const anim::RiggedModel& model = cesium();
  const mesh::Mesh& m = model.meshes.at(0);
  const mesh::RowMatrixXf<3> rest_faces = face_normals_at_vertices(m.positions, m);
  std::vector<Eigen::Index> smooth;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    if (m.normals.row(v).dot(rest_faces.row(v)) >= std::cos(5 * std::numbers::pi / 180)) smooth.push_back(v);
  ASSERT_GT(smooth.size(), static_cast<std::size_t>(m.vertex_count() / 2));
  for (const SkinningMode mode : kModes) {
    SCOPED_TRACE(static_cast<int>(mode));
    const io::PosedFrame frame = io::posed_frame(model, walking(model), mode);
    const mesh::RowMatrixXf<3> posed_faces = face_normals_at_vertices(frame.positions[0], m);
    // Blending bends the posed surface near joints a little away from the turned normals.
    EXPECT_GT(fraction_within(frame.normals[0], posed_faces, smooth, 10), 0.95);
    EXPECT_GT(fraction_within(frame.normals[0], posed_faces, smooth, 20), 0.99);
    EXPECT_LT(fraction_within(m.normals, posed_faces, smooth, 10), 0.1);
  }
}

TEST(PosedFrame, MeshWithoutNormalsGetsNone) {
  anim::RiggedModel model = cesium();
  model.meshes[0].normals.resize(0, 3);
  const io::PosedFrame frame = io::posed_frame(model, walking(model), SkinningMode::cga);
  ASSERT_EQ(frame.normals.size(), 1u);
  EXPECT_EQ(frame.normals[0].rows(), 0);
  EXPECT_EQ(frame.positions[0].rows(), model.meshes[0].vertex_count());
}

TEST(PosedFrame, StaticMeshTurnsItsNormalsWithItsNode) {
  // CesiumMan's mesh without its skin, hung from the joint that the walk turns most: a static
  // mesh follows its node, normals by the inverse transpose of the node's linear map.
  anim::RiggedModel model = cesium();
  const anim::Pose pose = walking(model);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  int node = 0;
  for (int j = 0; j < model.skeleton.size(); ++j)
    if ((gm[static_cast<std::size_t>(j)].topLeftCorner<3, 3>() - Eigen::Matrix3d::Identity()).norm() >
        (gm[static_cast<std::size_t>(node)].topLeftCorner<3, 3>() - Eigen::Matrix3d::Identity()).norm())
      node = j;
  mesh::Mesh& m = model.meshes.at(0);
  m.skin = {};
  m.node = node;
  const Eigen::Matrix3d normal_map = gm[static_cast<std::size_t>(node)].topLeftCorner<3, 3>().inverse().transpose();
  ASSERT_GT((normal_map - Eigen::Matrix3d::Identity()).norm(), 0.5);
  for (const SkinningMode mode : kModes) {
    SCOPED_TRACE(static_cast<int>(mode));
    const io::PosedFrame frame = io::posed_frame(model, pose, mode);
    ASSERT_EQ(frame.normals.at(0).rows(), m.vertex_count());
    double worst = 0;
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
      const Eigen::Vector3d expected = (normal_map * m.normals.row(v).transpose().cast<double>()).normalized();
      worst = std::max(worst, (frame.normals[0].row(v).transpose().cast<double>() - expected).norm());
    }
    EXPECT_LT(worst, 1e-5);
  }
}

}  // namespace
