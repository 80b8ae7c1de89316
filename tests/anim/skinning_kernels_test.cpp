// The vector kernels (blocks of 8 vertices: baseline, AVX2 and AVX-512 builds) against the scalar one.
#include <filesystem>
#include <unistd.h>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"

namespace {

using namespace cgamesh;
using anim::SkinningKernel;
using anim::SkinningMode;

constexpr SkinningMode kModes[] = {SkinningMode::cga, SkinningMode::versor, SkinningMode::matrix, SkinningMode::dqs};

std::vector<SkinningKernel> fast_kernels() {
  std::vector<SkinningKernel> out{SkinningKernel::vector};
  for (SkinningKernel k : {SkinningKernel::avx2, SkinningKernel::avx512})
    if (anim::kernel_available(k)) out.push_back(k);
  return out;
}

struct Frame {
  mesh::RowMatrixXf<3> positions, normals;
};

Frame skin(const mesh::Mesh& m, const anim::SkinningPalette& p, SkinningKernel kernel) {
  Frame f;
  anim::skin_into(m, p, f.positions, &f.normals, {.threads = 1, .kernel = kernel});
  return f;
}

/// Every mode and fast kernel equals the scalar kernel on the model's meshes in `pose`.
void expect_kernels_agree(const anim::RiggedModel& model, const anim::Pose& pose) {
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  for (const mesh::Mesh& m : model.meshes)
    for (SkinningMode mode : kModes) {
      const anim::SkinningPalette p = anim::make_palette(m, gv, gm, mode);
      const Frame ref = skin(m, p, SkinningKernel::scalar);
      // Float rounding, relative to the model's size. The 16-coefficient versor sandwich is the
      // least well conditioned: on huesitos.fbx (scaled joints, coordinates in the hundreds) the
      // scalar kernel itself is 3e-6 of the size away from the same sandwich in double.
      const double size = (ref.positions.colwise().maxCoeff() - ref.positions.colwise().minCoeff()).norm() *
                          (mode == SkinningMode::versor && p.motors.empty() ? 5.0 : 1.0);
      for (SkinningKernel kernel : fast_kernels()) {
        SCOPED_TRACE(m.name + " mode " + std::to_string(static_cast<int>(mode)) + " kernel " +
                     std::to_string(static_cast<int>(kernel)));
        const Frame f = skin(m, p, kernel);
        ASSERT_EQ(f.positions.rows(), m.vertex_count());
        ASSERT_EQ(f.normals.rows(), m.normals.rows());
        EXPECT_LE((f.positions - ref.positions).rowwise().norm().maxCoeff(), 2e-6 * size);
        // Asking for normals does not change the positions.
        mesh::RowMatrixXf<3> alone;
        anim::skin_into(m, p, alone, nullptr, {.threads = 1, .kernel = kernel});
        EXPECT_TRUE(alone == f.positions);
        if (m.normals.rows() > 0) {
          EXPECT_LE((f.normals - ref.normals).rowwise().norm().maxCoeff(), 1e-4);
        }
        // A range that starts and ends inside blocks: blocks from its start, the rest alone.
        ASSERT_GE(m.vertex_count(), 29);
        mesh::RowMatrixXf<3> part = mesh::RowMatrixXf<3>::Zero(m.vertex_count(), 3);
        anim::skin_range(m, p, 3, 29, part, nullptr, kernel);
        EXPECT_LE((part.middleRows(3, 26) - ref.positions.middleRows(3, 26)).rowwise().norm().maxCoeff(), 2e-6 * size);
        EXPECT_EQ(part.topRows(3).squaredNorm() + part.bottomRows(m.vertex_count() - 29).squaredNorm(), 0.0f);
        // Streaming stores write the same rows bit for bit, from a start inside a block too
        // (its rows are not 16-byte aligned: ordinary stores there).
        Frame streamed;
        anim::skin_into(m, p, streamed.positions, &streamed.normals,
                        {.threads = 1, .kernel = kernel, .stores = anim::SkinningStores::streaming});
        EXPECT_TRUE(streamed.positions == f.positions);
        EXPECT_TRUE(streamed.normals == f.normals);
        mesh::RowMatrixXf<3> streamed_part = mesh::RowMatrixXf<3>::Zero(m.vertex_count(), 3);
        anim::skin_range(m, p, 3, 29, streamed_part, nullptr, kernel, anim::SkinningStores::streaming);
        EXPECT_TRUE(streamed_part == part);
      }
    }
}

TEST(SkinningKernels, StreamingBytesIsTheReportedLastLevelCache) {
  // The size the system reports (Linux: sysconf), or the 32 MiB fallback: no processor skinning
  // meshes has a last-level cache under 256 KiB.
  EXPECT_GE(anim::streaming_bytes(), std::size_t{256} << 10);
#if defined(_SC_LEVEL3_CACHE_SIZE)
  if (sysconf(_SC_LEVEL3_CACHE_SIZE) > 0 && sysconf(_SC_LEVEL4_CACHE_SIZE) <= 0) {
    EXPECT_EQ(anim::streaming_bytes(), static_cast<std::size_t>(sysconf(_SC_LEVEL3_CACHE_SIZE)));
  }
#endif
}

TEST(SkinningKernels, EveryKernelEqualsTheScalarOneOnRealModels) {
  auto models = cgamesh_test::gltf_samples();
  for (const char* f : {"X/Testwuson.X", "FBX/huesitos.fbx"})
    if (std::filesystem::exists(cgamesh_test::assimp_model(f))) models.push_back(cgamesh_test::assimp_model(f));
  for (const auto& path : models) {
    SCOPED_TRACE(path.string());
    const anim::RiggedModel model = io::load_model(path);
    for (double t : {0.2, 0.9})
      expect_kernels_agree(model, model.clips.empty()
                                      ? anim::rest_pose(model.skeleton)
                                      : anim::sample(model.skeleton, model.clips[0], t, anim::BlendMode::format));
  }
}

// Scaled joints: dqs blends S first, versor blends 16 coefficients (dilators) and renormalises
// with the general closed form; a static mesh follows its node.
TEST(SkinningKernels, EveryKernelEqualsTheScalarOneWithScaledJointsAndStaticMeshes) {
  anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  anim::Pose pose = anim::sample(model.skeleton, model.clips[0], 0.5, anim::BlendMode::format);
  const std::vector<anim::JointEdit> edits{
      {.joint = 0, .scale = 1.7}, {.joint = 5, .scale = 0.6}, {.joint = 12, .scale = 1.4}};
  anim::apply_edits(pose, edits);
  mesh::Mesh still = model.meshes[0];
  still.skin = {};
  still.node = 3;
  model.meshes.push_back(still);
  expect_kernels_agree(model, pose);
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  const auto p = anim::make_palette(model.meshes[0], gv, gm, SkinningMode::versor);
  EXPECT_TRUE(p.motors.empty()) << "the scaled pose must exercise the 16-coefficient versor path";
  EXPECT_FALSE(anim::make_palette(model.meshes[0], gv, gm, SkinningMode::dqs).scales.empty());
}

TEST(SkinningKernels, AutomaticTakesTheBestThereAndAnAbsentKernelIsAnError) {
  EXPECT_TRUE(anim::kernel_available(SkinningKernel::automatic));
  EXPECT_TRUE(anim::kernel_available(SkinningKernel::scalar));
  EXPECT_TRUE(anim::kernel_available(SkinningKernel::vector));
  // AVX-512 code carries AVX2 and FMA: a processor with the first has the second.
  EXPECT_TRUE(!anim::kernel_available(SkinningKernel::avx512) || anim::kernel_available(SkinningKernel::avx2));
  const anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  const auto pose = anim::rest_pose(model.skeleton);
  const auto p = anim::make_palette(model.meshes[0], anim::global_versors(model.skeleton, pose),
                                    anim::global_matrices(model.skeleton, pose), SkinningMode::cga);
  for (SkinningKernel k : {SkinningKernel::avx2, SkinningKernel::avx512})
    if (!anim::kernel_available(k)) {
      mesh::RowMatrixXf<3> out;
      EXPECT_THROW(anim::skin_into(model.meshes[0], p, out, nullptr, {.kernel = k}), InvalidInputError);
    }
}

}  // namespace

namespace {

// Validate before Run (ozz's SkinningJob): a job that would read or write outside its arrays is
// an error naming the problem, in every kernel.
TEST(SkinningKernels, JobsOutsideTheirArraysAreRejected) {
  const anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  const anim::RiggedModel other = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const mesh::Mesh& m = model.meshes[0];
  const auto pose = anim::rest_pose(model.skeleton);
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  const auto p = anim::make_palette(m, gv, gm, SkinningMode::cga);
  const auto other_pose = anim::rest_pose(other.skeleton);
  const auto foreign = anim::make_palette(other.meshes[0], anim::global_versors(other.skeleton, other_pose),
                                          anim::global_matrices(other.skeleton, other_pose), SkinningMode::cga);
  const Eigen::Index n = m.vertex_count();
  for (SkinningKernel kernel : {SkinningKernel::scalar, SkinningKernel::vector}) {
    mesh::RowMatrixXf<3> out(n, 3), normals(n, 3), short_out(n - 1, 3);
    EXPECT_THROW(anim::skin_range(m, p, -1, 8, out, nullptr, kernel), InvalidInputError);
    EXPECT_THROW(anim::skin_range(m, p, 16, 8, out, nullptr, kernel), InvalidInputError);
    EXPECT_THROW(anim::skin_range(m, p, 0, n + 1, out, nullptr, kernel), InvalidInputError);
    EXPECT_THROW(anim::skin_range(m, p, 0, n, short_out, nullptr, kernel), InvalidInputError);
    EXPECT_THROW(anim::skin_range(m, p, 0, n, out, &short_out, kernel), InvalidInputError);
    EXPECT_THROW(anim::skin_range(m, foreign, 0, n, out, nullptr, kernel), InvalidInputError);
    EXPECT_NO_THROW(anim::skin_range(m, p, 0, n, out, &normals, kernel));
    // What a good job computes is unchanged by the checks.
    mesh::RowMatrixXf<3> ref;
    anim::skin_into(m, p, ref, nullptr, {.threads = 1, .kernel = SkinningKernel::scalar});
    EXPECT_LE((out - ref).cwiseAbs().maxCoeff(), 1e-4f);
  }
}

}  // namespace
