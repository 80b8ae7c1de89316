// The persistent pool behind skinning, motor blending and deformation frames: parts cover [0, n)
// exactly once, small calls run inline, exceptions reach the caller after every part finished,
// and calls from inside a part or from several threads at once neither deadlock nor mix.
#include "parallel_for.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace {

using cgamesh::detail::kMinPartSize;
using cgamesh::detail::parallel_for;

/// Σ i² over [0, n) through parallel_for: each item written by exactly one part.
std::vector<long long> squares(Eigen::Index n, int threads) {
  std::vector<long long> out(static_cast<std::size_t>(n), -1);
  parallel_for(n, threads, [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index i = begin; i < end; ++i) {
      auto& slot = out[static_cast<std::size_t>(i)];
      slot = slot == -1 ? i * i : -2;  // -2: written twice
    }
  });
  return out;
}

TEST(ParallelFor, EveryItemOnceAndResultsIndependentOfThreads) {
  for (const Eigen::Index n :
       {Eigen::Index{0}, Eigen::Index{1}, kMinPartSize - 1, 2 * kMinPartSize + 3, 10 * kMinPartSize + 17}) {
    std::vector<long long> expected(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) expected[static_cast<std::size_t>(i)] = i * i;
    for (const int threads : {1, 2, 3, 0, 8}) EXPECT_EQ(squares(n, threads), expected) << n << " " << threads;
  }
}

TEST(ParallelFor, SmallCallsRunInlineInOnePart) {
  const std::thread::id caller = std::this_thread::get_id();
  int parts = 0;
  bool inline_ = true;
  parallel_for(2 * kMinPartSize - 1, 0, [&](Eigen::Index begin, Eigen::Index end) {
    ++parts;
    inline_ = inline_ && std::this_thread::get_id() == caller && begin == 0 && end == 2 * kMinPartSize - 1;
  });
  EXPECT_EQ(parts, 1);
  EXPECT_TRUE(inline_);
}

TEST(ParallelFor, AllThreadsMeansOnePartPerHardwareThread) {
  const int hw = cgamesh::detail::hardware_threads();
  EXPECT_EQ(hw, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  std::atomic<int> parts = 0;
  parallel_for(64 * kMinPartSize, 0, [&](Eigen::Index, Eigen::Index) { ++parts; });
  EXPECT_EQ(parts, hw);
}

TEST(ParallelFor, FirstExceptionInPartOrderAfterEveryPartFinished) {
  const Eigen::Index n = 4 * kMinPartSize;
  for (int round = 0; round < 20; ++round) {
    std::atomic<int> finished{0};
    try {
      parallel_for(n, 4, [&](Eigen::Index begin, Eigen::Index) {
        const auto part = static_cast<int>(begin / kMinPartSize);
        if (part == 1 || part == 3) {
          ++finished;
          throw std::runtime_error("part " + std::to_string(part));
        }
        std::this_thread::sleep_for(std::chrono::microseconds(200));
        ++finished;
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "part 1");
    }
    EXPECT_EQ(finished.load(), 4);
  }
  // The pool is usable after a throwing call.
  EXPECT_EQ(squares(3 * kMinPartSize, 0)[static_cast<std::size_t>(kMinPartSize)], kMinPartSize * kMinPartSize);
}

TEST(ParallelFor, NestedAndConcurrentCallsComplete) {
  const Eigen::Index n = 4 * kMinPartSize;
  // A call from inside a part runs inline (its pool is busy running the outer call).
  std::vector<long long> inner_sums(4, 0);
  parallel_for(4 * kMinPartSize, 4, [&](Eigen::Index begin, Eigen::Index) {
    const std::vector<long long> s = squares(n, 0);
    inner_sums[static_cast<std::size_t>(begin / kMinPartSize)] = std::accumulate(s.begin(), s.end(), 0LL);
  });
  const std::vector<long long> s = squares(n, 1);
  const long long expected = std::accumulate(s.begin(), s.end(), 0LL);
  for (const long long sum : inner_sums) EXPECT_EQ(sum, expected);
  // Calls from several threads: one takes the pool, the others run inline.
  std::vector<std::thread> callers;
  std::vector<long long> sums(4, 0);
  for (std::size_t t = 0; t < sums.size(); ++t)
    callers.emplace_back([&, t] {
      for (int round = 0; round < 50; ++round) {
        const std::vector<long long> r = squares(n, 0);
        sums[t] = std::accumulate(r.begin(), r.end(), 0LL);
        if (sums[t] != expected) return;
      }
    });
  for (std::thread& c : callers) c.join();
  for (const long long sum : sums) EXPECT_EQ(sum, expected);
}

}  // namespace
