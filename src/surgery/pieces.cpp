#include "cgamesh/surgery/pieces.hpp"

#include <algorithm>
#include <string>

#include "cgamesh/errors.hpp"

#include "surgery_common.hpp"

namespace cgamesh::surgery {

Pieces pieces(const mesh::Mesh& m) { return pieces(m, weld_by_position(m.positions)); }

Pieces pieces(const mesh::Mesh& m, std::span<const int> weld) {
  const auto nv = static_cast<int>(m.vertex_count());
  if (m.face_count() > 0 && (m.faces.minCoeff() < 0 || m.faces.maxCoeff() >= nv))
    throw InvalidInputError("pieces: mesh '" + m.name + "' has a face index outside its " + std::to_string(nv) +
                            " vertices");
  if (weld.size() != static_cast<std::size_t>(nv) ||
      std::any_of(weld.begin(), weld.end(), [&](int w) { return w < 0 || w >= nv; }))
    throw InvalidInputError("pieces: the weld ids of mesh '" + m.name + "' do not fit its " + std::to_string(nv) +
                            " vertices");
  UnionFind sets(static_cast<std::size_t>(nv));
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const int a = weld[static_cast<std::size_t>(m.faces(f, 0))];
    sets.unite(a, weld[static_cast<std::size_t>(m.faces(f, 1))]);
    sets.unite(a, weld[static_cast<std::size_t>(m.faces(f, 2))]);
  }
  Pieces out;
  out.of_vertex.assign(static_cast<std::size_t>(nv), -1);
  std::vector<int> piece_of_root(static_cast<std::size_t>(nv), -1);
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const int r = sets.find(weld[static_cast<std::size_t>(m.faces(f, 0))]);
    int& p = piece_of_root[static_cast<std::size_t>(r)];
    if (p < 0) p = out.count++;
  }
  for (int v = 0; v < nv; ++v) {
    // A vertex in no face is its own root with no piece; a seam copy takes its weld's piece.
    out.of_vertex[static_cast<std::size_t>(v)] =
        piece_of_root[static_cast<std::size_t>(sets.find(weld[static_cast<std::size_t>(v)]))];
  }
  return out;
}

}  // namespace cgamesh::surgery
