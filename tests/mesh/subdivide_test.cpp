#include "cgamesh/mesh/subdivide.hpp"

#include <gtest/gtest.h>

#include <set>
#include <utility>

#include "anim/model_fixtures.hpp"
#include "cgamesh/io/model_loader.hpp"

namespace {

using namespace cgamesh;

TEST(Subdivide, CountsMidpointsAndWeights) {
  const mesh::Mesh in = io::load_model(cgamesh_test::demo_model()).meshes[0];
  std::set<std::pair<int, int>> edges;
  for (Eigen::Index f = 0; f < in.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = in.faces(f, k), b = in.faces(f, (k + 1) % 3);
      edges.emplace(std::min(a, b), std::max(a, b));
    }
  const mesh::Mesh out = mesh::subdivide_midpoint(in);
  ASSERT_EQ(out.vertex_count(), in.vertex_count() + static_cast<Eigen::Index>(edges.size()));
  ASSERT_EQ(out.face_count(), 4 * in.face_count());
  EXPECT_EQ(out.positions.topRows(in.vertex_count()), in.positions);
  // Face f's first child is (a, mid(a, b), mid(c, a)).
  for (Eigen::Index f = 0; f < in.face_count(); f += 97) {
    const int a = in.faces(f, 0), b = in.faces(f, 1);
    const int ab = out.faces(4 * f, 1);
    EXPECT_TRUE(out.positions.row(ab).isApprox(0.5f * (in.positions.row(a) + in.positions.row(b)), 1e-6f));
  }
  for (Eigen::Index i = 0; i < out.vertex_count(); ++i) {
    EXPECT_NEAR(out.skin.weights.row(i).sum(), 1.0f, 1e-5f);
    EXPECT_NEAR(out.normals.row(i).norm(), 1.0f, 1e-4f);
  }
}

}  // namespace
