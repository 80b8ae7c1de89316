// "Keep the 4 largest influences and renormalise", in its one home.
#include "cgamesh/mesh/influences.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace {

using namespace cgamesh::mesh;

TEST(Influences, MergedByJointLargestFourKeptRenormalised) {
  // Binary fractions, so that the merged weight ties exactly.
  std::vector<Influence> in{{0.125f, 7}, {0.375f, 2}, {0.25f, 7}, {0.0625f, 1}, {0.25f, 4}, {0.125f, 9}, {0.0f, 3}};
  const TopInfluences t = top_influences(in);
  EXPECT_TRUE(t.merged);
  EXPECT_EQ(t.distinct, 5);
  EXPECT_EQ(t.kept, 4);
  // 7: 0.375 (merged), 2: 0.375 — a tie goes to the smaller joint; then 4: 0.25, 9: 0.125; 1 dropped.
  EXPECT_EQ(t.joints, (std::array<std::uint16_t, 4>{2, 7, 4, 9}));
  const double sum = 0.375 + 0.375 + 0.25 + 0.125;
  EXPECT_NEAR(t.weights[0], 0.375 / sum, 1e-7);
  EXPECT_NEAR(t.weights[1], 0.375 / sum, 1e-7);
  EXPECT_NEAR(t.weights[2], 0.25 / sum, 1e-7);
  EXPECT_NEAR(t.weights[3], 0.125 / sum, 1e-7);
}

TEST(Influences, FewerThanFourLeaveZeroSlotsAndNoneIsZero) {
  std::vector<Influence> one{{2.0f, 5}, {-1.0f, 3}, {std::numeric_limits<float>::quiet_NaN(), 4}};
  const TopInfluences t = top_influences(one);
  EXPECT_EQ(t.kept, 1);
  EXPECT_FALSE(t.merged);
  EXPECT_EQ(t.joints, (std::array<std::uint16_t, 4>{5, 0, 0, 0}));
  EXPECT_EQ(t.weights, (std::array<float, 4>{1, 0, 0, 0}));
  std::vector<Influence> none{{0.0f, 1}, {-2.0f, 2}};
  const TopInfluences z = top_influences(none);
  EXPECT_EQ(z.kept, 0);
  EXPECT_EQ(z.weights, (std::array<float, 4>{0, 0, 0, 0}));
}

TEST(Influences, SumIsOneToHalfAnUlpAndOrderDoesNotMatter) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> weight(0.0f, 1.0f);
  std::uniform_int_distribution<int> joint(0, 9);
  for (int round = 0; round < 1000; ++round) {
    std::vector<Influence> in(8);
    for (Influence& i : in) i = {weight(rng), static_cast<std::uint16_t>(joint(rng))};
    std::vector<Influence> shuffled = in;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    const TopInfluences a = top_influences(in), b = top_influences(shuffled);
    EXPECT_EQ(a.joints, b.joints);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(a.weights[k], b.weights[k], 1e-6f);
    double sum = 0;
    for (const float w : a.weights) sum += w;
    EXPECT_LE(std::abs(sum - 1.0), 0.5 * std::numeric_limits<float>::epsilon()) << round;
    for (int k = 1; k < a.kept; ++k) EXPECT_GE(a.weights[k - 1], a.weights[k]);
  }
}

TEST(Influences, TheLargestFourOfAnyCountAsAReferenceKeepsThem) {
  // Counts on both sides of the insertion sort's limit (16), duplicated joints, zero, negative
  // and NaN weights, against a plain merge-and-sort.
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> weight(-0.2f, 1.0f);
  for (int round = 0; round < 2000; ++round) {
    const int count = round % 41;
    std::uniform_int_distribution<int> joint(0, 1 + round % 23);
    std::vector<Influence> in(static_cast<std::size_t>(count));
    for (Influence& i : in) {
      i = {weight(rng), static_cast<std::uint16_t>(joint(rng))};
      if (rng() % 17 == 0) i.weight = std::numeric_limits<float>::quiet_NaN();
    }
    std::map<std::uint16_t, double> merged;
    bool repeated = false;  // a joint listed twice with positive weights
    for (const Influence& i : in)
      if (i.weight > 0 && std::isfinite(i.weight)) {
        repeated = repeated || merged.contains(i.joint);
        merged[i.joint] += i.weight;
      }
    std::vector<std::pair<double, std::uint16_t>> by_weight;
    for (const auto& [j, w] : merged) by_weight.emplace_back(-w, j);
    std::sort(by_weight.begin(), by_weight.end());
    const std::size_t kept = std::min<std::size_t>(by_weight.size(), 4);
    double sum = 0;
    for (std::size_t k = 0; k < kept; ++k) sum -= by_weight[k].first;
    const TopInfluences t = top_influences(in);
    ASSERT_EQ(t.kept, static_cast<int>(kept)) << round;
    EXPECT_EQ(t.distinct, static_cast<int>(merged.size())) << round;
    EXPECT_EQ(t.merged, repeated) << round;
    for (std::size_t k = 0; k < kept; ++k) {
      EXPECT_EQ(t.joints[k], by_weight[k].second) << round << " slot " << k;
      EXPECT_NEAR(t.weights[k], -by_weight[k].first / sum, 1e-6) << round << " slot " << k;
    }
    for (std::size_t k = kept; k < 4; ++k) EXPECT_EQ(t.weights[k], 0.0f) << round;
  }
}

}  // namespace
