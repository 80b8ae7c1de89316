// place() and placed_normals(): the placed surface and its normals in one pose.
#include "cgamesh/surgery/placement.hpp"

#include <gtest/gtest.h>

#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/normals.hpp"

#include "anim/model_fixtures.hpp"

namespace {

using namespace cgamesh;

// The skinned normals are the placed surface's (against its faces' own normals, computed from the
// placed positions), and they follow the pose, not the rest shape.
TEST(Placement, PlacedNormalsAreThoseOfThePlacedSurface) {
  anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  const anim::Pose pose = anim::sample(model.skeleton, model.clips.at(0), 1.0, anim::BlendMode::format);
  const surgery::Placement placement = surgery::place(model, pose);
  const std::vector<mesh::RowMatrixXf<3>> normals = surgery::placed_normals(model, pose);
  ASSERT_EQ(normals.size(), model.meshes.size());
  const mesh::Mesh& m = model.meshes[0];
  ASSERT_EQ(normals[0].rows(), m.vertex_count());
  const mesh::RowMatrixXf<3> faces = mesh::area_weighted_normals(placement.positions[0], m.faces);
  double agree = 0, turned = 0;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    EXPECT_NEAR(normals[0].row(v).norm(), 1.0f, 1e-5f) << "vertex " << v;
    agree += normals[0].row(v).dot(faces.row(v));
    turned = std::max(turned, 1.0 - static_cast<double>(normals[0].row(v).dot(m.normals.row(v))));
  }
  EXPECT_GT(agree / static_cast<double>(m.vertex_count()), 0.95);
  EXPECT_GT(turned, 0.5) << "some normal turns by more than 60° from its rest direction";

  model.meshes[0].normals.resize(0, 3);
  EXPECT_EQ(surgery::placed_normals(model, pose)[0].rows(), 0);
}

}  // namespace
