#pragma once
// Private to the library: the hash map of surgery's small affected regions and of on-demand
// welding.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace cgamesh {

/// Hash of a 64-bit key (edge keys, ids): the key itself, as FlatMap mixes it.
struct KeyHash {
  [[nodiscard]] std::size_t operator()(std::uint64_t key) const noexcept { return static_cast<std::size_t>(key); }
};

/// An open-addressing (linear probing) hash map of small values. An operation's region holds a
/// few hundred vertices, faces and edges: node-based maps spent most of a cut or drill
/// allocating nodes and hashing by division. Pointers to values last until the next insertion.
/// `Hash` need not mix its bits: Fibonacci hashing (the high bits of h · 2⁶⁴/φ) does.
template <class Value, class Key = std::uint64_t, class Hash = KeyHash>
class FlatMap {
 public:
  /// Room for n entries without rehashing.
  void reserve(std::size_t n) {
    if (2 * n > slots_.size()) rehash(std::bit_ceil(2 * n));
  }

  /// The value of `key`, inserted as `value` when absent, and whether it was inserted.
  std::pair<Value*, bool> try_emplace(const Key& key, const Value& value) {
    if (2 * (size_ + 1) > slots_.size()) rehash(std::max<std::size_t>(64, 2 * slots_.size()));
    Slot& s = slots_[probe(key)];
    if (s.used) return {&s.value, false};
    s = {key, value, true};
    ++size_;
    return {&s.value, true};
  }

  [[nodiscard]] const Value* find(const Key& key) const {
    if (slots_.empty()) return nullptr;
    const Slot& s = slots_[probe(key)];
    return s.used ? &s.value : nullptr;
  }
  [[nodiscard]] Value* find(const Key& key) { return const_cast<Value*>(std::as_const(*this).find(key)); }

  [[nodiscard]] std::size_t size() const noexcept { return size_; }

 private:
  /// Key and value side by side: a probe reads one cache line, not one in each of two arrays.
  struct Slot {
    Key key{};
    Value value{};
    bool used = false;
  };

  /// The slot holding `key`, or the empty slot that ends its probe sequence.
  [[nodiscard]] std::size_t probe(const Key& key) const {
    std::size_t i =
        static_cast<std::size_t>((static_cast<std::uint64_t>(Hash{}(key)) * 0x9E3779B97F4A7C15ULL) >> shift_);
    while (slots_[i].used && !(slots_[i].key == key)) i = (i + 1) & (slots_.size() - 1);
    return i;
  }

  /// Moves the entries to `capacity` (a power of two) slots.
  void rehash(std::size_t capacity) {
    std::vector<Slot> old = std::exchange(slots_, std::vector<Slot>(capacity));
    shift_ = 64 - std::countr_zero(capacity);
    for (const Slot& s : old)
      if (s.used) slots_[probe(s.key)] = s;
  }

  std::vector<Slot> slots_;
  std::size_t size_ = 0;
  int shift_ = 64;
};

}  // namespace cgamesh
