#pragma once
// A rigged model: meshes with skins, the skeleton they hang from, and animation clips.

#include <string>
#include <vector>

#include "cgamesh/anim/clip.hpp"
#include "cgamesh/anim/skeleton.hpp"
#include "cgamesh/mesh/material.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::anim {

struct RiggedModel {
  std::vector<mesh::Mesh> meshes;
  Skeleton skeleton;
  std::vector<Clip> clips;
  std::vector<mesh::Material> materials;    ///< what Mesh::material indexes
  std::vector<mesh::TextureImage> textures;  ///< what Material::base_color_texture indexes
  /// Everything the loader approximated or dropped (non-uniform scale, > 4 influences, ...).
  std::vector<std::string> warnings;
  /// Largest number of joints influencing one vertex in the file (before keeping 4).
  int source_max_influences = 0;
  /// Index of the clip with this name, or -1.
  [[nodiscard]] int find_clip(const std::string& name) const noexcept {
    for (std::size_t i = 0; i < clips.size(); ++i)
      if (clips[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

}  // namespace cgamesh::anim
