// Skinning against an independent implementation: three.js SkinnedMesh (GLTFLoader,
// AnimationMixer.setTime, applyBoneTransform) run under node by tests/oracle/js/skin_reference.mjs.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "anim/model_fixtures.hpp"
#include "support/js_oracles.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/model_loader.hpp"

namespace {

using namespace cgamesh;
namespace fs = std::filesystem;

const std::vector<double> kTimes{0.0, 0.4, 0.9, 1.7};

TEST(ThreeJsOracle, CgaAndMatrixSkinningMatchThreeJs) {
  if (!cgamesh_test::three_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules missing (run scripts/install-deps.sh)";
  for (const fs::path& path : cgamesh_test::gltf_samples()) {
    SCOPED_TRACE(path.string());
    const nlohmann::json ref = cgamesh_test::three_reference(path, kTimes);
    const anim::RiggedModel model = io::load_model(path);
    ASSERT_EQ(ref["meshes"].size(), model.meshes.size());
    const double diag = ref["bbox_diagonal"].get<double>();
    for (std::size_t mi = 0; mi < model.meshes.size(); ++mi) {
      const mesh::Mesh& mesh = model.meshes[mi];
      const nlohmann::json& rm = ref["meshes"][mi];
      ASSERT_EQ(rm["vertex_count"].get<Eigen::Index>(), mesh.vertex_count());
      // Same vertex order: the rest positions agree exactly (no merging, no reordering).
      const auto& rest = rm["rest"];
      for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(mesh.positions(i, c), rest[3 * i + c].get<float>());
      for (double t : kTimes) {
        std::ostringstream key;
        key << t;
        const auto& posed = rm["posed"][key.str()];
        ASSERT_EQ(posed.size(), static_cast<std::size_t>(3 * mesh.vertex_count()));
        const anim::Pose pose = anim::sample(model.skeleton, model.clips[0], t, anim::BlendMode::format);
        const auto gv = anim::global_versors(model.skeleton, pose);
        const auto gm = anim::global_matrices(model.skeleton, pose);
        for (anim::SkinningMode mode : {anim::SkinningMode::cga, anim::SkinningMode::matrix}) {
          const auto ours = anim::skin(mesh, anim::make_palette(mesh, gv, gm, mode));
          double worst = 0;
          for (Eigen::Index i = 0; i < mesh.vertex_count(); ++i) {
            const Eigen::Vector3d theirs(posed[3 * i].get<double>(), posed[3 * i + 1].get<double>(),
                                         posed[3 * i + 2].get<double>());
            worst = std::max(worst, (ours.row(i).transpose().cast<double>() - theirs).norm());
          }
          EXPECT_LE(worst, 1e-5 * diag) << "t=" << t << " mode=" << static_cast<int>(mode);
        }
      }
    }
  }
}

}  // namespace
