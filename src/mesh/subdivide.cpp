#include "cgamesh/mesh/subdivide.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace cgamesh::mesh {
namespace {

std::uint64_t edge_key(int a, int b) {
  const auto [lo, hi] = std::minmax(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(lo)) << 32) | static_cast<std::uint32_t>(hi);
}

/// Mean of two vertices' influences, by joint; the 4 largest kept and renormalised.
void blend_influences(const Skin& s, int a, int b, Eigen::Index out, Skin& dst) {
  std::array<std::pair<float, std::uint16_t>, 8> all{};
  int n = 0;
  for (int v : {a, b})
    for (int k = 0; k < 4; ++k) {
      const float w = 0.5f * s.weights(v, k);
      if (w <= 0) continue;
      const std::uint16_t j = s.joints(v, k);
      auto* it = std::find_if(all.begin(), all.begin() + n, [&](const auto& p) { return p.second == j; });
      if (it != all.begin() + n) it->first += w;
      else all[n++] = {w, j};
    }
  // The 4 largest first (selection: n <= 8).
  for (int k = 0; k < std::min(n, 4); ++k)
    for (int m = k + 1; m < n; ++m)
      if (all[m].first > all[k].first) std::swap(all[k], all[m]);
  n = std::min(n, 4);
  float sum = 0;
  for (int k = 0; k < n; ++k) sum += all[k].first;
  for (int k = 0; k < 4; ++k) {
    dst.weights(out, k) = k < n ? all[k].first / sum : 0.0f;
    dst.joints(out, k) = k < n ? all[k].second : 0;
  }
}

}  // namespace

Mesh subdivide_midpoint(const Mesh& in) {
  Mesh out;
  out.name = in.name;
  out.node = in.node;
  out.skin.palette = in.skin.palette;
  out.skin.inverse_bind = in.skin.inverse_bind;
  out.skin.inverse_bind_versors = in.skin.inverse_bind_versors;

  std::unordered_map<std::uint64_t, int> midpoint;
  std::vector<std::pair<int, int>> edges;
  const Eigen::Index nv = in.vertex_count();
  const auto mid = [&](int a, int b) {
    const auto [it, added] = midpoint.try_emplace(edge_key(a, b), static_cast<int>(nv + edges.size()));
    if (added) edges.emplace_back(a, b);
    return it->second;
  };
  out.faces.resize(4 * in.face_count(), 3);
  for (Eigen::Index f = 0; f < in.face_count(); ++f) {
    const int a = in.faces(f, 0), b = in.faces(f, 1), c = in.faces(f, 2);
    const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    out.faces.row(4 * f) << a, ab, ca;
    out.faces.row(4 * f + 1) << ab, b, bc;
    out.faces.row(4 * f + 2) << ca, bc, c;
    out.faces.row(4 * f + 3) << ab, bc, ca;
  }
  const Eigen::Index total = nv + static_cast<Eigen::Index>(edges.size());
  const auto extend = [&](const auto& src, auto& dst, bool unit) {
    if (src.rows() == 0) return;
    dst.resize(total, src.cols());
    dst.topRows(nv) = src;
    for (std::size_t e = 0; e < edges.size(); ++e) {
      auto row = dst.row(nv + static_cast<Eigen::Index>(e));
      row = 0.5f * (src.row(edges[e].first) + src.row(edges[e].second));
      if (unit && row.norm() > 0) row.normalize();
    }
  };
  extend(in.positions, out.positions, false);
  extend(in.normals, out.normals, true);
  extend(in.uvs, out.uvs, false);
  if (!in.skin.empty()) {
    out.skin.joints.resize(total, 4);
    out.skin.weights.resize(total, 4);
    out.skin.joints.topRows(nv) = in.skin.joints;
    out.skin.weights.topRows(nv) = in.skin.weights;
    for (std::size_t e = 0; e < edges.size(); ++e)
      blend_influences(in.skin, edges[e].first, edges[e].second, nv + static_cast<Eigen::Index>(e), out.skin);
  }
  return out;
}

}  // namespace cgamesh::mesh
