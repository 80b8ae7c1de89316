#pragma once
// Private to the I/O module: reads glTF animations with their sampler interpolation, which Assimp
// drops (it loads STEP and CUBICSPLINE keys as if LINEAR).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cgamesh/anim/clip.hpp"
#include "cgamesh/anim/skeleton.hpp"

namespace cgamesh::io::detail {

/// True for a .gltf or .glb path (any case).
[[nodiscard]] bool is_gltf(const std::filesystem::path& path);

/// The clips of a .gltf/.glb file, channels bound to `skeleton` joints by node name (or Assimp's
/// "nodes[i]" for unnamed nodes), with times, values and interpolation as the file stores them
/// (cubic splines keep their in/out tangents). Morph-target weight channels are skipped.
/// Returns nullopt, with a warning, for a file tinygltf cannot parse (glTF 1.0).
/// @param[in] path      the .gltf or .glb file Assimp already loaded
/// @param[in] skeleton  the skeleton built from the same file
/// @param[out] warnings channels that could not be bound, appended
/// @throws FileError when the file's animation data is invalid.
[[nodiscard]] std::optional<std::vector<anim::Clip>> read_gltf_clips(const std::filesystem::path& path,
                                                                     const anim::Skeleton& skeleton,
                                                                     std::vector<std::string>& warnings);

}  // namespace cgamesh::io::detail
