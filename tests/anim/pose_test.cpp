#include "cgamesh/anim/pose.hpp"
#include "cgamesh/errors.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "anim/model_fixtures.hpp"
#include "cgamesh/cga/convert.hpp"
#include "cgamesh/io/model_loader.hpp"

namespace {

using namespace cgamesh;
using anim::BlendMode;
using anim::Channel;
using anim::ChannelPath;
using anim::Interpolation;

/// One joint, one channel with keys at 0 and 1 (and 2).
struct OneJoint {
  anim::Skeleton skeleton;
  anim::Clip clip;
  OneJoint(ChannelPath path, Interpolation interp, std::vector<double> values, std::vector<double> times = {0, 1}) {
    anim::EditableSkeleton e;
    e.joints.push_back({"root", -1, {}});
    skeleton = anim::Skeleton::build(e);
    Channel c;
    c.joint = 0;
    c.path = path;
    c.interpolation = interp;
    c.times = std::move(times);
    c.values = std::move(values);
    clip.duration = c.times.back();
    clip.channels.push_back(std::move(c));
  }
  anim::Transform at(double t, BlendMode mode) const { return anim::sample(skeleton, clip, t, mode).local[0]; }
};

Eigen::Vector4d axis_angle(double x, double y, double z, double angle) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, Eigen::Vector3d(x, y, z).normalized()));
  return {q.x(), q.y(), q.z(), q.w()};
}

TEST(Pose, TranslationLerpsInEveryModeAndClamps) {
  const OneJoint j(ChannelPath::translation, Interpolation::linear, {0, 0, 0, 2, 4, -6});
  for (BlendMode m : {BlendMode::format, BlendMode::linear, BlendMode::log}) {
    EXPECT_TRUE(j.at(0.25, m).translation.isApprox(Eigen::Vector3d(0.5, 1, -1.5), 1e-12));
    EXPECT_TRUE(j.at(5.0, m).translation.isApprox(Eigen::Vector3d(2, 4, -6), 1e-12));
    EXPECT_TRUE(j.at(-1.0, m).translation.isZero());
  }
}

// The log blend of rotors is the slerp of the quaternions; the linear blend is nlerp: equal
// at the keys and the middle, different elsewhere.
TEST(Pose, RotationLogBlendIsSlerpAndLinearIsNlerp) {
  const Eigen::Vector4d a = axis_angle(0, 0, 1, 0.2), b = axis_angle(1, 2, 0.5, 2.4);
  std::vector<double> values(a.data(), a.data() + 4);
  values.insert(values.end(), b.data(), b.data() + 4);
  const OneJoint j(ChannelPath::rotation, Interpolation::linear, values);
  const Eigen::Quaterniond qa(a[3], a[0], a[1], a[2]), qb(b[3], b[0], b[1], b[2]);
  for (double t : {0.0, 0.1, 0.37, 0.5, 0.8, 1.0}) {
    const Eigen::Quaterniond slerp = qa.slerp(t, qb);
    EXPECT_LE(j.at(t, BlendMode::log).rotation.angularDistance(slerp), 1e-9) << t;
    EXPECT_LE(j.at(t, BlendMode::format).rotation.angularDistance(slerp), 1e-9) << t;
    const Eigen::Quaterniond nlerp(((1 - t) * qa.coeffs() + t * qb.coeffs()).normalized());
    EXPECT_LE(j.at(t, BlendMode::linear).rotation.angularDistance(nlerp), 1e-9) << t;
  }
  EXPECT_GT(j.at(0.2, BlendMode::linear).rotation.angularDistance(qa.slerp(0.2, qb)), 1e-4);
}

TEST(Pose, ScaleBlendModes) {
  const OneJoint j(ChannelPath::scale, Interpolation::linear, {1, 1, 1, 4, 4, 4});
  EXPECT_NEAR(j.at(0.5, BlendMode::format).scale.x(), 2.5, 1e-12);
  EXPECT_NEAR(j.at(0.5, BlendMode::log).scale.x(), 2.0, 1e-12);  // geometric: exp of a line in log s
  const double linear = j.at(0.5, BlendMode::linear).scale.x();
  EXPECT_GT(linear, 1.0);
  EXPECT_LT(linear, 4.0);
}

TEST(Pose, StepAndCubicSpline) {
  const OneJoint step(ChannelPath::translation, Interpolation::step, {1, 0, 0, 3, 0, 0});
  EXPECT_DOUBLE_EQ(step.at(0.99, BlendMode::format).translation.x(), 1.0);
  EXPECT_DOUBLE_EQ(step.at(1.0, BlendMode::format).translation.x(), 3.0);
  // in-tangent, value, out-tangent per key; zero tangents give smoothstep.
  const OneJoint cubic(ChannelPath::translation, Interpolation::cubic_spline,
                       {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0});
  EXPECT_NEAR(cubic.at(0.25, BlendMode::format).translation.x(), 3 * 0.0625 - 2 * 0.015625, 1e-12);
}

TEST(Pose, EditsComposeInTheJointFrame) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::asset("RiggedSimple.glb"));
  anim::Pose pose = anim::rest_pose(m.skeleton);
  const int j = m.skeleton.size() - 1;
  const anim::JointEdit e{.joint = j, .axis = Eigen::Vector3d::UnitZ(), .angle = std::numbers::pi / 2};
  anim::apply_edits(pose, std::span(&e, 1));
  const auto gv = anim::global_versors(m.skeleton, pose);
  const auto gm = anim::global_matrices(m.skeleton, pose);
  for (int k = 0; k < m.skeleton.size(); ++k)
    EXPECT_TRUE(cga::to_matrix(gv[k]).isApprox(gm[k], 1e-6)) << k;  // the file's float TRS
  const Eigen::Matrix4d before = anim::global_matrices(m.skeleton, anim::rest_pose(m.skeleton))[j];
  const Eigen::Matrix4d expected = before * Eigen::Affine3d(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ())).matrix();
  EXPECT_TRUE(gm[j].isApprox(expected, 1e-9));

  const anim::JointEdit bad_joint{.joint = 99};
  EXPECT_THROW(anim::apply_edits(pose, std::span(&bad_joint, 1)), InvalidInputError);
  const anim::JointEdit bad_scale{.joint = 0, .scale = -1};
  EXPECT_THROW(anim::apply_edits(pose, std::span(&bad_scale, 1)), InvalidInputError);
}

TEST(Pose, NanTimeThrows) {
  const OneJoint j(ChannelPath::translation, Interpolation::linear, {0, 0, 0, 1, 1, 1});
  EXPECT_THROW((void)anim::sample(j.skeleton, j.clip, std::nan(""), BlendMode::format), InvalidInputError);
}

TEST(Skeleton, BuildPutsParentsFirstAndRejectsCycles) {
  anim::EditableSkeleton e;
  e.joints.push_back({"child", 1, {}});
  e.joints.push_back({"root", -1, {}});
  std::vector<int> remap;
  const anim::Skeleton s = anim::Skeleton::build(e, &remap);
  EXPECT_EQ(remap, (std::vector<int>{1, 0}));
  EXPECT_EQ(s.parents()[1], 0);
  EXPECT_EQ(s.find("child"), 1);
  EXPECT_EQ(s.find("nobody"), -1);
  e.joints[1].parent = 0;  // child <-> root
  EXPECT_THROW((void)anim::Skeleton::build(e), InvalidInputError);
  e.joints[1].parent = 7;
  EXPECT_THROW((void)anim::Skeleton::build(e), InvalidInputError);
}

}  // namespace
