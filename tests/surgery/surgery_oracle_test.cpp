// The results of surgery re-animate in an independent implementation: cut pieces, a torn and a
// drilled model, written as glTF and posed by three.js (tests/oracle/js/skin_reference.mjs),
// match our eq. (17) skinning, and they pass the Khronos validator.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "anim/model_fixtures.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/tear.hpp"
#include "support/js_oracles.hpp"
#include "support/temp_dir.hpp"
#include "surgery/surgery_checks.hpp"
#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;

/// Writes `model` as glTF, checks it with the Khronos validator, poses it with three.js at a
/// few times and compares with our eq. (17) skinning of the file as loaded back.
void expect_three_js_agrees(const anim::RiggedModel& model, const std::string& name) {
  cgamesh_test::TempDir dir;
  const std::vector<double> times{0.0, 0.5, 1.3};
  const std::filesystem::path file = dir.path() / (name + ".glb");
  (void)io::write_gltf(model, file);
  std::string log;
  EXPECT_EQ(cgamesh_test::validate_gltf(file, log), 0) << log;
  const anim::RiggedModel loaded = io::load_model(file);
  const nlohmann::json ref = cgamesh_test::three_reference(file, times);
  const double diag = ref["bbox_diagonal"].get<double>();
  // three.js makes a mesh of each primitive; the primitives of one glTF mesh (one per material:
  // a cap, a wall) share its vertices, which load_model reads as one mesh.
  std::vector<nlohmann::json> meshes;
  for (const auto& entry : ref["meshes"])
    if (!entry["primitive"].is_number() || entry["primitive"].get<int>() == 0) meshes.push_back(entry);
  ASSERT_EQ(meshes.size(), loaded.meshes.size());
  for (std::size_t k = 0; k < loaded.meshes.size(); ++k) {
    const mesh::Mesh& m = loaded.meshes[k];
    for (double t : times) {
      std::ostringstream key;
      key << t;
      const auto& posed = meshes[k]["posed"][key.str()];
      ASSERT_EQ(posed.size(), static_cast<std::size_t>(3 * m.vertex_count()));
      const cgamesh_test::Points ours = cgamesh_test::skinned(loaded, m, t);
      double worst = 0;
      for (Eigen::Index i = 0; i < m.vertex_count(); ++i)
        worst = std::max(worst, (ours.row(i).transpose().cast<double>() -
                                 Eigen::Vector3d(posed[3 * i].get<double>(), posed[3 * i + 1].get<double>(),
                                                 posed[3 * i + 2].get<double>()))
                                    .norm());
      EXPECT_LE(worst, 1e-5 * diag) << name << " mesh " << k << " t=" << t;
    }
  }
}

class SurgeryOracle : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!cgamesh_test::three_available() || !cgamesh_test::validator_available())
      GTEST_SKIP() << "node or tests/oracle/js/node_modules missing (run scripts/install-deps.sh)";
  }
  const anim::RiggedModel model_ = io::load_model(cgamesh_test::demo_model());
  const surgery::Placement placement_ =
      surgery::place(model_, anim::sample(model_.skeleton, model_.clips[0], 0.7, anim::BlendMode::format));
  [[nodiscard]] Eigen::Vector3d torso() const { return cgamesh_test::torso_centre(placement_.positions[0]); }
};

TEST_F(SurgeryOracle, PiecesOfAPosedCutAnimateInThreeJsAsInCgamesh) {
  const surgery::ModelCut c = surgery::cut(model_, placement_, cga::plane<double>({0.3, 1, 0.1}, 0.75), {.cap = true});
  expect_three_js_agrees(c.pieces[0], "piece0");
  expect_three_js_agrees(c.pieces[1], "piece1");
}

TEST_F(SurgeryOracle, AnOpenedTearAnimatesInThreeJsAsInCgamesh) {
  const Eigen::Vector3d c = torso(), z(0, 0, 0.5);
  const std::vector<surgery::Scalpel> steps{{c + z, c}, {c + Eigen::Vector3d(-0.015, 0.03, 0) + z, c},
                                            {c + Eigen::Vector3d(-0.03, 0.06, 0) + z, c + Eigen::Vector3d(-0.03, 0.06, 0)}};
  const surgery::ModelTear t = surgery::tear(model_, placement_, steps, {.open = 0.01});
  EXPECT_GT(t.new_vertices, 2);
  expect_three_js_agrees(t.model, "torn");
}

TEST_F(SurgeryOracle, AWalledDrillHoleAnimatesInThreeJsAsInCgamesh) {
  const Eigen::Vector3d c = torso(), z(0, 0, 0.5);
  const surgery::ModelDrill d = surgery::drill(model_, placement_, c - z, c + z, 0.04, {.wall = true});
  EXPECT_GT(d.intersection_points, 6);
  expect_three_js_agrees(d.model, "drilled");
}

}  // namespace
