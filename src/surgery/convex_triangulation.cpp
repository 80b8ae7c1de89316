#include "convex_triangulation.hpp"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

namespace cgamesh::surgery::detail {
namespace {

double quality(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double sides = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return sides > 0 ? (b - a).cross(c - a).norm() / sides : 0.0;
}

}  // namespace

void triangulate_convex(std::span<const Eigen::Vector3d> points, std::vector<std::array<int, 3>>& out) {
  const auto n = static_cast<int>(points.size());
  if (n < 3) return;
  if (n == 3) {
    out.push_back({0, 1, 2});
    return;
  }
  // best[i][j]: the best smallest quality of the sub-polygon i..j; split[i][j] its apex.
  const auto at = [n](int i, int j) { return static_cast<std::size_t>(i * n + j); };
  std::vector<double> best(static_cast<std::size_t>(n * n), std::numeric_limits<double>::infinity());
  std::vector<int> split(static_cast<std::size_t>(n * n), -1);
  for (int len = 2; len < n; ++len)
    for (int i = 0; i + len < n; ++i) {
      const int j = i + len;
      double b = -1;
      for (int k = i + 1; k < j; ++k) {
        const double q = std::min({quality(points[static_cast<std::size_t>(i)], points[static_cast<std::size_t>(k)],
                                           points[static_cast<std::size_t>(j)]),
                                   best[at(i, k)], best[at(k, j)]});
        if (q > b) {
          b = q;
          split[at(i, j)] = k;
        }
      }
      best[at(i, j)] = b;
    }
  // Emit the triangles of 0..n−1 (an explicit stack: no recursion).
  std::vector<std::array<int, 2>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2) continue;
    const int k = split[at(i, j)];
    out.push_back({i, k, j});
    stack.push_back({i, k});
    stack.push_back({k, j});
  }
}

}  // namespace cgamesh::surgery::detail
