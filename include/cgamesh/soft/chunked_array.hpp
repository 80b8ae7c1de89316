#pragma once
// Per-vertex state of a tissue (soft/tissue.hpp) that grows by the few vertices each operation
// adds without moving what it holds: a std::vector would reallocate and copy (and fault in) the
// whole array of a million-vertex mesh the first time it grows after being copied (an undo
// snapshot restored), a spike of tens of milliseconds in the middle of a drag.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace cgamesh::soft {

/// An array of T in fixed chunks of kChunk values: resize() adds or drops whole chunks at the
/// end; the values that stay never move.
template <class T>
class ChunkedArray {
 public:
  static constexpr std::size_t kChunk = std::size_t{1} << 14;

  ChunkedArray() = default;
  ChunkedArray(std::size_t size, const T& value) { resize(size, value); }

  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  [[nodiscard]] T& operator[](std::size_t i) noexcept { return chunks_[i / kChunk][i % kChunk]; }
  [[nodiscard]] const T& operator[](std::size_t i) const noexcept { return chunks_[i / kChunk][i % kChunk]; }

  /// `size` values; those added are `value`.
  void resize(std::size_t size, const T& value) {
    while (chunks_.size() * kChunk < size) chunks_.emplace_back(kChunk, value);
    for (std::size_t i = size_; i < size && i / kChunk < chunks_.size(); ++i) (*this)[i] = value;
    chunks_.resize((size + kChunk - 1) / kChunk);
    size_ = size;
  }

  /// Calls f(value) on each value in order.
  template <class F>
  void for_each(F&& f) {
    for (std::size_t i = 0; i < size_; ++i) f((*this)[i]);
  }
  template <class F>
  void for_each(F&& f) const {
    for (std::size_t i = 0; i < size_; ++i) f((*this)[i]);
  }

 private:
  std::vector<std::vector<T>> chunks_;
  std::size_t size_ = 0;
};

}  // namespace cgamesh::soft
