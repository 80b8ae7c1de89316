#include "cgamesh/mesh/weld.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>

#include "cgamesh/errors.hpp"

#include "position_welder.hpp"

namespace cgamesh::mesh {

std::size_t PositionHash::operator()(const std::array<float, 3>& p) const noexcept {
  std::array<std::uint32_t, 3> bits;
  std::memcpy(bits.data(), p.data(), sizeof bits);
  return (static_cast<std::size_t>(bits[0]) * 73856093u) ^ (static_cast<std::size_t>(bits[1]) * 19349663u) ^
         (static_cast<std::size_t>(bits[2]) * 83492791u);
}

int PositionWelder::operator()(int v) { return *first_.try_emplace(position_key(positions_, v), v).first; }

std::vector<int> weld_by_position(const RowMatrixXf<3>& positions) {
  PositionWelder weld(positions);
  std::vector<int> out(static_cast<std::size_t>(positions.rows()));
  for (Eigen::Index i = 0; i < positions.rows(); ++i) out[static_cast<std::size_t>(i)] = weld(static_cast<int>(i));
  return out;
}

int number_classes(std::span<int> ids) {
  // A representative is its class's first vertex, so it is numbered before its copies.
  int count = 0;
  for (std::size_t v = 0; v < ids.size(); ++v) {
    if (ids[v] < 0 || ids[v] > static_cast<int>(v))
      throw InvalidInputError("number_classes: vertex " + std::to_string(v) + " has representative " +
                              std::to_string(ids[v]) + ", not one of the vertices 0 … " + std::to_string(v));
    ids[v] = ids[v] == static_cast<int>(v) ? count++ : ids[static_cast<std::size_t>(ids[v])];
  }
  return count;
}

namespace {

/// Everything a vertex holds, as bits (+0.0f for −0.0f): two vertices are one when these agree.
using VertexBits = std::array<std::uint32_t, 16>;

struct VertexBitsHash {
  std::size_t operator()(const VertexBits& b) const noexcept {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (const std::uint32_t w : b) h = (h ^ w) * 0x100000001b3ULL;
    return static_cast<std::size_t>(h);
  }
};

std::uint32_t bits(float x) { return std::bit_cast<std::uint32_t>(x + 0.0f); }

VertexBits vertex_bits(const Mesh& m, Eigen::Index v) {
  VertexBits b{};
  for (int c = 0; c < 3; ++c) b[static_cast<std::size_t>(c)] = bits(m.positions(v, c));
  if (m.normals.rows() > 0)
    for (int c = 0; c < 3; ++c) b[static_cast<std::size_t>(3 + c)] = bits(m.normals(v, c));
  if (m.uvs.rows() > 0)
    for (int c = 0; c < 2; ++c) b[static_cast<std::size_t>(6 + c)] = bits(m.uvs(v, c));
  if (!m.skin.empty())
    for (int k = 0; k < 4; ++k) {
      b[static_cast<std::size_t>(8 + k)] = bits(m.skin.weights(v, k));
      b[12 + static_cast<std::size_t>(k / 2)] |= static_cast<std::uint32_t>(m.skin.joints(v, k)) << (16 * (k % 2));
    }
  if (m.generated.rows() > 0) b[14] = m.generated(v);
  // Morph displacements: hashed here, compared exactly when two vertices meet (same_morph).
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const MorphTarget& t : m.morph_targets) {
    for (int c = 0; c < 3; ++c) h = (h ^ bits(t.positions(v, c))) * 0x100000001b3ULL;
    if (t.normals.rows() > 0)
      for (int c = 0; c < 3; ++c) h = (h ^ bits(t.normals(v, c))) * 0x100000001b3ULL;
  }
  b[15] = static_cast<std::uint32_t>(h ^ (h >> 32));
  return b;
}

/// Whether vertices a and b move alike under every morph target.
bool same_morph(const Mesh& m, Eigen::Index a, Eigen::Index b) {
  return std::all_of(m.morph_targets.begin(), m.morph_targets.end(), [&](const MorphTarget& t) {
    return t.positions.row(a) == t.positions.row(b) && (t.normals.rows() == 0 || t.normals.row(a) == t.normals.row(b));
  });
}

}  // namespace

int join_identical_vertices(Mesh& m) {
  const Eigen::Index nv = m.vertex_count();
  FlatMap<int, VertexBits, VertexBitsHash> first;
  first.reserve(static_cast<std::size_t>(nv));
  std::vector<int> kept, new_id(static_cast<std::size_t>(nv));
  kept.reserve(static_cast<std::size_t>(nv));
  for (Eigen::Index v = 0; v < nv; ++v) {
    const auto [id, added] = first.try_emplace(vertex_bits(m, v), static_cast<int>(kept.size()));
    if (!added && !same_morph(m, kept[static_cast<std::size_t>(*id)], v)) {
      new_id[static_cast<std::size_t>(v)] = static_cast<int>(kept.size());
      kept.push_back(static_cast<int>(v));
      continue;
    }
    if (added) kept.push_back(static_cast<int>(v));
    new_id[static_cast<std::size_t>(v)] = *id;
  }
  const int removed = static_cast<int>(nv) - static_cast<int>(kept.size());
  if (removed == 0) return 0;
  m.positions = m.positions(kept, Eigen::all).eval();
  if (m.normals.rows() > 0) m.normals = m.normals(kept, Eigen::all).eval();
  if (m.uvs.rows() > 0) m.uvs = m.uvs(kept, Eigen::all).eval();
  if (m.generated.rows() > 0) m.generated = m.generated(kept).eval();
  if (m.file_index.rows() > 0) m.file_index = m.file_index(kept).eval();
  for (MorphTarget& t : m.morph_targets) {
    t.positions = t.positions(kept, Eigen::all).eval();
    if (t.normals.rows() > 0) t.normals = t.normals(kept, Eigen::all).eval();
  }
  if (!m.skin.empty()) {
    m.skin.joints = m.skin.joints(kept, Eigen::all).eval();
    m.skin.weights = m.skin.weights(kept, Eigen::all).eval();
  }
  for (Eigen::Index f = 0; f < m.face_count(); ++f)
    for (int c = 0; c < 3; ++c) m.faces(f, c) = new_id[static_cast<std::size_t>(m.faces(f, c))];
  return removed;
}

}  // namespace cgamesh::mesh
