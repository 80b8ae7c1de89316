#pragma once
// Paths of the real models the animation and I/O tests run on.

#include <filesystem>
#include <string>
#include <vector>

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

}  // namespace cgamesh_test
