#pragma once
// Private to the I/O module: what Assimp drops from a glTF file, read with tinygltf — the
// animations' sampler interpolation (Assimp loads STEP and CUBICSPLINE keys as if LINEAR) and
// the vertex attribute _CGAMESH_GENERATED (Mesh::generated), morph-weight channels and node weights.

#include <filesystem>
#include <string>
#include <vector>

#include "cgamesh/anim/clip.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skeleton.hpp"

namespace cgamesh::io::detail {

/// True for a .gltf or .glb path (any case).
[[nodiscard]] bool is_gltf(const std::filesystem::path& path);

/// The name of the vertex attribute that keeps Mesh::generated (glTF: application-specific
/// attribute names start with '_').
inline constexpr const char* kGeneratedAttribute = "_CGAMESH_GENERATED";

/// Reads the file again with tinygltf and puts into `model` what Assimp dropped: its clips with
/// the file's interpolation , and Mesh::generated of each mesh whose
/// primitive has _CGAMESH_GENERATED and exactly the mesh's positions. What cannot be read is a
/// warning in model.warnings.
/// @throws FileError when the file's animation data is invalid.
void read_gltf_extras(const std::filesystem::path& path, anim::RiggedModel& model);

}  // namespace cgamesh::io::detail
