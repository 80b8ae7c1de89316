// Morph targets (blend shapes) before skinning, against three.js (GLTFLoader, AnimationMixer,
// getVertexPosition: morph, then skin), through loading, sampling, writing and welding.
#include "cgamesh/anim/morph.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/mesh/weld.hpp"

#include "anim/model_fixtures.hpp"
#include "support/gltf_edit.hpp"
#include "support/js_oracles.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;
namespace fs = std::filesystem;
using anim::SkinningMode;

anim::Pose pose_at(const anim::RiggedModel& model, double t) {
  return model.clips.empty() ? anim::rest_pose(model.skeleton)
                             : anim::sample(model.skeleton, model.clips[0], t, anim::BlendMode::format);
}

/// The largest distance between `model` posed by cgamesh (`mode`) and `file` posed by three.js,
/// over every vertex and time, in diagonals of three.js' box (clip 0; the rest pose without one).
double worst_against_three(const anim::RiggedModel& model, const fs::path& file, const std::vector<double>& times,
                           SkinningMode mode) {
  const nlohmann::json ref = cgamesh_test::three_reference(file, times);
  EXPECT_EQ(ref["meshes"].size(), model.meshes.size());
  const double diag = ref["bbox_diagonal"].get<double>();
  double worst = 0;
  for (const double t : times) {
    const auto ours = io::posed_positions(model, pose_at(model, t), mode);
    std::ostringstream key;
    key << t;
    for (std::size_t k = 0; k < model.meshes.size() && k < ref["meshes"].size(); ++k) {
      const auto& theirs = ref["meshes"][k]["posed"][key.str()];
      EXPECT_EQ(theirs.size(), static_cast<std::size_t>(3 * ours[k].rows()));
      for (Eigen::Index i = 0; i < ours[k].rows() && static_cast<std::size_t>(3 * i + 2) < theirs.size(); ++i)
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, std::abs(static_cast<double>(ours[k](i, c)) - theirs[3 * i + c].get<double>()));
    }
  }
  return worst / diag;
}

const fs::path kRig = cgamesh_test::asset("rigged_simple_morph.glb");
const std::vector<double> kTimes{0.0, 0.5, 1.3, 2.0};

TEST(MorphTargets, LoadedWithNamesDefaultWeightsAndTheirChannel) {
  const anim::RiggedModel model = io::load_model(kRig);
  const mesh::Mesh& m = model.meshes[0];
  ASSERT_EQ(m.morph_targets.size(), 2u);
  EXPECT_EQ(m.morph_targets[0].name, "bulge");
  EXPECT_EQ(m.morph_targets[1].name, "tip");
  EXPECT_EQ(m.morph_weights, (std::vector<float>{0.5f, 0.0f})) << "the node's weights override the mesh's";
  EXPECT_EQ(m.morph_targets[0].normals.rows(), 0);
  EXPECT_EQ(m.morph_targets[1].normals.rows(), m.vertex_count());
  // The sparse target: only the upper half moves.
  const auto moved = (m.morph_targets[1].positions.array() != 0).rowwise().any().count();
  EXPECT_GT(moved, 0);
  EXPECT_LT(moved, m.vertex_count());
  ASSERT_EQ(model.clips.size(), 1u);
  const auto& channels = model.clips[0].channels;
  const auto weights = std::find_if(channels.begin(), channels.end(),
                                    [](const anim::Channel& c) { return c.path == anim::ChannelPath::weights; });
  ASSERT_NE(weights, channels.end());
  EXPECT_EQ(weights->weight_count, 2);
  EXPECT_EQ(weights->joint, m.node);
  // Halfway between the keys (0, 0) and (1, 0.5) at about 0.04 and 1.04 s.
  const anim::Pose p = anim::sample(model.skeleton, model.clips[0], 0.5 * (weights->times[0] + weights->times[1]),
                                    anim::BlendMode::format);
  const auto w = anim::morph_weights(p, m);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NEAR(w[0], 0.5, 1e-6);
  EXPECT_NEAR(w[1], 0.25, 1e-6);
}

TEST(MorphTargets, WeightChannelsInterpolateAsTheFileSays) {
  anim::RiggedModel model = io::load_model(kRig);
  anim::Clip clip{.name = "w", .duration = 2, .channels = {}};
  anim::Channel ch{.joint = model.meshes[0].node,
                   .path = anim::ChannelPath::weights,
                   .interpolation = anim::Interpolation::step,
                   .times = {0, 1},
                   .values = {0, 1, 1, 0},
                   .weight_count = 2};
  clip.channels = {ch};
  EXPECT_EQ(anim::sample(model.skeleton, clip, 0.75, anim::BlendMode::format).morph_weights[ch.joint],
            (std::vector<float>{0, 1}));
  clip.channels[0].interpolation = anim::Interpolation::linear;
  EXPECT_EQ(anim::sample(model.skeleton, clip, 0.75, anim::BlendMode::log).morph_weights[ch.joint],
            (std::vector<float>{0.75f, 0.25f}));
  // Cubic: in-tangent, value, out-tangent per key; zero tangents give the smoothstep.
  clip.channels[0].interpolation = anim::Interpolation::cubic_spline;
  clip.channels[0].values = {0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0};
  const auto w = anim::sample(model.skeleton, clip, 0.25, anim::BlendMode::format).morph_weights[ch.joint];
  EXPECT_NEAR(w[0], 3 * 0.0625 - 2 * 0.015625, 1e-6);
  EXPECT_NEAR(w[1], 1 - (3 * 0.0625 - 2 * 0.015625), 1e-6);
  clip.channels[0].weight_count = 3;  // 2 cubic keys of 3 weights hold 18 values, not 12
  EXPECT_THROW((void)anim::sample(model.skeleton, clip, 0.25, anim::BlendMode::format), InvalidInputError);
}

TEST(MorphTargets, SkinnedRigWithAnimatedWeightsPosesAsThreeJs) {
  if (!cgamesh_test::three_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules missing";
  const anim::RiggedModel model = io::load_model(kRig);
  for (const SkinningMode mode : {SkinningMode::cga, SkinningMode::matrix})
    EXPECT_LE(worst_against_three(model, kRig, kTimes, mode), 1e-6) << static_cast<int>(mode);
  // The same rig without its targets is far off: the comparison sees them.
  anim::RiggedModel bare = model;
  bare.meshes[0].morph_targets.clear();
  bare.meshes[0].morph_weights.clear();
  EXPECT_GT(worst_against_three(bare, kRig, kTimes, SkinningMode::cga), 1e-2);
}

TEST(MorphTargets, StaticMeshWithAnimatedWeightsPosesAsThreeJs) {
  const fs::path cube =
      cgamesh_test::assimp_model("glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
  if (!cgamesh_test::three_available() || !fs::exists(cube)) GTEST_SKIP() << "three.js or AnimatedMorphCube missing";
  const anim::RiggedModel model = io::load_model(cube);
  EXPECT_LE(worst_against_three(model, cube, {0.0, 0.7, 1.9, 3.3}, SkinningMode::cga), 1e-6);
}

// Its first target leaves every normal as it is: written, that target's normals hold no data,
// which Assimp refused to read back ("data is null when extracting data from accessors[3]").
TEST(MorphTargets, ATargetThatMovesNothingIsWrittenSoThatItReadsBack) {
  const fs::path cube =
      cgamesh_test::assimp_model("glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
  if (!fs::exists(cube)) GTEST_SKIP() << "AnimatedMorphCube missing";
  const anim::RiggedModel model = io::load_model(cube);
  ASSERT_EQ(model.meshes[0].morph_targets.size(), 2u);
  ASSERT_TRUE((model.meshes[0].morph_targets[0].normals.array() == 0).all());
  cgamesh_test::TempDir dir;
  const fs::path out = dir.path() / "cube.glb";
  (void)io::write_gltf(model, out);
  if (cgamesh_test::validator_available()) {
    std::string log;
    EXPECT_EQ(cgamesh_test::validate_gltf(out, log), 0) << log;
  }
  const anim::RiggedModel again = io::load_model(out);
  ASSERT_EQ(again.meshes[0].morph_targets.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(again.meshes[0].morph_targets[k].positions, model.meshes[0].morph_targets[k].positions);
    EXPECT_EQ(again.meshes[0].morph_targets[k].normals, model.meshes[0].morph_targets[k].normals);
  }
}

TEST(MorphTargets, WrittenGltfKeepsTargetsSparseWeightsAndTheirChannel) {
  const anim::RiggedModel model = io::load_model(kRig);
  cgamesh_test::TempDir dir;
  const fs::path out = dir.path() / "morph.glb";
  (void)io::write_gltf(model, out);
  if (cgamesh_test::validator_available()) {
    std::string log;
    EXPECT_EQ(cgamesh_test::validate_gltf(out, log), 0) << log;
  }
  const anim::RiggedModel again = io::load_model(out);
  const mesh::Mesh &a = model.meshes[0], &b = again.meshes[0];
  ASSERT_EQ(b.morph_targets.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(b.morph_targets[k].name, a.morph_targets[k].name);
    EXPECT_EQ(b.morph_targets[k].positions, a.morph_targets[k].positions);
    EXPECT_EQ(b.morph_targets[k].normals, a.morph_targets[k].normals);
  }
  EXPECT_EQ(b.morph_weights, a.morph_weights);
  if (cgamesh_test::three_available()) {
    EXPECT_LE(worst_against_three(again, out, kTimes, SkinningMode::cga), 1e-6);
  }
  // Sparse where few vertices move (the tip), dense where all do (the bulge).
  const tinygltf::Model gltf = cgamesh_test::read_glb(out);
  const auto& targets = gltf.meshes[0].primitives[0].targets;
  const auto sparse = [&](int accessor) { return gltf.accessors[static_cast<std::size_t>(accessor)].sparse.isSparse; };
  EXPECT_FALSE(sparse(targets[0].at("POSITION")));
  EXPECT_TRUE(sparse(targets[1].at("POSITION")));
  EXPECT_TRUE(sparse(targets[1].at("NORMAL")));
  const tinygltf::Value& names = gltf.meshes[0].extras.Get("targetNames");
  ASSERT_TRUE(names.IsArray());
  EXPECT_EQ(names.Get(1).Get<std::string>(), "tip");
}

// A real exporter's file (Assimp's glTF exporter, PlayCanvas' bitmoji): 82 sparse targets on a
// skinned head. Set a few weights, write, and three.js poses the written file as cgamesh does.
TEST(MorphTargets, SparseTargetsOfARealHeadPoseAsThreeJsOnceWritten) {
  anim::RiggedModel model = io::load_model(cgamesh_test::asset("bitmoji.glb"));
  mesh::Mesh& head = model.meshes[0];
  ASSERT_EQ(head.morph_targets.size(), 82u);
  for (const std::size_t k : {1u, 17u, 40u, 81u}) head.morph_weights[k] = 0.8f;
  cgamesh_test::TempDir dir;
  const fs::path out = dir.path() / "bitmoji.glb";
  (void)io::write_gltf(model, out);
  const tinygltf::Model gltf = cgamesh_test::read_glb(out);
  for (const auto& target : gltf.meshes[0].primitives[0].targets)
    EXPECT_TRUE(gltf.accessors[static_cast<std::size_t>(target.at("POSITION"))].sparse.isSparse)
        << "sparse as in the file";
  if (!cgamesh_test::three_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules missing";
  EXPECT_LE(worst_against_three(model, out, {0.0}, SkinningMode::cga), 1e-6);
  anim::RiggedModel still = model;
  std::fill(still.meshes[0].morph_weights.begin(), still.meshes[0].morph_weights.end(), 0.0f);
  EXPECT_GT(worst_against_three(still, out, {0.0}, SkinningMode::cga), 1e-3) << "the weights move the face";
}

TEST(MorphTargets, WeightsThatDoNotFitTheMeshAreRefused) {
  const anim::RiggedModel model = io::load_model(kRig);
  const std::vector<float> three{0, 0, 0}, nan{0, NAN}, two{0.5f, 0.5f};
  mesh::RowMatrixXf<3> p, n;
  const mesh::Mesh& m = model.meshes[0];
  EXPECT_THROW(anim::morph_rows(m, three, 0, m.vertex_count(), p, &n), InvalidInputError);
  EXPECT_THROW(anim::morph_rows(m, nan, 0, m.vertex_count(), p, &n), InvalidInputError);
  EXPECT_THROW(anim::morph_rows(m, two, 1, m.vertex_count() + 1, p, &n), InvalidInputError);
  EXPECT_THROW(anim::morph_rows(m, two, 2, 1, p, &n), InvalidInputError);
}

TEST(MorphTargets, AJobMorphsItsOwnRowsAsTheWholeMeshWould) {
  const anim::RiggedModel model = io::load_model(kRig);
  const mesh::Mesh& m = model.meshes[0];
  ASSERT_EQ(m.morph_targets.size(), 2u);
  const std::vector<float> weights{0.7f, -0.4f};
  mesh::RowMatrixXf<3> all_p, all_n, p, n;
  anim::morph_rows(m, weights, 0, m.vertex_count(), all_p, &all_n);
  EXPECT_GT((all_p - m.positions).cwiseAbs().maxCoeff(), 0.1f) << "the weights move the mesh";
  const Eigen::Index begin = m.vertex_count() / 3, end = m.vertex_count() - 2;
  anim::morph_rows(m, weights, begin, end, p, &n);
  ASSERT_EQ(p.rows(), end - begin);
  EXPECT_EQ(Eigen::MatrixXf(p), Eigen::MatrixXf(all_p.middleRows(begin, end - begin)));
  for (Eigen::Index v = begin; v < end; ++v)
    EXPECT_LE((Eigen::RowVector3f(p.row(v - begin) - m.positions.row(v)) - anim::morph_offset(m, weights, v).transpose())
                  .norm(),
              1e-6f);
  // Skinning in jobs of 13 vertices (a block of 8 and 5 single ones, each job morphing its own
  // rows) equals skinning the whole mesh at once.
  const anim::Pose pose = pose_at(model, 0.6);
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  const anim::SkinningPalette palette = anim::make_palette(m, gv, gm, SkinningMode::cga, weights);
  mesh::RowMatrixXf<3> whole, whole_n;
  anim::skin_into(m, palette, whole, &whole_n, {.threads = 1});
  mesh::RowMatrixXf<3> jobs(m.vertex_count(), 3), jobs_n(m.vertex_count(), 3);
  for (Eigen::Index b = 0; b < m.vertex_count(); b += 13)
    anim::skin_range(m, palette, b, std::min<Eigen::Index>(b + 13, m.vertex_count()), jobs, &jobs_n);
  EXPECT_LE((jobs - whole).cwiseAbs().maxCoeff(), 1e-6f);
  EXPECT_LE((jobs_n - whole_n).cwiseAbs().maxCoeff(), 1e-6f);
}

TEST(MorphTargets, VerticesThatMorphApartAreNotJoined) {
  mesh::Mesh m;
  m.positions.resize(6, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0;
  m.faces.resize(2, 3);
  m.faces << 0, 1, 2, 3, 4, 5;
  mesh::MorphTarget t{.name = "lift", .positions = mesh::RowMatrixXf<3>::Zero(6, 3), .normals = {}};
  t.positions(3, 2) = 1;  // the second triangle's first corner moves, the first's does not
  m.morph_targets.push_back(t);
  m.morph_weights = {1};
  EXPECT_EQ(mesh::join_identical_vertices(m), 2);
  ASSERT_EQ(m.vertex_count(), 4);
  EXPECT_EQ(m.morph_targets[0].positions.rows(), 4);
  EXPECT_NE(m.faces(0, 0), m.faces(1, 0));
  EXPECT_EQ(m.morph_targets[0].positions(m.faces(1, 0), 2), 1);
}

}  // namespace
