// Vertices blended from an old mesh's (section 4.3): appended in place exactly as resample()
// makes them in a new mesh, with influences that sum to 1.
#include "cgamesh/mesh/vertex_source.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"

namespace {

using namespace cgamesh;

/// Copies, edge points and face points of random vertices of `m`, some restricted to the
/// influences of one slot.
std::vector<mesh::VertexSource> random_sources(const mesh::Mesh& m, int n) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(m.vertex_count()) - 1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<mesh::VertexSource> out;
  for (int i = 0; i < n; ++i) {
    const float p = unit(rng), q = (1 - p) * unit(rng);
    switch (i % 3) {
      case 0:
        out.push_back(mesh::VertexSource::copy(vertex(rng)));
        break;
      case 1:
        out.push_back(mesh::VertexSource::edge(vertex(rng), vertex(rng), p));
        break;
      default:
        out.push_back(mesh::VertexSource::face(vertex(rng), vertex(rng), vertex(rng), p, q, 1 - p - q));
    }
    if (i % 5 == 0) out.back().influence_mask = 0b010;
  }
  return out;
}

TEST(VertexSource, AppendedInPlaceAsResampled) {
  const mesh::Mesh old = io::load_model(cgamesh_test::demo_model()).meshes[0];
  ASSERT_FALSE(old.skin.empty());
  const std::vector<mesh::VertexSource> sources = random_sources(old, 300);
  const mesh::Mesh fresh = mesh::resample(old, sources, Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>(0, 3));
  mesh::Mesh grown = old;
  mesh::append_resampled(grown, sources);
  const Eigen::Index nv = old.vertex_count(), n = static_cast<Eigen::Index>(sources.size());
  ASSERT_EQ(grown.vertex_count(), nv + n);
  EXPECT_EQ(grown.faces, old.faces);
  EXPECT_EQ(grown.positions.topRows(nv), old.positions);
  EXPECT_EQ(grown.positions.bottomRows(n), fresh.positions);
  EXPECT_EQ(grown.normals.bottomRows(n), fresh.normals);
  EXPECT_EQ(grown.uvs.bottomRows(n), fresh.uvs);
  EXPECT_EQ(grown.skin.joints.topRows(nv), old.skin.joints);
  EXPECT_EQ(grown.skin.joints.bottomRows(n), fresh.skin.joints);
  EXPECT_EQ(grown.skin.weights.bottomRows(n), fresh.skin.weights);
  // The file's numbering: a copy keeps its origin's, a blend has none.
  ASSERT_EQ(old.file_index.rows(), nv);
  ASSERT_EQ(grown.file_index.rows(), nv + n);
  ASSERT_EQ(fresh.file_index.rows(), n);
  EXPECT_EQ(grown.file_index.bottomRows(n), fresh.file_index);
  for (Eigen::Index i = 0; i < n; ++i) {
    const mesh::VertexSource& s = sources[static_cast<std::size_t>(i)];
    EXPECT_EQ(fresh.file_index[i], s.count() == 1 ? old.file_index[s.vertex[0]] : -1) << i;
  }
  for (Eigen::Index i = nv; i < nv + n; ++i) {
    EXPECT_NEAR(grown.skin.weights.row(i).sum(), 1.0f, 1e-6f);
    EXPECT_NEAR(grown.normals.row(i).norm(), 1.0f, 1e-5f);
  }
  // A face point lies in the plane of its three corners, at its barycentric weights.
  const mesh::VertexSource& s = sources[2];
  const Eigen::RowVector3f expected = s.weight[0] * old.positions.row(s.vertex[0]) +
                                      s.weight[1] * old.positions.row(s.vertex[1]) +
                                      s.weight[2] * old.positions.row(s.vertex[2]);
  EXPECT_TRUE(grown.positions.row(nv + 2).isApprox(expected, 1e-6f));
}

TEST(VertexSource, AppendRejectsAnOutsideSourceAndLeavesTheMesh) {
  mesh::Mesh m = io::load_model(cgamesh_test::demo_model()).meshes[0];
  const mesh::Mesh before = m;
  const std::vector<mesh::VertexSource> sources{mesh::VertexSource::copy(0),
                                                mesh::VertexSource::edge(1, static_cast<int>(m.vertex_count()), 0.5f)};
  EXPECT_THROW(mesh::append_resampled(m, sources), InvalidInputError);
  EXPECT_EQ(m.vertex_count(), before.vertex_count());
  EXPECT_EQ(m.positions, before.positions);
}

}  // namespace
