#include "cgamesh/deform/fabrik.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/errors.hpp"

namespace {

using namespace cgamesh;  // NOLINT(google-build-using-namespace)
using Vec3 = Eigen::Vector3d;

std::vector<Vec3> chain() { return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(2.5, 0, 0), Vec3(3, 0, 0)}; }

void expect_bone_lengths_kept(const std::vector<Vec3>& rest, const std::vector<Vec3>& solved) {
  ASSERT_EQ(rest.size(), solved.size());
  for (std::size_t i = 0; i + 1 < rest.size(); ++i)
    EXPECT_NEAR((solved[i + 1] - solved[i]).norm(), (rest[i + 1] - rest[i]).norm(), 1e-9) << i;
  EXPECT_EQ(solved[0], rest[0]);
}

TEST(DeformFabrik, ReachesReachableTargets) {
  for (const Vec3& target : {Vec3(1.5, 1.5, 0.5), Vec3(0, 2, 0), Vec3(-1, 0, 0.5), Vec3(2.9, 0.1, 0)}) {
    const deform::FabrikResult r = deform::fabrik(chain(), target, {1e-8, 500});
    EXPECT_TRUE(r.reached) << target.transpose() << " distance " << r.distance;
    EXPECT_LE((r.joints.back() - target).norm(), 1e-8);
    expect_bone_lengths_kept(chain(), r.joints);
  }
}

TEST(DeformFabrik, ReportsUnreachableTargetsAndPointsAtThem) {
  const Vec3 target(0, 10, 0);
  const deform::FabrikResult r = deform::fabrik(chain(), target);
  EXPECT_FALSE(r.reached);
  EXPECT_NEAR(r.distance, 7.0, 1e-9);
  expect_bone_lengths_kept(chain(), r.joints);
  for (const Vec3& p : r.joints) EXPECT_NEAR(p.x(), 0.0, 1e-12);
}

// The motors carry each rest joint, and the next one along its bone, to the solved chain.
TEST(DeformFabrik, MotorsMapTheRestChainOntoTheSolvedOne) {
  const std::vector<Vec3> rest = chain();
  const deform::FabrikResult r = deform::fabrik(rest, Vec3(-2, 0.5, 0));  // folds bones past 90 degrees
  ASSERT_TRUE(r.reached);
  ASSERT_EQ(r.motors.size(), rest.size());
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const cga::PointMap<double> map(r.motors[i]);
    EXPECT_LT((map(rest[i]) - r.joints[i]).norm(), 1e-9) << i;
    if (i + 1 < rest.size()) {
      EXPECT_LT((map(rest[i + 1]) - r.joints[i + 1]).norm(), 1e-9) << i;
    }
  }
  // Folding the last bone straight back is a half turn: still a finite motor.
  const deform::FabrikResult back = deform::fabrik(std::vector<Vec3>{Vec3(0, 0, 0), Vec3(1, 0, 0)}, Vec3(-1, 0, 0));
  EXPECT_TRUE(back.reached);
  EXPECT_LT((cga::PointMap<double>(back.motors[0])(Vec3(1, 0, 0)) - Vec3(-1, 0, 0)).norm(), 1e-9);
}

TEST(DeformFabrik, RejectsBadChains) {
  EXPECT_THROW((void)deform::fabrik(std::vector<Vec3>{Vec3(0, 0, 0)}, Vec3(1, 0, 0)), InvalidInputError);
  EXPECT_THROW((void)deform::fabrik(std::vector<Vec3>{Vec3(0, 0, 0), Vec3(0, 0, 0)}, Vec3(1, 0, 0)), InvalidInputError);
  EXPECT_THROW((void)deform::fabrik(chain(), Vec3(NAN, 0, 0)), InvalidInputError);
}

}  // namespace
