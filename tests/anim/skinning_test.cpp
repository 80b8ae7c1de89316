#include "cgamesh/anim/skinning.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"

namespace {

using namespace cgamesh;
using anim::SkinningMode;

struct Posed {
  std::vector<cga::Versor<double>> gv;
  std::vector<Eigen::Matrix4d> gm;
};

Posed posed(const anim::RiggedModel& m, const anim::Pose& p) {
  return {anim::global_versors(m.skeleton, p), anim::global_matrices(m.skeleton, p)};
}

mesh::RowMatrixXf<3> run(const mesh::Mesh& mesh, const Posed& p, SkinningMode mode, int threads = 0) {
  return anim::skin(mesh, anim::make_palette(mesh, p.gv, p.gm, mode), threads);
}

double max_distance(const mesh::RowMatrixXf<3>& a, const mesh::RowMatrixXf<3>& b) {
  return (a - b).rowwise().norm().maxCoeff();
}
double diagonal(const mesh::RowMatrixXf<3>& a) { return (a.colwise().maxCoeff() - a.colwise().minCoeff()).norm(); }

std::vector<std::filesystem::path> rigged_models() {
  auto models = cgamesh_test::gltf_samples();
  for (const char* f : {"X/BCN_Epileptic.X", "X/Testwuson.X"})
    if (std::filesystem::exists(cgamesh_test::assimp_model(f))) models.push_back(cgamesh_test::assimp_model(f));
  return models;
}

// Eq. (17) (cga) must equal matrix LBS to float precision, and so must the literal per-vertex
// sandwich reference; with rigid joints the versor blend must equal dual-quaternion skinning.
TEST(Skinning, CgaEqualsMatrixAndReferenceOnRealModels) {
  for (const auto& path : rigged_models()) {
    SCOPED_TRACE(path.string());
    const anim::RiggedModel m = io::load_model(path);
    ASSERT_FALSE(m.clips.empty());
    for (double t : {0.0, 0.3, 0.7, 1.1}) {
      const Posed p = posed(m, anim::sample(m.skeleton, m.clips[0], t, anim::BlendMode::format));
      for (const mesh::Mesh& mesh : m.meshes) {
        const auto matrix = run(mesh, p, SkinningMode::matrix);
        const double tol = 1e-5 * diagonal(matrix);
        EXPECT_LE(max_distance(run(mesh, p, SkinningMode::cga), matrix), tol) << mesh.name << " t=" << t;
        EXPECT_LE(max_distance(anim::skin_cga_reference(mesh, p.gv), matrix), tol) << mesh.name << " t=" << t;
        EXPECT_LE(max_distance(run(mesh, p, SkinningMode::versor), run(mesh, p, SkinningMode::dqs)), tol)
            << mesh.name << " t=" << t;
      }
    }
  }
}

// The blend modes differ from linear blend skinning where joints bend (no candy wrapper), so
// the test above is not trivially satisfied by returning the same positions for all modes.
TEST(Skinning, VersorBlendDiffersFromLinearBlendWhereJointsBend) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const Posed p = posed(m, anim::sample(m.skeleton, m.clips[0], 1.0, anim::BlendMode::format));
  const auto matrix = run(m.meshes[0], p, SkinningMode::matrix);
  EXPECT_GT(max_distance(run(m.meshes[0], p, SkinningMode::versor), matrix), 1e-3 * diagonal(matrix));
}

// A dilation of one bone: the versor mode scales the region bound to that bone uniformly
// (distances between its vertices grow by the factor) and agrees with the matrix there.
TEST(Skinning, DilationScalesTheBoneRegionUniformly) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const mesh::Mesh& mesh = m.meshes[0];
  const int palette_entry = mesh.skin.joints(0, 0);
  const int joint = mesh.skin.palette[palette_entry];
  std::vector<Eigen::Index> region;
  for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i)
    if (mesh.skin.joints(i, 0) == palette_entry && mesh.skin.weights(i, 0) == 1.0f) region.push_back(i);
  ASSERT_GE(region.size(), 4u);

  anim::Pose pose = anim::rest_pose(m.skeleton);
  const Posed before = posed(m, pose);
  const anim::JointEdit edit{.joint = joint, .scale = 2.0};
  anim::apply_edits(pose, std::span(&edit, 1));
  const Posed after = posed(m, pose);
  const auto a = run(mesh, before, SkinningMode::versor), b = run(mesh, after, SkinningMode::versor);
  const auto bm = run(mesh, after, SkinningMode::matrix);
  for (std::size_t k = 1; k < region.size(); ++k) {
    const float d0 = (a.row(region[k]) - a.row(region[0])).norm();
    const float d1 = (b.row(region[k]) - b.row(region[0])).norm();
    EXPECT_NEAR(d1, 2.0f * d0, 1e-4f * (1 + d0));
    EXPECT_LE((b.row(region[k]) - bm.row(region[k])).norm(), 1e-4f);
  }
}

// Dual quaternions hold no scale: joint scale goes first (Kavan et al. 2008), so on a rigid
// pose under one uniform scale every vertex whose joints agree lands where matrix LBS puts it,
// and a scaled rig keeps its size.
TEST(Skinning, DualQuaternionsKeepJointScale) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::demo_model());
  const mesh::Mesh& mesh = m.meshes[0];
  anim::Pose pose = anim::sample(m.skeleton, m.clips[0], 0.5, anim::BlendMode::format);
  const anim::JointEdit edit{.joint = 0, .scale = 1.7};
  anim::apply_edits(pose, std::span(&edit, 1));
  const Posed p = posed(m, pose);
  const auto matrix = run(mesh, p, SkinningMode::matrix), dqs = run(mesh, p, SkinningMode::dqs);
  const double diag = diagonal(matrix);
  int single = 0;
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.skin.weights(v, 0) == 1.0f) {
      ++single;
      ASSERT_LE((dqs.row(v) - matrix.row(v)).norm(), 1e-5 * diag) << v;
    }
  EXPECT_GT(single, 100);
  EXPECT_NEAR(diagonal(dqs) / diag, 1.0, 0.02);

  // The bind pose under the same scale: every vertex, blended or not.
  anim::Pose bind = anim::rest_pose(m.skeleton);
  anim::apply_edits(bind, std::span(&edit, 1));
  const Posed b = posed(m, bind);
  EXPECT_LE(max_distance(run(mesh, b, SkinningMode::dqs), run(mesh, b, SkinningMode::matrix)),
            1e-5 * diagonal(run(mesh, b, SkinningMode::matrix)));
}

// FBX rigs scale their joints (centimetre units): dqs came out half (huesitos) or a tenth
// (animation_with_skeleton) of the size matrix skinning gives.
TEST(Skinning, DualQuaternionsKeepTheSizeOfScaledFbxRigs) {
  for (const auto& [file, time] : {std::pair{"FBX/huesitos.fbx", 0.4}, {"FBX/animation_with_skeleton.fbx", 0.5}}) {
    const auto path = cgamesh_test::assimp_model(file);
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " not installed";
    SCOPED_TRACE(file);
    const anim::RiggedModel m = io::load_model(path);
    const anim::Pose pose = m.clips.empty() ? anim::rest_pose(m.skeleton)
                                            : anim::sample(m.skeleton, m.clips[0], time, anim::BlendMode::format);
    const Posed p = posed(m, pose);
    for (const mesh::Mesh& mesh : m.meshes) {
      if (mesh.skin.empty()) continue;
      const double ratio = diagonal(run(mesh, p, SkinningMode::dqs)) / diagonal(run(mesh, p, SkinningMode::matrix));
      EXPECT_NEAR(ratio, 1.0, 0.1) << mesh.name;
    }
  }
}

TEST(Skinning, ThreadedJobsEqualOneJob) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::demo_model());
  const Posed p = posed(m, anim::sample(m.skeleton, m.clips[0], 0.5, anim::BlendMode::format));
  for (SkinningMode mode : {SkinningMode::cga, SkinningMode::versor, SkinningMode::matrix, SkinningMode::dqs}) {
    const auto one = run(m.meshes[0], p, mode, 1);
    EXPECT_EQ(one, run(m.meshes[0], p, mode, 4));
  }
}

TEST(Skinning, PaletteRejectsPoseOfAnotherSkeleton) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const std::vector<cga::Versor<double>> too_few(1);
  const std::vector<Eigen::Matrix4d> none;
  EXPECT_THROW((void)anim::make_palette(m.meshes[0], too_few, none, SkinningMode::cga), InvalidInputError);
}

}  // namespace

namespace {

TEST(SkinNormals, RigidVerticesTurnWithTheirJointInEveryMode) {
  const auto model = io::load_model(cgamesh_test::demo_model());
  const mesh::Mesh& m = model.meshes[0];
  ASSERT_EQ(m.normals.rows(), m.vertex_count());
  const Posed p = posed(model, anim::sample(model.skeleton, model.clips[0], 0.6, anim::BlendMode::format));
  int rigid = 0;
  for (const SkinningMode mode : {SkinningMode::cga, SkinningMode::versor, SkinningMode::matrix, SkinningMode::dqs}) {
    const mesh::RowMatrixXf<3> n = anim::skin_normals(m, anim::make_palette(m, p.gv, p.gm, mode));
    ASSERT_EQ(n.rows(), m.vertex_count());
    rigid = 0;
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
      ASSERT_NEAR(n.row(v).norm(), 1.0f, 1e-5f);
      if (m.skin.weights(v, 0) < 1.0f) continue;
      ++rigid;
      // One influence: the normal turns by that joint's rotation, M_n B_n.
      const std::size_t k = m.skin.joints(v, 0);
      const Eigen::Matrix3d r =
          (p.gm[static_cast<std::size_t>(m.skin.palette[k])] * m.skin.inverse_bind[k]).topLeftCorner<3, 3>();
      const Eigen::Vector3d expected = (r * m.normals.row(v).transpose().cast<double>()).normalized();
      ASSERT_LT((n.row(v).transpose().cast<double>() - expected).norm(), 1e-4) << static_cast<int>(mode) << " " << v;
    }
  }
  EXPECT_GT(rigid, 100);
}

TEST(SkinNormals, CofactorKeepsNormalsPerpendicularUnderNonUniformScale) {
  // One triangle on a joint that scales x by 3: its skinned normal must stay perpendicular to
  // the skinned triangle, which a plain linear map of the normal would not.
  mesh::Mesh m;
  m.positions.resize(3, 3);
  m.positions << 0, 0, 0, 1, 0, 1, 0, 1, 0;
  m.faces.resize(1, 3);
  m.faces << 0, 1, 2;
  const Eigen::Vector3f face = Eigen::Vector3f(1, 0, 1).cross(Eigen::Vector3f(0, 1, 0)).normalized();
  m.normals = face.transpose().replicate(3, 1);
  m.skin.palette = {0};
  m.skin.inverse_bind = {Eigen::Matrix4d::Identity()};
  m.skin.inverse_bind_versors = {cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>())};
  m.skin.joints.setZero(3, 4);
  m.skin.weights.setZero(3, 4);
  m.skin.weights.col(0).setOnes();
  Eigen::Matrix4d g = Eigen::Matrix4d::Identity();
  g.diagonal().head<3>() << 3, 1, 1;
  const std::vector<Eigen::Matrix4d> gm{g};
  const std::vector<cga::Versor<double>> gv{cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>())};
  const auto palette = anim::make_palette(m, gv, gm, SkinningMode::matrix);
  const mesh::RowMatrixXf<3> x = anim::skin(m, palette);
  const mesh::RowMatrixXf<3> n = anim::skin_normals(m, palette);
  const Eigen::Vector3f e1 = (x.row(1) - x.row(0)).transpose(), e2 = (x.row(2) - x.row(0)).transpose();
  EXPECT_NEAR(n.row(0).dot(e1), 0, 1e-6);
  EXPECT_NEAR(n.row(0).dot(e2), 0, 1e-6);
  EXPECT_GT(n.row(0).dot(e1.cross(e2)), 0);
  // Without normals there is nothing to skin; a wrong row count is an error.
  mesh::Mesh bare = m;
  bare.normals.resize(0, 3);
  EXPECT_EQ(anim::skin_normals(bare, palette).rows(), 0);
  bare.normals.resize(2, 3);
  EXPECT_THROW(static_cast<void>(anim::skin_normals(bare, palette)), InvalidInputError);
}

}  // namespace
