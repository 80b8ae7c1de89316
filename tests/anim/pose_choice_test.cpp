// choose_pose: the one set of rules by which every front end turns a clip, a time, a blend, edits
// and morph weights into a pose.

#include "cgamesh/anim/pose_choice.hpp"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "model_fixtures.hpp"

namespace {

using namespace cgamesh;

bool same(const anim::Pose& a, const anim::Pose& b) {
  if (a.local.size() != b.local.size()) return false;
  for (std::size_t j = 0; j < a.local.size(); ++j)
    if (a.local[j].matrix() != b.local[j].matrix()) return false;
  return true;
}

bool mentions(const std::vector<std::string>& warnings, const std::string& text) {
  for (const std::string& w : warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

class PoseChoice : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { model_ = new anim::RiggedModel(io::load_model(cgamesh_test::demo_model())); }
  static void TearDownTestSuite() { delete model_; }
  static const anim::RiggedModel& model() { return *model_; }
  static anim::RiggedModel* model_;
};
anim::RiggedModel* PoseChoice::model_ = nullptr;

TEST_F(PoseChoice, NothingAskedIsTheBindPose) {
  const anim::ChosenPose c = anim::choose_pose(model(), {});
  EXPECT_EQ(c.clip, -1);
  EXPECT_TRUE(c.warnings.empty());
  EXPECT_TRUE(same(c.pose, anim::rest_pose(model().skeleton)));
}

TEST_F(PoseChoice, ATimeAlonePicksTheFirstClip) {
  anim::PoseRequest r;
  r.time = 0.7;
  r.blend = anim::BlendMode::log;
  const anim::ChosenPose c = anim::choose_pose(model(), r);
  EXPECT_EQ(c.clip, 0);
  EXPECT_EQ(c.time, 0.7);
  EXPECT_TRUE(same(c.pose, anim::sample(model().skeleton, model().clips[0], 0.7, anim::BlendMode::log)));
  EXPECT_FALSE(same(c.pose, anim::rest_pose(model().skeleton)));
}

TEST_F(PoseChoice, AClipWithoutTimeIsSampledAtZeroAndEditsComeAfter) {
  anim::PoseRequest r;
  r.clip = 0;
  anim::JointEdit e;
  e.joint = 3;
  e.scale = 1.5;
  r.edits.push_back(e);
  const anim::ChosenPose c = anim::choose_pose(model(), r);
  anim::Pose expected = anim::sample(model().skeleton, model().clips[0], 0.0, anim::BlendMode::format);
  anim::apply_edits(expected, r.edits);
  EXPECT_EQ(c.time, 0.0);
  EXPECT_TRUE(same(c.pose, expected));
}

TEST_F(PoseChoice, PastTheEndWarnsAndUsesTheLastPose) {
  anim::PoseRequest r;
  r.clip = 0;
  r.time = model().clips[0].duration + 5;
  const anim::ChosenPose c = anim::choose_pose(model(), r);
  EXPECT_TRUE(mentions(c.warnings, "past the end of clip")) << ::testing::PrintToString(c.warnings);
  EXPECT_TRUE(same(c.pose, anim::sample(model().skeleton, model().clips[0], model().clips[0].duration,
                                        anim::BlendMode::format)));
  r.time = model().clips[0].duration;
  EXPECT_TRUE(anim::choose_pose(model(), r).warnings.empty());
}

TEST_F(PoseChoice, ATimeOnAModelWithoutClipsWarnsAndBinds) {
  anim::RiggedModel still = model();
  still.clips.clear();
  anim::PoseRequest r;
  r.time = 1;
  const anim::ChosenPose c = anim::choose_pose(still, r);
  EXPECT_EQ(c.clip, -1);
  EXPECT_TRUE(mentions(c.warnings, "no animation"));
}

TEST_F(PoseChoice, BadRequestsAreRefused) {
  anim::PoseRequest r;
  r.clip = static_cast<int>(model().clips.size());
  EXPECT_THROW((void)anim::choose_pose(model(), r), InvalidInputError);
  r.clip = -2;
  EXPECT_THROW((void)anim::choose_pose(model(), r), InvalidInputError);
  for (const double t : {-1.0, std::nan(""), static_cast<double>(INFINITY)}) {
    anim::PoseRequest bad;
    bad.time = t;
    EXPECT_THROW((void)anim::choose_pose(model(), bad), InvalidInputError) << t;
  }
  anim::PoseRequest morph;
  morph.morphs.push_back({"no such target", 1.0f});
  EXPECT_THROW((void)anim::choose_pose(model(), morph), InvalidInputError);
}

}  // namespace
