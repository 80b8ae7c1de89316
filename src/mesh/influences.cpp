#include "cgamesh/mesh/influences.hpp"

#include <algorithm>
#include <cmath>

namespace cgamesh::mesh {

TopInfluences top_influences(std::span<Influence> all) noexcept {
  TopInfluences out;
  // Positive weights first, by joint, so that the copies of a joint are next to each other.
  const auto positive = std::partition(all.begin(), all.end(),
                                       [](const Influence& i) { return i.weight > 0 && std::isfinite(i.weight); });
  const std::span<Influence> used(all.begin(), positive);
  std::sort(used.begin(), used.end(), [](const Influence& a, const Influence& b) { return a.joint < b.joint; });
  std::size_t n = 0;
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (n > 0 && used[n - 1].joint == used[i].joint) {
      used[n - 1].weight += used[i].weight;
      out.merged = true;
    } else {
      used[n++] = used[i];
    }
  }
  out.distinct = static_cast<int>(n);
  const std::size_t kept = std::min<std::size_t>(n, 4);
  std::partial_sort(used.begin(), used.begin() + static_cast<std::ptrdiff_t>(kept),
                    used.begin() + static_cast<std::ptrdiff_t>(n), [](const Influence& a, const Influence& b) {
                      return a.weight > b.weight || (a.weight == b.weight && a.joint < b.joint);
                    });
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
