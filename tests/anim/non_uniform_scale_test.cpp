// Rigs that are not made of similarities (non-uniform scale keys, rest scale and inverse binds,
// the shear they make below them): cga takes the exact matrix of every joint map no versor
// holds, so it equals matrix skinning and three.js; versor and dqs approximate, and a posed
// frame says by how much.
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/surgery/placement.hpp"

#include "anim/model_fixtures.hpp"
#include "support/js_oracles.hpp"
#include "support/non_uniform_rig.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;
using anim::SkinningMode;
using Points = mesh::RowMatrixXf<3>;

const std::vector<double> kTimes{0.0, 0.4, 0.9, 1.7};

double max_distance(const Points& a, const Points& b) {
  double worst = 0;
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    worst = std::max(worst, static_cast<double>((a.row(i) - b.row(i)).norm()));
  return worst;
}

double diagonal(const Points& p) {
  return static_cast<double>((p.colwise().maxCoeff() - p.colwise().minCoeff()).norm());
}

Points skinned(const anim::RiggedModel& model, const anim::Pose& pose, SkinningMode mode) {
  return io::posed_positions(model, pose, mode)[0];
}

struct NonUniformRig : ::testing::Test {
  cgamesh_test::TempDir dir;
  std::filesystem::path path = cgamesh_test::non_uniform_simple(dir.path());
  anim::RiggedModel model = io::load_model(path);

  [[nodiscard]] anim::Pose at(double t) const {
    return anim::sample(model.skeleton, model.clips[0], t, anim::BlendMode::format);
  }
  [[nodiscard]] bool similar(const anim::Pose& pose) const {
    return anim::maps_by_similarities(model.meshes[0], anim::global_matrices(model.skeleton, pose));
  }
};

TEST_F(NonUniformRig, TheRigIsNotMadeOfSimilaritiesAndTheLoaderSaysSo) {
  for (const double t : kTimes) EXPECT_FALSE(similar(at(t))) << t;
  EXPECT_FALSE(similar(anim::rest_pose(model.skeleton)));
  int said = 0;
  for (const std::string& w : model.warnings)
    said += w.find("cga and matrix skinning keep it exactly, versor and dqs approximate it") != std::string::npos;
  EXPECT_GE(said, 3) << "rest scale, inverse bind and clip keys";
  const anim::RiggedModel shipped = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const anim::Pose pose = anim::sample(shipped.skeleton, shipped.clips[0], 0.9, anim::BlendMode::format);
  EXPECT_TRUE(anim::maps_by_similarities(shipped.meshes[0], anim::global_matrices(shipped.skeleton, pose)));
}

// cga equals matrix skinning to float rounding, in the clip and at rest, positions and normals.
TEST_F(NonUniformRig, CgaSkinningIsExact) {
  std::vector<anim::Pose> poses{anim::rest_pose(model.skeleton)};
  for (const double t : kTimes) poses.push_back(at(t));
  for (const anim::Pose& pose : poses) {
    const io::PosedFrame cga = io::posed_frame(model, pose, SkinningMode::cga);
    const io::PosedFrame matrix = io::posed_frame(model, pose, SkinningMode::matrix);
    const double diag = diagonal(matrix.positions[0]);
    EXPECT_LE(max_distance(cga.positions[0], matrix.positions[0]), 1e-6 * diag);
    EXPECT_LE(max_distance(cga.normals[0], matrix.normals[0]), 1e-5);
    EXPECT_TRUE(cga.warnings.empty());
    EXPECT_EQ(cga.displacement, 0.0);
  }
}

// The independent oracle: three.js poses the edited file as cgamesh's cga and matrix modes do.
TEST_F(NonUniformRig, CgaAndMatrixSkinningMatchThreeJs) {
  if (!cgamesh_test::three_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules missing";
  const nlohmann::json ref = cgamesh_test::three_reference(path, kTimes);
  const double diag = ref["bbox_diagonal"].get<double>();
  for (const double t : kTimes) {
    std::ostringstream key;
    key << t;
    const auto& posed = ref["meshes"][0]["posed"][key.str()];
    ASSERT_EQ(posed.size(), static_cast<std::size_t>(3 * model.meshes[0].vertex_count()));
    Points theirs(model.meshes[0].vertex_count(), 3);
    for (Eigen::Index i = 0; i < theirs.rows(); ++i)
      for (int c = 0; c < 3; ++c) theirs(i, c) = posed[static_cast<std::size_t>(3 * i + c)].get<float>();
    for (const SkinningMode mode : {SkinningMode::cga, SkinningMode::matrix})
      EXPECT_LE(max_distance(skinned(model, at(t), mode), theirs), 1e-6 * diag)
          << "t=" << t << " " << io::skinning_name(mode);
  }
}

// versor and dqs cannot hold these maps: the posed frame reports the largest distance to the
// exact skinning, which is the measured one, and says it in a warning.
TEST_F(NonUniformRig, VersorAndDqsReportHowFarTheyAreFromTheExactSkinning) {
  for (const double t : {0.4, 1.7})
    for (const SkinningMode mode : {SkinningMode::versor, SkinningMode::dqs}) {
      SCOPED_TRACE(io::skinning_name(mode) + " t=" + std::to_string(t));
      const io::PosedFrame frame = io::posed_frame(model, at(t), mode);
      const Points exact = skinned(model, at(t), SkinningMode::matrix);
      const double measured = max_distance(frame.positions[0], exact);
      EXPECT_GT(measured, 1e-4 * diagonal(exact)) << "the rig is far from similarities";
      EXPECT_NEAR(frame.displacement, measured, 1e-9 * diagonal(exact));
      ASSERT_EQ(frame.warnings.size(), 1u);
      const std::string& w = frame.warnings[0];
      EXPECT_EQ(w.rfind(io::skinning_name(mode) + " skinning approximates", 0), 0u) << w;
      const std::size_t at_number = w.find("up to ");
      ASSERT_NE(at_number, std::string::npos) << w;
      EXPECT_NEAR(std::stod(w.substr(at_number + 6)), measured, 1e-5 * measured) << w;
    }
}

// On a similarity rig nothing is approximated, whatever the mode.
TEST(NonUniformScale, SimilarityRigsReportNoDisplacement) {
  const anim::RiggedModel model = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const anim::Pose pose = anim::sample(model.skeleton, model.clips[0], 0.9, anim::BlendMode::format);
  for (const SkinningMode mode : {SkinningMode::cga, SkinningMode::versor, SkinningMode::matrix, SkinningMode::dqs}) {
    const io::PosedFrame frame = io::posed_frame(model, pose, mode);
    EXPECT_EQ(frame.displacement, 0.0) << io::skinning_name(mode);
    EXPECT_TRUE(frame.warnings.empty()) << io::skinning_name(mode);
  }
}

// Surgery places the mesh with its cga palettes: on this rig that is matrix skinning.
TEST_F(NonUniformRig, SurgeryPlacementIsTheExactSkinning) {
  for (const double t : {0.4, 1.7}) {
    const surgery::Placement placement = surgery::place(model, at(t));
    const Points exact = skinned(model, at(t), SkinningMode::matrix);
    EXPECT_LE(max_distance(placement.positions[0], exact), 1e-6 * diagonal(exact)) << t;
  }
}

// A joint under a non-uniform parent whose own scale undoes the stretch has a similarity for its
// global map: its versor is that map exactly (composing the geometric means misplaces it).
TEST(NonUniformScale, GlobalVersorBelowACounterScaledParentIsExact) {
  anim::EditableSkeleton e;
  e.joints.push_back({"parent", -1, {.scale = Eigen::Vector3d(2, 1, 0.5)}});
  e.joints.push_back({"child",
                      0,
                      {.translation = Eigen::Vector3d(1, 2, 3),
                       .rotation = Eigen::Quaterniond::Identity(),
                       .scale = Eigen::Vector3d(0.5, 1, 2)}});
  const anim::Skeleton skeleton = anim::Skeleton::build(e);
  const anim::Pose pose = anim::rest_pose(skeleton);
  const Eigen::Matrix4d exact = anim::global_matrices(skeleton, pose)[1];
  ASSERT_TRUE(anim::is_similarity(exact));
  const Eigen::Matrix4d ours = anim::Transform::from_versor(anim::global_versors(skeleton, pose)[1]).matrix();
  EXPECT_TRUE(ours.isApprox(exact, 1e-12)) << ours << "\n\n" << exact;
}

}  // namespace
