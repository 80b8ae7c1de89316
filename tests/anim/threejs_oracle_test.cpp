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
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/model_loader.hpp"

namespace {

using namespace cgamesh;
namespace fs = std::filesystem;

const std::vector<double> kTimes{0.0, 0.4, 0.9, 1.7};

bool oracle_available() {
  return std::system("node --version > /dev/null 2>&1") == 0 &&
         fs::exists(fs::path(CGAMESH_JS_ORACLES) / "node_modules" / "three");
}

/// Runs three.js on `model` and returns its JSON. Weights are normalised, as cgamesh does on
/// load (the glTF sample models store some weight rows that do not sum to 1).
nlohmann::json three_reference(const fs::path& model) {
  const fs::path out = fs::temp_directory_path() / ("cgamesh_three_" + model.stem().string() + ".json");
  std::ostringstream times;
  for (std::size_t i = 0; i < kTimes.size(); ++i) times << (i ? "," : "") << kTimes[i];
  const std::string cmd = "node \"" + (fs::path(CGAMESH_JS_ORACLES) / "skin_reference.mjs").string() + "\" \"" +
                          model.string() + "\" \"" + out.string() + "\" --weights normalized --times " + times.str() +
                          " 2> /dev/null";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("three.js oracle failed: " + cmd);
  std::ifstream in(out);
  nlohmann::json j = nlohmann::json::parse(in);
  fs::remove(out);
  return j;
}

TEST(ThreeJsOracle, CgaAndMatrixSkinningMatchThreeJs) {
  if (!oracle_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules missing (run scripts/install-deps.sh)";
  for (const fs::path& path : cgamesh_test::gltf_samples()) {
    SCOPED_TRACE(path.string());
    const nlohmann::json ref = three_reference(path);
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
