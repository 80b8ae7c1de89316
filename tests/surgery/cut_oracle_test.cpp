// The pieces of a cut re-animate in an independent implementation: written as glTF, posed by
// three.js (tests/oracle/js/skin_reference.mjs), they match our eq. (17) skinning, and they pass
// the Khronos validator.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "anim/model_fixtures.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "support/js_oracles.hpp"
#include "support/temp_dir.hpp"
#include "surgery/surgery_checks.hpp"

namespace {

using namespace cgamesh;

TEST(CutOracle, PiecesOfAPosedCutAnimateInThreeJsAsInCgamesh) {
  if (!cgamesh_test::three_available() || !cgamesh_test::validator_available())
    GTEST_SKIP() << "node or tests/oracle/js/node_modules missing (run scripts/install-deps.sh)";
  const anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  const anim::Pose pose = anim::sample(model.skeleton, model.clips[0], 0.7, anim::BlendMode::format);
  const surgery::ModelCut c =
      surgery::cut(model, surgery::place(model, pose), cga::plane<double>({0.3, 1, 0.1}, 0.75), {.cap = true});
  cgamesh_test::TempDir dir;
  const std::vector<double> times{0.0, 0.5, 1.3};
  for (int p = 0; p < 2; ++p) {
    const std::filesystem::path file = dir.path() / ("piece" + std::to_string(p) + ".glb");
    (void)io::write_gltf(c.pieces[static_cast<std::size_t>(p)], file);
    std::string log;
    EXPECT_EQ(cgamesh_test::validate_gltf(file, log), 0) << log;
    const anim::RiggedModel piece = io::load_model(file);
    const nlohmann::json ref = cgamesh_test::three_reference(file, times);
    const double diag = ref["bbox_diagonal"].get<double>();
    ASSERT_EQ(ref["meshes"].size(), piece.meshes.size());
    const mesh::Mesh& m = piece.meshes[0];
    for (double t : times) {
      std::ostringstream key;
      key << t;
      const auto& posed = ref["meshes"][0]["posed"][key.str()];
      ASSERT_EQ(posed.size(), static_cast<std::size_t>(3 * m.vertex_count()));
      const cgamesh_test::Points ours = cgamesh_test::skinned(piece, m, t);
      double worst = 0;
      for (Eigen::Index i = 0; i < m.vertex_count(); ++i)
        worst = std::max(worst, (ours.row(i).transpose().cast<double>() -
                                 Eigen::Vector3d(posed[3 * i].get<double>(), posed[3 * i + 1].get<double>(),
                                                 posed[3 * i + 2].get<double>()))
                                    .norm());
      EXPECT_LE(worst, 1e-5 * diag) << "piece " << p << " t=" << t;
    }
  }
}

}  // namespace
