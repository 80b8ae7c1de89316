#include "cgamesh/mesh/vertex_source.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "cgamesh/errors.hpp"

namespace cgamesh::mesh {
namespace {

/// Row r of the new attribute: the blend of the old rows (a plain copy for a copy).
template <class Matrix>
void blend_rows(const Matrix& src, std::span<const VertexSource> sources, Matrix& dst, bool unit) {
  if (src.rows() == 0) return;
  dst.resize(static_cast<Eigen::Index>(sources.size()), src.cols());
  for (std::size_t i = 0; i < sources.size(); ++i) {
    const VertexSource& s = sources[i];
    auto row = dst.row(static_cast<Eigen::Index>(i));
    if (s.count() == 1) {
      row = src.row(s.vertex[0]);
      continue;
    }
    row = s.weight[0] * src.row(s.vertex[0]);
    for (int k = 1; k < s.count(); ++k) row += s.weight[k] * src.row(s.vertex[k]);
    if (unit && row.norm() > 0) row.normalize();
  }
}

}  // namespace

void blend_influences(const Skin& skin, const VertexSource& source, std::span<std::uint16_t, 4> joints,
                      std::span<float, 4> weights) noexcept {
  std::array<std::pair<float, std::uint16_t>, 12> all{};
  int n = 0;
  const auto gather = [&](std::uint8_t mask) {
    for (int s = 0; s < source.count(); ++s) {
      if ((mask & (1u << s)) == 0) continue;
      for (int k = 0; k < 4; ++k) {
        const float w = source.weight[s] * skin.weights(source.vertex[s], k);
        if (!(w > 0)) continue;
        const std::uint16_t j = skin.joints(source.vertex[s], k);
        auto* it = std::find_if(all.begin(), all.begin() + n, [&](const auto& p) { return p.second == j; });
        if (it != all.begin() + n) it->first += w;
        else all[static_cast<std::size_t>(n++)] = {w, j};
      }
    }
  };
  gather(source.influence_mask);
  if (n == 0) gather(0b111);
  // The 4 largest first (selection sort: n <= 12).
  for (int k = 0; k < std::min(n, 4); ++k)
    for (int m = k + 1; m < n; ++m)
      if (all[static_cast<std::size_t>(m)].first > all[static_cast<std::size_t>(k)].first)
        std::swap(all[static_cast<std::size_t>(k)], all[static_cast<std::size_t>(m)]);
  n = std::min(n, 4);
  float sum = 0;
  for (int k = 0; k < n; ++k) sum += all[static_cast<std::size_t>(k)].first;
  for (std::size_t k = 0; k < 4; ++k) {
    const bool used = static_cast<int>(k) < n;
    weights[k] = used ? all[k].first / sum : 0.0f;
    joints[k] = used ? all[k].second : 0;
  }
}

Mesh resample(const Mesh& old, std::span<const VertexSource> sources,
              const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& faces) {
  const Eigen::Index nv = old.vertex_count();
  for (std::size_t i = 0; i < sources.size(); ++i)
    for (int k = 0; k < sources[i].count(); ++k)
      if (sources[i].vertex[static_cast<std::size_t>(k)] < 0 || sources[i].vertex[static_cast<std::size_t>(k)] >= nv)
        throw InvalidInputError("resample: new vertex " + std::to_string(i) + " refers to vertex " +
                                std::to_string(sources[i].vertex[static_cast<std::size_t>(k)]) + " of a mesh with " +
                                std::to_string(nv));
  if (faces.size() > 0 && (faces.minCoeff() < 0 || faces.maxCoeff() >= static_cast<int>(sources.size())))
    throw InvalidInputError("resample: a face refers to a vertex outside the " + std::to_string(sources.size()) +
                            " new vertices");
  Mesh out;
  out.name = old.name;
  out.node = old.node;
  out.faces = faces;
  blend_rows(old.positions, sources, out.positions, false);
  blend_rows(old.normals, sources, out.normals, true);
  blend_rows(old.uvs, sources, out.uvs, false);
  if (!old.skin.empty()) {
    out.skin.palette = old.skin.palette;
    out.skin.inverse_bind = old.skin.inverse_bind;
    out.skin.inverse_bind_versors = old.skin.inverse_bind_versors;
    const auto n = static_cast<Eigen::Index>(sources.size());
    out.skin.joints.resize(n, 4);
    out.skin.weights.resize(n, 4);
    for (Eigen::Index i = 0; i < n; ++i) {
      const VertexSource& s = sources[static_cast<std::size_t>(i)];
      if (s.count() == 1 && (s.influence_mask & 1u) != 0) {
        out.skin.joints.row(i) = old.skin.joints.row(s.vertex[0]);
        out.skin.weights.row(i) = old.skin.weights.row(s.vertex[0]);
        continue;
      }
      blend_influences(old.skin, s, std::span<std::uint16_t, 4>(out.skin.joints.row(i).data(), 4),
                       std::span<float, 4>(out.skin.weights.row(i).data(), 4));
    }
  }
  return out;
}

}  // namespace cgamesh::mesh
