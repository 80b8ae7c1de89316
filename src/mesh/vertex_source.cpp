#include "cgamesh/mesh/vertex_source.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>

#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/influences.hpp"

namespace cgamesh::mesh {
namespace {

/// Copies row v of an old row-major attribute to row i of the new one. Raw pointers, so that
/// they stay in registers across the calls of a loop (an Eigen matrix's would be reloaded).
template <class T, int Cols>
struct CopyRows {
  const T* from;
  T* to;
  void operator()(int v, Eigen::Index i) const {
    // memcpy of a constant size is inlined; std::copy_n becomes a call of memmove.
    std::memcpy(to + Cols * i, from + Cols * static_cast<Eigen::Index>(v), sizeof(T) * Cols);
  }
};

/// Row i of the new attribute `dst`: the blend of the old rows of `src` that `s` (not a
/// copy) names, renormalised if `unit`.
template <class Matrix>
void blend_row(const Matrix& src, const VertexSource& s, Matrix& dst, Eigen::Index i, bool unit) {
  auto row = dst.row(i);
  row = s.weight[0] * src.row(s.vertex[0]);
  for (int k = 1; k < s.count(); ++k) row += s.weight[k] * src.row(s.vertex[k]);
  if (unit && row.norm() > 0) row.normalize();
}

}  // namespace

void blend_influences(const Skin& skin, const VertexSource& source, std::span<std::uint16_t, 4> joints,
                      std::span<float, 4> weights) noexcept {
  std::array<Influence, 12> all{};
  std::size_t n = 0;
  const auto gather = [&](std::uint8_t mask) {
    for (int s = 0; s < source.count(); ++s) {
      if ((mask & (1u << s)) == 0) continue;
      for (int k = 0; k < 4; ++k)
        all[n++] = {source.weight[s] * skin.weights(source.vertex[s], k), skin.joints(source.vertex[s], k)};
    }
  };
  gather(source.influence_mask);
  TopInfluences top = top_influences(std::span(all.data(), n));
  if (top.kept == 0) {
    n = 0;
    gather(0b111);
    top = top_influences(std::span(all.data(), n));
  }
  std::copy(top.joints.begin(), top.joints.end(), joints.begin());
  std::copy(top.weights.begin(), top.weights.end(), weights.begin());
}

namespace {

/// @throws InvalidInputError when a source names a vertex outside the old mesh's `nv`.
void check_sources(std::span<const VertexSource> sources, Eigen::Index nv) {
  for (std::size_t i = 0; i < sources.size(); ++i)
    for (int k = 0; k < sources[i].count(); ++k)
      if (sources[i].vertex[static_cast<std::size_t>(k)] < 0 || sources[i].vertex[static_cast<std::size_t>(k)] >= nv)
        throw InvalidInputError("resample: new vertex " + std::to_string(i) + " refers to vertex " +
                                std::to_string(sources[i].vertex[static_cast<std::size_t>(k)]) + " of a mesh with " +
                                std::to_string(nv));
}

/// Rows first … first + #sources − 1 of `out`'s attributes (sized already): the blends of
/// `old`'s rows. `out` may be `old` itself, grown, as long as the sources lie before `first`.
void blend_rows(const Mesh& old, std::span<const VertexSource> sources, Mesh& out, Eigen::Index first) {
  const bool has_normals = old.normals.rows() > 0, has_uvs = old.uvs.rows() > 0, has_skin = !old.skin.empty();
  const bool had_generated = old.generated.rows() > 0, has_file_index = old.file_index.rows() > 0;
  // One pass over the sources for all attributes: most new vertices are copies.
  const CopyRows<float, 3> positions{old.positions.data(), out.positions.data()},
      normals{old.normals.data(), out.normals.data()};
  const CopyRows<float, 2> uvs{old.uvs.data(), out.uvs.data()};
  const CopyRows<std::uint16_t, 4> joints{old.skin.joints.data(), out.skin.joints.data()};
  const CopyRows<float, 4> weights{old.skin.weights.data(), out.skin.weights.data()};
  for (std::size_t n = 0; n < sources.size(); ++n) {
    const VertexSource& s = sources[n];
    const Eigen::Index i = first + static_cast<Eigen::Index>(n);
    if (s.count() == 1) {
      const int v = s.vertex[0];
      positions(v, i);
      if (has_normals) normals(v, i);
      if (has_uvs) uvs(v, i);
      out.generated[i] = had_generated ? old.generated[v] : std::uint8_t{0};
      if (has_file_index) out.file_index[i] = old.file_index[v];
    } else {
      out.generated[i] = 1;
      if (has_file_index) out.file_index[i] = -1;
      blend_row(old.positions, s, out.positions, i, false);
      if (has_normals) blend_row(old.normals, s, out.normals, i, true);
      if (has_uvs) blend_row(old.uvs, s, out.uvs, i, false);
    }
    for (std::size_t t = 0; t < old.morph_targets.size(); ++t) {
      const MorphTarget& from = old.morph_targets[t];
      MorphTarget& to = out.morph_targets[t];
      blend_row(from.positions, s, to.positions, i, false);
      if (from.normals.rows() > 0) blend_row(from.normals, s, to.normals, i, false);
    }
    if (!has_skin) continue;
    if (s.count() == 1 && (s.influence_mask & 1u) != 0) {
      joints(s.vertex[0], i);
      weights(s.vertex[0], i);
    } else {
      blend_influences(old.skin, s, std::span<std::uint16_t, 4>(out.skin.joints.row(i).data(), 4),
                       std::span<float, 4>(out.skin.weights.row(i).data(), 4));
    }
  }
}

/// Grows `m` by `n` rows, keeping its rows (an absent attribute, with 0 rows, stays absent).
template <class Matrix>
void grow_rows(Matrix& m, Eigen::Index n) {
  if (m.rows() > 0) m.conservativeResize(m.rows() + n, Eigen::NoChange);
}

}  // namespace

Mesh resample(const Mesh& old, std::span<const VertexSource> sources, const Faces& faces) {
  check_sources(sources, old.vertex_count());
  // One unsigned comparison per index (a negative one wraps above any count), with no early exit
  // so that it vectorises.
  const auto count = static_cast<std::uint32_t>(sources.size());
  std::uint32_t outside = 0;
  for (const int x : std::span(faces.data(), static_cast<std::size_t>(faces.size())))
    outside |= static_cast<std::uint32_t>(x) >= count ? 1u : 0u;
  if (outside != 0)
    throw InvalidInputError("resample: a face refers to a vertex outside the " + std::to_string(sources.size()) +
                            " new vertices");
  Mesh out;
  out.name = old.name;
  out.node = old.node;
  out.material = old.material;
  out.faces = faces;
  // Attributes the old mesh lacks (0 rows) stay empty.
  const auto n = static_cast<Eigen::Index>(sources.size());
  out.positions.resize(n, 3);
  if (old.normals.rows() > 0) out.normals.resize(n, 3);
  if (old.uvs.rows() > 0) out.uvs.resize(n, 2);
  out.generated.resize(n);
  if (old.file_index.rows() > 0) out.file_index.resize(n);
  out.morph_weights = old.morph_weights;
  for (const MorphTarget& t : old.morph_targets)
    out.morph_targets.push_back({t.name, RowMatrixXf<3>(n, 3), RowMatrixXf<3>(t.normals.rows() > 0 ? n : 0, 3)});
  if (!old.skin.empty()) {
    out.skin.palette = old.skin.palette;
    out.skin.inverse_bind = old.skin.inverse_bind;
    out.skin.inverse_bind_versors = old.skin.inverse_bind_versors;
    out.skin.joints.resize(n, 4);
    out.skin.weights.resize(n, 4);
  }
  blend_rows(old, sources, out, 0);
  return out;
}

void append_resampled(Mesh& m, std::span<const VertexSource> sources) {
  const Eigen::Index first = m.vertex_count(), n = static_cast<Eigen::Index>(sources.size());
  check_sources(sources, first);
  if (n == 0) return;
  grow_rows(m.positions, n);
  grow_rows(m.normals, n);
  grow_rows(m.uvs, n);
  if (m.generated.rows() > 0)
    m.generated.conservativeResize(first + n);
  else
    m.generated.setZero(first + n);
  grow_rows(m.file_index, n);
  for (MorphTarget& t : m.morph_targets) {
    grow_rows(t.positions, n);
    grow_rows(t.normals, n);
  }
  if (!m.skin.empty()) {
    grow_rows(m.skin.joints, n);
    grow_rows(m.skin.weights, n);
  }
  blend_rows(m, sources, m, first);
}

}  // namespace cgamesh::mesh
