#include "cgamesh/mesh/influences.hpp"

#include <algorithm>
#include <cmath>

namespace cgamesh::mesh {

namespace {

/// Sorts by `less`: insertion sort for the few influences of a blended vertex (2–3 vertices × 4),
/// where std::sort's and std::partial_sort's set-up costs more than the sorting; std::sort above.
template <class Less>
void sort_influences(std::span<Influence> s, Less less) noexcept {
  if (s.size() > 16) {
    std::sort(s.begin(), s.end(), less);
    return;
  }
  for (std::size_t i = 1; i < s.size(); ++i) {
    const Influence x = s[i];
    std::size_t j = i;
    for (; j > 0 && less(x, s[j - 1]); --j) s[j] = s[j - 1];
    s[j] = x;
  }
}

}  // namespace

TopInfluences top_influences(std::span<Influence> all) noexcept {
  TopInfluences out;
  std::size_t positive = 0;
  for (const Influence& i : all)
    if (i.weight > 0 && std::isfinite(i.weight)) all[positive++] = i;
  const std::span<Influence> used = all.first(positive);
  // The copies of a joint merged into the first: for a blended vertex's few influences, found by
  // scanning the joints kept so far (a quarter faster than sorting by joint first); beyond that,
  // made neighbours by sorting by joint.
  const bool few = used.size() <= 16;
  if (!few) sort_influences(used, [](const Influence& a, const Influence& b) { return a.joint < b.joint; });
  std::size_t n = 0;
  for (std::size_t i = 0; i < used.size(); ++i) {
    std::size_t j = few || n == 0 ? 0 : n - 1;  // sorted: a copy can only be the last kept
    while (j < n && used[j].joint != used[i].joint) ++j;
    if (j < n) {
      used[j].weight += used[i].weight;
      out.merged = true;
    } else {
      used[n++] = used[i];
    }
  }
  out.distinct = static_cast<int>(n);
  const std::size_t kept = std::min<std::size_t>(n, 4);
  const auto heavier = [](const Influence& a, const Influence& b) {
    return a.weight > b.weight || (a.weight == b.weight && a.joint < b.joint);
  };
  if (n > 16)
    std::partial_sort(used.begin(), used.begin() + static_cast<std::ptrdiff_t>(kept),
                      used.begin() + static_cast<std::ptrdiff_t>(n), heavier);
  else
    sort_influences(used.first(n), heavier);
  out.kept = static_cast<int>(kept);
  if (kept == 0) return out;
  double sum = 0;
  for (std::size_t k = 0; k < kept; ++k) sum += used[k].weight;
  double total = 0;
  for (std::size_t k = 0; k < kept; ++k) {
    out.joints[k] = used[k].joint;
    out.weights[k] = static_cast<float>(used[k].weight / sum);
    total += out.weights[k];
  }
  // The rounding remainder goes to the largest weight; taken away, to the last of those tied
  // with it, so that the order stays.
  const double remainder = 1.0 - total;
  std::size_t k = 0;
  while (remainder < 0 && k + 1 < kept && out.weights[k + 1] == out.weights[0]) ++k;
  out.weights[k] = static_cast<float>(out.weights[k] + remainder);
  return out;
}

}  // namespace cgamesh::mesh
