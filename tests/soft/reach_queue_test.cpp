// The region's priority queue (soft/reach_queue.hpp) against a binary min-heap of the same keys.
#include "cgamesh/soft/reach_queue.hpp"

#include <bit>
#include <cstdint>
#include <functional>
#include <queue>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace {

using cgamesh::soft::ReachQueue;

std::uint64_t key(float reach, std::uint32_t index) {
  return std::uint64_t{std::bit_cast<std::uint32_t>(reach)} << 32 | index;
}

TEST(ReachQueue, PopsInTheOrderOfAMinHeapWhilePushesInterleave) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> reach(0.0f, 1.0f);
  for (int trial = 0; trial < 20; ++trial) {
    ReachQueue q;
    std::priority_queue<std::uint64_t, std::vector<std::uint64_t>, std::greater<>> heap;
    std::uint32_t next = 0;
    const auto push = [&](std::uint64_t k) {
      q.push(k);
      heap.push(k);
    };
    // Ends of the range, ties of reach (told apart by the index), and a growth that pushes keys
    // below the last one popped, as a region's walk does.
    for (const float r : {0.0f, 1.0f, 0.5f, 0.5f, std::nextafter(1.0f, 0.0f)}) push(key(r, next++));
    for (int i = 0; i < 2000; ++i) {
      if (heap.empty() || rng() % 3 != 0) {
        push(key(reach(rng) * (trial % 2 == 0 ? 1.0f : 0.01f), next++));
        continue;
      }
      ASSERT_EQ(q.size(), heap.size());
      const std::uint64_t top = q.top();
      ASSERT_EQ(top, heap.top());
      q.pop();
      heap.pop();
      const float below = std::bit_cast<float>(static_cast<std::uint32_t>(top >> 32)) * 0.5f;
      if (rng() % 4 == 0) push(key(below, next++));
    }
    while (!heap.empty()) {
      ASSERT_FALSE(q.empty());
      ASSERT_EQ(q.top(), heap.top());
      q.pop();
      heap.pop();
    }
    EXPECT_TRUE(q.empty());
    q.clear();
    q.push(key(0.25f, 1));
    EXPECT_EQ(q.top(), key(0.25f, 1));
  }
}

}  // namespace
