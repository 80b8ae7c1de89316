#include "cgamesh/mesh/material.hpp"

namespace cgamesh::mesh {

Material cut_surface_material() {
  Material m;
  m.name = kCutSurfaceMaterialName;
  m.base_color = Eigen::Vector4f(0.6f, 0.1f, 0.1f, 1.0f);
  m.roughness = 0.6f;
  return m;
}

int cut_surface_material_index(std::vector<Material>& materials) {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == kCutSurfaceMaterialName) return static_cast<int>(i);
  materials.push_back(cut_surface_material());
  return static_cast<int>(materials.size()) - 1;
}

}  // namespace cgamesh::mesh
