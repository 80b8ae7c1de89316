// Clips as long as the file says (issue #33, item 5): a clip's length is the one its file declares
// (Assimp's mDuration / mTicksPerSecond) when that is past its last key, as loaded and after a glTF
// round trip; a clip whose file gives no ticks per second is read at an assumed rate, said.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;
namespace fs = std::filesystem;
using cgamesh_test::TempDir;

double last_key(const anim::Clip& clip) {
  double last = 0;
  for (const anim::Channel& ch : clip.channels)
    if (!ch.times.empty()) last = std::max(last, ch.times.back());
  return last;
}

anim::RiggedModel round_trip(const anim::RiggedModel& model, const TempDir& dir) {
  (void)io::write_gltf(model, dir / "round_trip.glb");
  return io::load_model(dir / "round_trip.glb");
}

void expect_same_pose(const anim::RiggedModel& a, const anim::RiggedModel& b, std::size_t clip, double t) {
  const anim::Pose x = anim::sample(a.skeleton, a.clips[clip], t, anim::BlendMode::format);
  const anim::Pose y = anim::sample(b.skeleton, b.clips[clip], t, anim::BlendMode::format);
  for (int j = 0; j < a.skeleton.size(); ++j) {
    const int k = b.skeleton.find(a.skeleton.names()[static_cast<std::size_t>(j)]);
    ASSERT_GE(k, 0);
    const anim::Transform &p = x.local[static_cast<std::size_t>(j)], &q = y.local[static_cast<std::size_t>(k)];
    EXPECT_LT((p.translation - q.translation).norm(), 1e-4 * (1 + p.translation.norm())) << "t " << t << " joint " << j;
    EXPECT_LT(p.rotation.angularDistance(q.rotation), 1e-5) << "t " << t << " joint " << j;
  }
}

// RiggedSimple as an FBX (Assimp's exporter) whose AnimationStack declares 5 s while its keys end
// at 2.083 s, as the field's 3ds Max export declares 5 s over keys all at 0.
TEST(ClipDuration, FbxDeclaredLengthKeptAsLoadedAndThroughGltf) {
  TempDir dir;
  const anim::RiggedModel fbx = io::load_model(cgamesh_test::asset("rigged_simple_5s.fbx"));
  ASSERT_EQ(fbx.clips.size(), 1u);
  EXPECT_NEAR(last_key(fbx.clips[0]), 2.0833, 1e-3);
  EXPECT_NEAR(fbx.clips[0].duration, 5.0, 1e-9);
  const anim::RiggedModel back = round_trip(fbx, dir);
  ASSERT_EQ(back.clips.size(), 1u);
  EXPECT_NEAR(back.clips[0].duration, 5.0, 1e-6);
  for (const double t : {1.0, 2.5, 5.0}) expect_same_pose(fbx, back, 0, t);
}

// OGRE declares each animation's length; the ninja's are past their last keys (Attack2: keys to
// 1.0833 s, 1.1667 s long), and a loop of them must keep its rhythm.
TEST(ClipDuration, OgreLengthsKeptAsLoadedAndThroughGltf) {
  TempDir dir;
  const anim::RiggedModel ninja = io::load_model(cgamesh_test::asset("ogre_ninja/ninja.mesh"));
  ASSERT_EQ(ninja.clips.size(), 20u);
  const int attack2 = ninja.find_clip("Attack2");
  ASSERT_GE(attack2, 0);
  const auto a2 = static_cast<std::size_t>(attack2);
  EXPECT_NEAR(ninja.clips[a2].duration, 1.1667, 1e-4);
  EXPECT_NEAR(last_key(ninja.clips[a2]), 1.0833, 1e-4);
  const anim::RiggedModel back = round_trip(ninja, dir);
  ASSERT_EQ(back.clips.size(), ninja.clips.size());
  for (std::size_t c = 0; c < ninja.clips.size(); ++c) {
    EXPECT_EQ(back.clips[c].name, ninja.clips[c].name);
    EXPECT_NEAR(back.clips[c].duration, ninja.clips[c].duration, 1e-6) << ninja.clips[c].name;
  }
  EXPECT_NEAR(back.clips[a2].duration, 1.1667, 1e-4);
  for (const double t : {0.5, 1.1, 1.1667}) expect_same_pose(ninja, back, a2, t);
}

// A DirectX .x file without AnimTicksPerSecond: Assimp reports 0 ticks per second; the loader
// reads the keys at LoadOptions::default_ticks_per_second and says which rate it assumed.
TEST(ClipDuration, FileWithoutTicksPerSecondWarnsNamingTheAssumedRate) {
  TempDir dir;
  {
    std::ofstream x(dir / "no_rate.x");
    x << "xof 0303txt 0032\n"
         "Frame Root {\n"
         "  FrameTransformMatrix { 1.0,0.0,0.0,0.0, 0.0,1.0,0.0,0.0, 0.0,0.0,1.0,0.0, 0.0,0.0,0.0,1.0;; }\n"
         "  Mesh Tri { 3; 0.0;0.0;0.0;, 1.0;0.0;0.0;, 0.0;1.0;0.0;; 1; 3;0,1,2;; }\n"
         "}\n"
         "AnimationSet Move {\n"
         "  Animation { {Root}\n"
         "    AnimationKey { 2; 2; 0;3;0.0,0.0,0.0;;, 50;3;1.0,0.0,0.0;;; }\n"
         "  }\n"
         "}\n";
  }
  const anim::RiggedModel model = io::load_model(dir / "no_rate.x");
  ASSERT_EQ(model.clips.size(), 1u);
  EXPECT_NEAR(model.clips[0].duration, 2.0, 1e-12);  // 50 ticks at 25 per second
  EXPECT_TRUE(std::any_of(model.warnings.begin(), model.warnings.end(), [](const std::string& w) {
    return w.find("no ticks per second") != std::string::npos && w.find("'Move'") != std::string::npos &&
           w.find("25 ticks per second assumed") != std::string::npos;
  })) << ::testing::PrintToString(model.warnings);
  const anim::RiggedModel faster = io::load_model(dir / "no_rate.x", {.default_ticks_per_second = 50});
  EXPECT_NEAR(faster.clips.at(0).duration, 1.0, 1e-12);
  // A file that gives its rate is read at it, without the warning.
  const anim::RiggedModel rated = io::load_model(cgamesh_test::asset("rigged_simple_5s.fbx"));
  EXPECT_TRUE(std::none_of(rated.warnings.begin(), rated.warnings.end(),
                           [](const std::string& w) { return w.find("ticks per second") != std::string::npos; }));
}

}  // namespace
