#pragma once
// Paths of the real models the animation and I/O tests run on.

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "cgamesh/io/model_loader.hpp"

namespace cgamesh_test {

inline std::filesystem::path asset(const std::string& name) { return std::filesystem::path(CGAMESH_TEST_ASSETS) / name; }
inline std::filesystem::path demo_model() { return std::filesystem::path(CGAMESH_DATA_DIR) / "CesiumMan.glb"; }
/// Rigged models of Debian's assimp-testmodels package (installed by scripts/install-deps.sh).
inline std::filesystem::path assimp_model(const std::string& relative) {
  return std::filesystem::path("/usr/share/assimp/models") / relative;
}

/// The shipped glTF sample models.
inline std::vector<std::filesystem::path> gltf_samples() {
  return {asset("RiggedSimple.glb"), asset("RiggedFigure.glb"), demo_model()};
}

/// The joint that the most vertices of the model's first mesh hang from (their largest weight).
inline std::string busiest_joint(const std::filesystem::path& model) {
  const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(model);
  const cgamesh::mesh::Mesh& mesh = m.meshes.at(0);
  std::vector<int> count(mesh.skin.palette.size(), 0);
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) ++count[static_cast<std::size_t>(mesh.skin.joints(v, 0))];
  const auto best = std::max_element(count.begin(), count.end()) - count.begin();
  return std::string(m.skeleton.names()[static_cast<std::size_t>(mesh.skin.palette[static_cast<std::size_t>(best)])]);
}

}  // namespace cgamesh_test
