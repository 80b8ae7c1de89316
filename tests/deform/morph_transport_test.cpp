// Morph targets through a deformation of the rest shape: displacements turn and stretch with the
// surface (to first order), exactly under a similarity.
#include "cgamesh/deform/morph_transport.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/normals.hpp"

#include "deform/deform_fixtures.hpp"

namespace {

using namespace cgamesh;
using cgamesh_deform_test::cylinder;

/// A cylinder (split at a seam) with a target that pushes each vertex outward by 0.05 times
/// (1 + z), and a normal displacement along z.
mesh::Mesh cylinder_with_target(int around = 24, int rings = 11) {
  mesh::Mesh m = cylinder(around, rings, true);
  mesh::MorphTarget t;
  t.name = "swell";
  t.positions.resize(m.vertex_count(), 3);
  t.normals.resize(m.vertex_count(), 3);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    t.positions.row(v) << 0.05f * (1 + m.positions(v, 2)) * m.positions(v, 0),
        0.05f * (1 + m.positions(v, 2)) * m.positions(v, 1), 0.0f;
    t.normals.row(v) << 0, 0, 0.1f;
  }
  m.morph_targets.push_back(t);
  m.morph_weights = {1.0f};
  return m;
}

/// A twist about z by `turns` radians per unit of height: it turns the cylinder's normals with
/// its surface, so that the deformation of the morphed shape is what carried displacements give
/// (to first order).
Eigen::Vector3d twisted(const Eigen::Vector3d& x, double turns) {
  const double a = turns * x.z(), c = std::cos(a), s = std::sin(a);
  return {c * x.x() - s * x.y(), s * x.x() + c * x.y(), x.z()};
}

double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / std::numbers::pi;
}

TEST(MorphTransport, ASimilarityTurnsAndScalesTheDisplacementsExactly) {
  mesh::Mesh m = cylinder_with_target();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const double scale = 1.8;
  mesh::RowMatrixXf<3> moved(m.vertex_count(), 3);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    moved.row(v) = (scale * r * m.positions.row(v).transpose().cast<double>() + Eigen::Vector3d(0.5, -1, 2))
                       .transpose()
                       .cast<float>();
  for (const Eigen::Matrix3d& j : deform::local_linear_maps(m.positions, moved, m.faces))
    EXPECT_LE((j - scale * r).cwiseAbs().maxCoeff(), 1e-5);
  const mesh::MorphTarget before = m.morph_targets[0];
  deform::transport_morph_targets(m, moved);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const Eigen::Vector3d d = before.positions.row(v).transpose().cast<double>();
    const Eigen::Vector3d n = before.normals.row(v).transpose().cast<double>();
    EXPECT_LE((m.morph_targets[0].positions.row(v).transpose().cast<double>() - scale * r * d).norm(), 1e-6);
    EXPECT_LE((m.morph_targets[0].normals.row(v).transpose().cast<double>() - r * n).norm(), 1e-6);
  }
}

TEST(MorphTransport, ATwistedSurfaceCarriesItsShapeToFirstOrder) {
  // Fine enough that the maps, fitted over one ring of edges, are close to the twist's Jacobian.
  mesh::Mesh m = cylinder_with_target(96, 41);
  mesh::RowMatrixXf<3> moved(m.vertex_count(), 3);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    moved.row(v) = twisted(m.positions.row(v).transpose().cast<double>(), 1.5).transpose().cast<float>();
  const mesh::MorphTarget before = m.morph_targets[0];
  mesh::Mesh carried = m;
  deform::transport_morph_targets(carried, moved);
  // The reference: the deformation applied to the morphed rest shape.
  double kept = 0, carried_error = 0;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const Eigen::Vector3d x = m.positions.row(v).transpose().cast<double>();
    const Eigen::Vector3d d = before.positions.row(v).transpose().cast<double>();
    const Eigen::Vector3d truth = twisted(x + d, 1.5);
    const Eigen::Vector3d y = moved.row(v).transpose().cast<double>();
    kept = std::max(kept, (y + d - truth).norm());
    carried_error =
        std::max(carried_error, (y + carried.morph_targets[0].positions.row(v).transpose().cast<double>() - truth).norm());
  }
  EXPECT_GT(kept, 0.05) << "the displacements as they were point the wrong way on the twisted surface";
  EXPECT_LT(carried_error, kept / 5) << "carried: " << carried_error << ", kept: " << kept;
  // Seam vertices (one position, two vertices) get one map.
  const auto maps = deform::local_linear_maps(m.positions, moved, m.faces);
  EXPECT_EQ(maps[0], maps[96]);
}

TEST(MorphTransport, TheDeformedModelCarriesItsTargets) {
  anim::RiggedModel model;
  model.meshes.push_back(cylinder_with_target());
  const deform::DeformSpec s =
      deform::parse_spec(R"({"method": "harmonic", "handles": [{"box": [-2, -2, -1, 2, 2, 0.01]},
      {"box": [-2, -2, 0.99, 2, 2, 2]}], "keys": [{}, {"rotate": [1, 0, 0, 30], "center": [0, 0, 1]}]})",
                         "inline");
  const deform::BoundDeformer bound(s, model);
  const mesh::RowMatrixXf<3> positions = bound.apply(bound.keys());
  const anim::RiggedModel out = bound.deformed_model(model, positions);
  const mesh::Mesh& m = out.meshes[0];
  ASSERT_EQ(m.morph_targets.size(), 1u);
  const auto maps = deform::local_linear_maps(model.meshes[0].positions, m.positions, m.faces);
  // The target swells along the normal; on the bent cylinder it still does (the displacement
  // kept as it was points off the surface's normal by up to 44°, carried by up to 9°).
  const mesh::RowMatrixXf<3> normals = mesh::area_weighted_normals(m.positions, m.faces);
  double carried = 0, kept = 0;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const Eigen::Vector3d d = model.meshes[0].morph_targets[0].positions.row(v).transpose().cast<double>();
    const Eigen::Vector3d e = m.morph_targets[0].positions.row(v).transpose().cast<double>();
    const Eigen::Vector3d n = normals.row(v).transpose().cast<double>();
    EXPECT_LE((e - maps[static_cast<std::size_t>(v)] * d).norm(), 1e-6);
    carried = std::max(carried, degrees_between(e, n));
    kept = std::max(kept, degrees_between(d, n));
  }
  EXPECT_GT(kept, 20.0);
  EXPECT_LT(carried, kept / 4) << "kept: " << kept;
  EXPECT_THROW(deform::transport_morph_targets(model.meshes[0], mesh::RowMatrixXf<3>(3, 3)), InvalidInputError);
}

}  // namespace
