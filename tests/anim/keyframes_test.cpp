#include "cgamesh/anim/keyframes.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "anim/model_fixtures.hpp"
#include "cgamesh/cga/interpolation.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

namespace {

using namespace cgamesh;

anim::JointEdit bend(int joint, double degrees, double scale = 1) {
  return {.joint = joint, .axis = Eigen::Vector3d(1, 0, 0.5), .angle = degrees * std::numbers::pi / 180, .scale = scale};
}

// The generated clip replays the keyframes at their times, and in between holds the blend of
// the two keyframe versors (the paper's on-the-fly keyframes).
TEST(Keyframes, GeneratedClipReplaysKeysAndBlends) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const int j = m.skeleton.size() - 2;
  const std::vector<anim::Keyframe> keys{{0.0, {}}, {1.0, {bend(j, 80, 1.5)}}, {2.0, {bend(j, -40)}}};
  for (anim::BlendMode mode : {anim::BlendMode::linear, anim::BlendMode::log}) {
    const anim::Clip clip = anim::generate_clip(m.skeleton, keys, {.blend = mode, .fps = 10});
    EXPECT_EQ(clip.channels.size(), 3u);
    EXPECT_DOUBLE_EQ(clip.duration, 2.0);
    EXPECT_EQ(clip.channels[0].times.size(), 21u);
    std::vector<anim::Pose> key_poses;
    for (const auto& k : keys) {
      key_poses.push_back(anim::rest_pose(m.skeleton));
      anim::apply_edits(key_poses.back(), k.edits);
    }
    const auto versor_at = [&](double t) {
      return anim::sample(m.skeleton, clip, t, anim::BlendMode::format).local_versors[j];
    };
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(cga::max_abs(cga::Versor<double>(versor_at(keys[k].time) - key_poses[k].local_versors[j])), 1e-9);
    // A frame time between keys 0 and 1.
    const cga::Versor<double>& a = key_poses[0].local_versors[j];
    const cga::Versor<double>& b = key_poses[1].local_versors[j];
    const cga::Versor<double> expected =
        mode == anim::BlendMode::linear ? cga::lerp_normalized(a, b, 0.3) : cga::log_blend(a, b, 0.3);
    EXPECT_LE(cga::max_abs(cga::Versor<double>(versor_at(0.3) - expected)), 1e-9);
  }
}

TEST(Keyframes, BadInput) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  const std::vector<anim::Keyframe> one{{0.0, {bend(1, 10)}}};
  EXPECT_THROW((void)anim::generate_clip(m.skeleton, one), InvalidInputError);
  const std::vector<anim::Keyframe> backwards{{1.0, {}}, {0.5, {bend(1, 10)}}};
  EXPECT_THROW((void)anim::generate_clip(m.skeleton, backwards), InvalidInputError);
  const std::vector<anim::Keyframe> ok{{0.0, {}}, {1.0, {bend(1, 10)}}};
  EXPECT_THROW((void)anim::generate_clip(m.skeleton, ok, {.blend = anim::BlendMode::format}), InvalidInputError);
  EXPECT_THROW((void)anim::generate_clip(m.skeleton, ok, {.fps = 0}), InvalidInputError);
  const std::vector<anim::Keyframe> bad_joint{{0.0, {}}, {1.0, {bend(77, 10)}}};
  EXPECT_THROW((void)anim::generate_clip(m.skeleton, bad_joint), InvalidInputError);
}

}  // namespace
