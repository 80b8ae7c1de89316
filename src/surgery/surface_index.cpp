#include "cgamesh/surgery/surface_index.hpp"

#include <string>

#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/adjacency.hpp"
#include "cgamesh/mesh/weld.hpp"

#include "surgery_common.hpp"

namespace cgamesh::surgery {

int MeshIndex::edge_across(int f, int k) const noexcept { return mesh::edge_across(neighbor, f, k); }

SurfaceIndex SurfaceIndex::build(const anim::RiggedModel& model, const Placement& placement) {
  require_placement_fits(model, placement);
  SurfaceIndex out;
  out.meshes.reserve(model.meshes.size());
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    if (!placement.positions[i].allFinite())
      throw InvalidInputError("surgery: the placed positions of mesh '" + model.meshes[i].name + "' hold NaN");
    MeshIndex& index = out.meshes.emplace_back();
    index.bvh = mesh::TriangleBvh(placement.positions[i], model.meshes[i].faces);
    index.weld = mesh::weld_by_position(model.meshes[i].positions);
    index.neighbor = mesh::face_adjacency(model.meshes[i].faces, index.weld);
  }
  return out;
}

}  // namespace cgamesh::surgery
