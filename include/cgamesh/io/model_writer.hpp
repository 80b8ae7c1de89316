#pragma once
// Writing a model by its path's extension, as every front end does: .glb and .gltf keep the
// rig (gltf_writer.hpp), .obj and .ply hold one surface in world space (mesh_writer.hpp).

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/mesh/world_surface.hpp"

namespace cgamesh::io {

/// What write_model() writes: the formats that keep the rig, then the surfaces.
inline const std::vector<std::string> kRiggedExtensions{".glb", ".gltf"};
inline const std::vector<std::string> kModelExtensions{".glb", ".gltf", ".obj", ".ply"};

/// True for .glb and .gltf (any case): the formats that keep the rig.
[[nodiscard]] bool is_rigged_format(const std::filesystem::path& path);

/// The files of `model` written to `out`: for .glb/.gltf the rigged model (encode_gltf()); for
/// .obj/.ply the meshes' faces with the surface `surface()` gives (called only then: a pose, a
/// placement, a deformation), encode_mesh().
/// @param[out] warnings  if not null, the glTF writer's warnings
/// @throws InvalidInputError for another extension (naming the four), or as the writers.
[[nodiscard]] std::vector<EncodedFile> encode_model(const anim::RiggedModel& model, const std::filesystem::path& out,
                                                    const std::function<mesh::WorldSurface()>& surface,
                                                    std::vector<std::string>* warnings = nullptr);

/// encode_model() written all-or-nothing (write_files_atomically()).
/// @return the glTF writer's warnings
/// @throws as encode_model(); WriteError when the files cannot be written.
std::vector<std::string> write_model(const anim::RiggedModel& model, const std::filesystem::path& out,
                                     const std::function<mesh::WorldSurface()>& surface);

}  // namespace cgamesh::io
