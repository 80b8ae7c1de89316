// Round trip: a model loaded by cgamesh, written as glTF (.glb, or .gltf + .bin) by write_gltf and
// loaded back must pose exactly like the original: for every clip, at several times, with CGA
// and matrix skinning, the world-space vertices of every mesh agree to 1e-5 of the bounding box
// diagonal, with the same vertex and face counts (no seam merged). Every written file must pass
// the Khronos glTF validator with no errors.

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <system_error>
#include <unistd.h>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "support/js_oracles.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace cgamesh;
using anim::SkinningMode;

using cgamesh_test::TempDir;

/// World-space posed vertices of every mesh.
std::vector<mesh::RowMatrixXf<3>> posed(const anim::RiggedModel& m, const anim::Pose& pose, SkinningMode mode) {
  const auto gv = anim::global_versors(m.skeleton, pose);
  const auto gm = anim::global_matrices(m.skeleton, pose);
  std::vector<mesh::RowMatrixXf<3>> out;
  for (const mesh::Mesh& mesh : m.meshes) out.push_back(anim::skin(mesh, anim::make_palette(mesh, gv, gm, mode), 1));
  return out;
}

/// Diagonal of the bounding box of all meshes.
double diagonal(const std::vector<mesh::RowMatrixXf<3>>& meshes) {
  Eigen::RowVector3f lo = Eigen::RowVector3f::Constant(std::numeric_limits<float>::infinity()), hi = -lo;
  for (const auto& m : meshes)
    if (m.rows() > 0) {
      lo = lo.cwiseMin(m.colwise().minCoeff());
      hi = hi.cwiseMax(m.colwise().maxCoeff());
    }
  return static_cast<double>((hi - lo).norm());
}

struct Deviation {
  double relative = 0;   ///< largest vertex distance / bounding box diagonal of `a`'s pose
  std::size_t mesh = 0;  ///< where it is
};

/// How far `b` in `pose_b` is from `a` in `pose_a`, mesh by mesh (meshes and vertices matched in
/// order; the vertex counts must agree).
Deviation deviation(const anim::RiggedModel& a, const anim::Pose& pose_a, const anim::RiggedModel& b,
                    const anim::Pose& pose_b, SkinningMode mode) {
  const auto pa = posed(a, pose_a, mode), pb = posed(b, pose_b, mode);
  const double diag = diagonal(pa);
  EXPECT_GT(diag, 0);
  Deviation d;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    EXPECT_EQ(pa[i].rows(), pb[i].rows());
    if (pa[i].rows() != pb[i].rows()) return {std::numeric_limits<double>::infinity(), i};
    const double worst = pa[i].rows() == 0 ? 0.0 : static_cast<double>((pa[i] - pb[i]).rowwise().norm().maxCoeff());
    if (worst / diag > d.relative) d = {worst / diag, i};
  }
  return d;
}

/// Checks that `b` poses like `a`, with CGA and with matrix skinning.
void expect_same_positions(const anim::RiggedModel& a, const anim::Pose& pose_a, const anim::RiggedModel& b,
                           const anim::Pose& pose_b, const std::string& what) {
  for (SkinningMode mode : {SkinningMode::cga, SkinningMode::matrix}) {
    const Deviation d = deviation(a, pose_a, b, pose_b, mode);
    EXPECT_LE(d.relative, 1e-5) << what << ", mesh " << d.mesh << " ('" << a.meshes[d.mesh].name << "'), "
                                << (mode == SkinningMode::cga ? "cga" : "matrix")
                                << " skinning: largest distance / bounding box diagonal";
  }
}

void expect_round_trip(const anim::RiggedModel& a, const anim::RiggedModel& b) {
  // Meshes in order, nothing merged or dropped.
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (std::size_t i = 0; i < a.meshes.size(); ++i) {
    SCOPED_TRACE("mesh " + std::to_string(i) + " ('" + a.meshes[i].name + "')");
    ASSERT_EQ(a.meshes[i].vertex_count(), b.meshes[i].vertex_count());
    ASSERT_EQ(a.meshes[i].face_count(), b.meshes[i].face_count());
    EXPECT_TRUE(a.meshes[i].faces == b.meshes[i].faces) << "faces differ";
    EXPECT_EQ(a.meshes[i].skin.empty(), b.meshes[i].skin.empty());
    EXPECT_EQ(a.meshes[i].normals.rows(), b.meshes[i].normals.rows());
    EXPECT_EQ(a.meshes[i].uvs.rows(), b.meshes[i].uvs.rows());
    if (a.meshes[i].uvs.rows() == b.meshes[i].uvs.rows()) {
      EXPECT_TRUE(a.meshes[i].uvs.isApprox(b.meshes[i].uvs, 1e-6f)) << "texture coordinates differ";
    }
    // The material: base colour factor and the texture's bytes as the file had them.
    const int ma = a.meshes[i].material, mb = b.meshes[i].material;
    if (ma < 0) continue;
    ASSERT_GE(mb, 0) << "the material is lost";
    const mesh::Material &fa = a.materials[static_cast<std::size_t>(ma)],
                         &fb = b.materials[static_cast<std::size_t>(mb)];
    EXPECT_TRUE(fa.base_color.isApprox(fb.base_color, 1e-6f))
        << fa.base_color.transpose() << " vs " << fb.base_color.transpose();
    EXPECT_EQ(fa.base_color_texture >= 0, fb.base_color_texture >= 0);
    if (fa.base_color_texture >= 0 && fb.base_color_texture >= 0) {
      EXPECT_EQ(*a.textures[static_cast<std::size_t>(fa.base_color_texture)].bytes,
                *b.textures[static_cast<std::size_t>(fb.base_color_texture)].bytes);
    }
  }
  expect_same_positions(a, anim::rest_pose(a.skeleton), b, anim::rest_pose(b.skeleton), "rest pose");

  // The writer drops clips without keys; the others keep their order and names.
  std::vector<const anim::Clip*> written;
  for (const anim::Clip& c : a.clips)
    if (std::any_of(c.channels.begin(), c.channels.end(), [](const anim::Channel& ch) { return !ch.times.empty(); }))
      written.push_back(&c);
  ASSERT_EQ(b.clips.size(), written.size());
  for (std::size_t k = 0; k < written.size(); ++k) {
    const anim::Clip& ca = *written[k];
    const int index = b.clips[k].name == ca.name ? static_cast<int>(k) : b.find_clip(ca.name);
    ASSERT_GE(index, 0) << "clip '" << ca.name << "' is missing after the round trip";
    const anim::Clip& cb = b.clips[static_cast<std::size_t>(index)];
    EXPECT_NEAR(cb.duration, ca.duration, 1e-6 * std::max(1.0, ca.duration)) << ca.name;
    for (double t : {0.0, 0.3, 0.77, ca.duration}) {
      const anim::Pose pa = anim::sample(a.skeleton, ca, t, anim::BlendMode::format);
      const anim::Pose pb = anim::sample(b.skeleton, cb, t, anim::BlendMode::format);
      expect_same_positions(a, pa, b, pb, "clip '" + ca.name + "' at t=" + std::to_string(t));
    }
  }
}

/// Load, write as .glb and as .gltf + .bin, load again, compare.
void check_round_trip(const fs::path& path, bool optional) {
  if (optional && !fs::exists(path)) GTEST_SKIP() << path << " is not installed (assimp-testmodels)";
  const anim::RiggedModel original = io::load_model(path);
  ASSERT_FALSE(original.meshes.empty());
  TempDir dir;
  // A space in the .gltf name: its buffer goes to "round_trip.bin".
  for (const char* name : {"round_trip.glb", "round trip.gltf"}) {
    SCOPED_TRACE(path.string() + " -> " + name);
    const fs::path out = dir.path() / name;
    (void)io::write_gltf(original, out);
    ASSERT_TRUE(fs::exists(out));
    if (out.extension() == ".gltf") {
      ASSERT_TRUE(fs::exists(dir.path() / "round_trip.bin"));
    }
    const anim::RiggedModel reloaded = io::load_model(out);
    expect_round_trip(original, reloaded);
  }
}

/// The .glb and the .gltf (+ .bin) written for `path` pass the Khronos validator.
void check_validator(const fs::path& path, bool optional) {
  if (optional && !fs::exists(path)) GTEST_SKIP() << path << " is not installed (assimp-testmodels)";
  if (!cgamesh_test::validator_available())
    GTEST_SKIP() << "node or tests/oracle/js/node_modules is missing (npm ci there)";
  const anim::RiggedModel original = io::load_model(path);
  TempDir dir;
  for (const char* name : {"model.glb", "model.gltf"}) {
    const fs::path out = dir.path() / name;
    (void)io::write_gltf(original, out);
    std::string log;
    const int status = cgamesh_test::validate_gltf(out, log);
    EXPECT_EQ(status, 0) << path << " -> " << name << ":\n" << log;
    EXPECT_NE(log.find(" 0 error(s)"), std::string::npos) << path << " -> " << name << ":\n" << log;
  }
}

/// One round-trip test and one validator test per model.
#define CGAMESH_ROUND_TRIP_TESTS(name, path, optional)        \
  TEST(RoundTrip, name) { check_round_trip(path, optional); } \
  TEST(RoundTripValidator, name) { check_validator(path, optional); }

CGAMESH_ROUND_TRIP_TESTS(RiggedSimple, cgamesh_test::asset("RiggedSimple.glb"), false)
CGAMESH_ROUND_TRIP_TESTS(RiggedFigure, cgamesh_test::asset("RiggedFigure.glb"), false)
CGAMESH_ROUND_TRIP_TESTS(CesiumMan, cgamesh_test::demo_model(), false)
// From Debian's assimp-testmodels, skipped when not installed.
CGAMESH_ROUND_TRIP_TESTS(BcnEpilepticX, cgamesh_test::assimp_model("X/BCN_Epileptic.X"), true)
CGAMESH_ROUND_TRIP_TESTS(TestwusonX, cgamesh_test::assimp_model("X/Testwuson.X"), true)
// Non-uniform scales in nodes and inverse binds, 6 influences per vertex.
CGAMESH_ROUND_TRIP_TESTS(AnimationWithSkeletonFbx, cgamesh_test::assimp_model("FBX/animation_with_skeleton.fbx"), true)
// Static meshes hanging from nodes (the writer must keep their order): with node animation, on
// nodes that have children, several meshes on one node.
CGAMESH_ROUND_TRIP_TESTS(StaticMeshesDae,
                         cgamesh_test::assimp_model("Collada/anims_with_full_rotations_between_keys.DAE"), true)
CGAMESH_ROUND_TRIP_TESTS(StaticMeshesFbx, cgamesh_test::assimp_model("FBX/cubes_with_names.fbx"), true)
CGAMESH_ROUND_TRIP_TESTS(CesiumMilkTruck, cgamesh_test::assimp_model("glTF/CesiumMilkTruck/CesiumMilkTruck.gltf"), true)

#undef CGAMESH_ROUND_TRIP_TESTS

// Read-write cycles keep the node tree: no synthetic root, no node per mesh added each time.
TEST(RoundTripHierarchy, CyclesKeepNodeCountNamesParentsAndTransforms) {
  TempDir dir;
  for (const fs::path& source : {cgamesh_test::demo_model(), cgamesh_test::asset("RiggedFigure.glb")}) {
    SCOPED_TRACE(source.string());
    const anim::RiggedModel first = io::load_model(source);
    anim::RiggedModel model = first;
    std::vector<std::string> names;
    for (int cycle = 0; cycle < 3; ++cycle) {
      const fs::path out = dir.path() / ("cycle" + std::to_string(cycle) + ".glb");
      (void)io::write_gltf(model, out);
      model = io::load_model(out);
      const anim::Skeleton &a = first.skeleton, &b = model.skeleton;
      ASSERT_EQ(b.size(), a.size()) << "cycle " << cycle;
      for (int j = 0; j < a.size(); ++j) {
        EXPECT_EQ(b.parents()[j], a.parents()[j]) << j;
        const anim::Transform &ta = a.rest()[j], &tb = b.rest()[j];
        EXPECT_LE((ta.translation - tb.translation).norm(), 1e-6) << j;
        EXPECT_LE(ta.rotation.angularDistance(tb.rotation), 1e-6) << j;
        EXPECT_LE((ta.scale - tb.scale).norm(), 1e-6) << j;
      }
      // Names: as the first cycle gave them (unnamed nodes are named once, by their index).
      if (cycle == 0) names.assign(b.names().begin(), b.names().end());
      for (int j = 0; j < a.size(); ++j) EXPECT_EQ(b.names()[j], names[static_cast<std::size_t>(j)]) << j;
      ASSERT_EQ(model.meshes.size(), first.meshes.size());
      for (std::size_t i = 0; i < first.meshes.size(); ++i) EXPECT_EQ(model.meshes[i].node, first.meshes[i].node);
    }
  }
}

// The comparison above is not blind: a tenth of a degree on one key, or a time 10 ms off, is seen.
TEST(RoundTripComparison, SeesSmallDifferences) {
  const anim::RiggedModel a = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  ASSERT_FALSE(a.clips.empty());
  anim::RiggedModel b = a;
  anim::Channel* rotation = nullptr;
  for (anim::Channel& ch : b.clips[0].channels)
    if (ch.path == anim::ChannelPath::rotation && ch.times.size() > 1) rotation = &ch;
  ASSERT_NE(rotation, nullptr);
  const double t = rotation->times[1];
  // Rotate key 1 by 0.1 degree about x.
  Eigen::Quaterniond q(rotation->values[7], rotation->values[4], rotation->values[5], rotation->values[6]);
  q = q * Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()));
  rotation->values[4] = q.x();
  rotation->values[5] = q.y();
  rotation->values[6] = q.z();
  rotation->values[7] = q.w();
  for (SkinningMode mode : {SkinningMode::cga, SkinningMode::matrix}) {
    const auto pa = anim::sample(a.skeleton, a.clips[0], t, anim::BlendMode::format);
    EXPECT_LE(deviation(a, pa, a, pa, mode).relative, 0.0);
    EXPECT_GT(deviation(a, pa, b, anim::sample(b.skeleton, b.clips[0], t, anim::BlendMode::format), mode).relative,
              1e-5);
    EXPECT_GT(
        deviation(a, pa, a, anim::sample(a.skeleton, a.clips[0], t + 0.01, anim::BlendMode::format), mode).relative,
        1e-5);
  }
}

}  // namespace
