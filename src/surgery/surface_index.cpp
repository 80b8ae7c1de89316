#include "cgamesh/surgery/surface_index.hpp"

#include <algorithm>
#include <cstdint>
#include <string>

#include "cgamesh/errors.hpp"
#include "surgery_common.hpp"

namespace cgamesh::surgery {

int MeshIndex::edge_across(int f, int k) const noexcept {
  const int g = neighbor[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
  if (g < 0) return -1;
  for (int j = 0; j < 3; ++j)
    if (neighbor[static_cast<std::size_t>(g)][static_cast<std::size_t>(j)] == f) return j;
  return -1;
}

namespace {

MeshIndex index_mesh(const mesh::Mesh& m, const mesh::RowMatrixXf<3>& placed) {
  MeshIndex out;
  out.bvh = mesh::TriangleBvh(placed, m.faces);
  out.weld = weld_by_position(m.positions);
  const auto nf = static_cast<std::size_t>(m.face_count());
  // Directed welded edges sorted by key: a manifold edge has exactly one twin.
  std::vector<std::pair<std::uint64_t, int>> directed;
  directed.reserve(3 * nf);
  const auto w = [&](std::size_t f, int k) {
    return out.weld[static_cast<std::size_t>(m.faces(static_cast<Eigen::Index>(f), k % 3))];
  };
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) directed.emplace_back(directed_key(w(f, k), w(f, k + 1)), static_cast<int>(3 * f) + k);
  std::sort(directed.begin(), directed.end());
  const auto range = [&](std::uint64_t key) {
    return std::equal_range(directed.begin(), directed.end(), std::pair<std::uint64_t, int>{key, -1},
                            [](const auto& x, const auto& y) { return x.first < y.first; });
  };
  out.neighbor.assign(nf, {-1, -1, -1});
  for (std::size_t i = 0; i < directed.size(); ++i) {
    const auto [key, slot] = directed[i];
    const auto a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    if (a == b) continue;
    const bool unique = (i == 0 || directed[i - 1].first != key) && (i + 1 == directed.size() || directed[i + 1].first != key);
    if (!unique) continue;
    const auto [lo, hi] = range(directed_key(b, a));
    if (hi - lo != 1) continue;
    out.neighbor[static_cast<std::size_t>(slot / 3)][static_cast<std::size_t>(slot % 3)] = lo->second / 3;
  }
  return out;
}

}  // namespace

SurfaceIndex SurfaceIndex::build(const anim::RiggedModel& model, const Placement& placement) {
  require_placement_fits(model, placement);
  SurfaceIndex out;
  out.meshes.reserve(model.meshes.size());
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    if (!placement.positions[i].allFinite())
      throw InvalidInputError("surgery: the placed positions of mesh '" + model.meshes[i].name + "' hold NaN");
    out.meshes.push_back(index_mesh(model.meshes[i], placement.positions[i]));
  }
  return out;
}

}  // namespace cgamesh::surgery
