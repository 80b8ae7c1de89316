#pragma once
// The priority queue a tissue's region grows by (soft/tissue.hpp): candidate faces nearest
// first. A binary heap spent a third of the growth's time in its log n sift steps with
// unpredictable branches; buckets by reach make a push and a pop a few steps.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace cgamesh::soft {

/// A min-priority queue of 64-bit keys whose high 32 bits are the bits of a float reach in
/// [0, 1] (a non-negative float orders as its bits do) and whose low 32 bits are free (an
/// index). It pops in the order a binary min-heap of the same keys would, including keys pushed
/// below the last one popped.
class ReachQueue {
 public:
  static constexpr std::size_t kBuckets = 1024;

  ReachQueue() : buckets_(kBuckets + 1) {}

  /// Empties the queue (keeping its capacity).
  void clear() noexcept {
    for (std::vector<std::uint64_t>& b : buckets_) b.clear();
    current_ = 0;
    size_ = 0;
  }
  [[nodiscard]] bool empty() const noexcept { return size_ == 0; }
  [[nodiscard]] std::size_t size() const noexcept { return size_; }

  /// Adds `key`; its reach (high half) must lie in [0, 1].
  void push(std::uint64_t key) {
    std::size_t b = bucket(key);
    ++size_;
    if (b > current_) {
      buckets_[b].push_back(key);
      return;
    }
    // The current bucket stays sorted, greatest first, so that its least is at the back.
    std::vector<std::uint64_t>& c = buckets_[current_];
    c.insert(std::upper_bound(c.begin(), c.end(), key, std::greater<>()), key);
  }

  /// The least key. Requires !empty().
  [[nodiscard]] std::uint64_t top() {
    settle();
    return buckets_[current_].back();
  }
  /// Removes the least key. Requires !empty().
  void pop() {
    settle();
    buckets_[current_].pop_back();
    --size_;
  }

 private:
  [[nodiscard]] static std::size_t bucket(std::uint64_t key) noexcept {
    const float reach = std::bit_cast<float>(static_cast<std::uint32_t>(key >> 32));
    return std::min(kBuckets, static_cast<std::size_t>(reach * static_cast<float>(kBuckets)));
  }
  /// Moves to the first non-empty bucket, sorted (every key below lies in the current bucket).
  void settle() {
    if (!buckets_[current_].empty()) return;
    do ++current_;
    while (buckets_[current_].empty());
    std::sort(buckets_[current_].begin(), buckets_[current_].end(), std::greater<>());
  }

  std::vector<std::vector<std::uint64_t>> buckets_;  ///< by reach × kBuckets; the last holds reach 1
  std::size_t current_ = 0;  ///< buckets before it are empty; it is sorted
  std::size_t size_ = 0;
};

}  // namespace cgamesh::soft
