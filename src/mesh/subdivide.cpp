#include "cgamesh/mesh/subdivide.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "cgamesh/mesh/vertex_source.hpp"

namespace cgamesh::mesh {
namespace {

std::uint64_t edge_key(int a, int b) {
  const auto [lo, hi] = std::minmax(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(lo)) << 32) | static_cast<std::uint32_t>(hi);
}

}  // namespace

Mesh subdivide_midpoint(const Mesh& in) {
  const Eigen::Index nv = in.vertex_count();
  std::vector<VertexSource> sources;
  sources.reserve(static_cast<std::size_t>(nv + 2 * in.face_count()));
  for (Eigen::Index v = 0; v < nv; ++v) sources.push_back(VertexSource::copy(static_cast<int>(v)));
  std::unordered_map<std::uint64_t, int> midpoint;
  const auto mid = [&](int a, int b) {
    const auto [it, added] = midpoint.try_emplace(edge_key(a, b), static_cast<int>(sources.size()));
    if (added) sources.push_back(VertexSource::edge(a, b, 0.5f));
    return it->second;
  };
  Faces faces(4 * in.face_count(), 3);
  for (Eigen::Index f = 0; f < in.face_count(); ++f) {
    const int a = in.faces(f, 0), b = in.faces(f, 1), c = in.faces(f, 2);
    const int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
    faces.row(4 * f) << a, ab, ca;
    faces.row(4 * f + 1) << ab, b, bc;
    faces.row(4 * f + 2) << ca, bc, c;
    faces.row(4 * f + 3) << ab, bc, ca;
  }
  Mesh out = resample(in, sources, faces);
  if (in.face_materials.rows() > 0) {  // the four faces of face f are 4f … 4f + 3
    out.face_materials.resize(4 * in.face_count());
    for (Eigen::Index f = 0; f < in.face_count(); ++f)
      out.face_materials.segment(4 * f, 4).setConstant(in.face_materials[f]);
  }
  return out;
}

}  // namespace cgamesh::mesh
