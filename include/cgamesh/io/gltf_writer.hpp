#pragma once
// Writing a rigged model as glTF 2.0 (.glb, or .gltf with a .bin next to it).

#include <filesystem>
#include <string>
#include <vector>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/io/atomic_file.hpp"

namespace cgamesh::io {

struct GltfWriteOptions {
  /// .gltf only: indent the JSON (a .glb's JSON chunk is always compact).
  bool pretty_json = true;
  /// .gltf only: embed the binary buffer as a base64 data URI instead of writing NAME.bin.
  bool embed_buffer = false;
};

/// Writes `model` as glTF 2.0 (asset.generator "cgamesh"); the file passes the Khronos glTF
/// validator with no errors.
///
/// Layout:
///  - node i is skeleton joint i (name, rest TRS; non-uniform scale kept), children from the
///    parents; skeleton roots are scene roots. If a skin's joints lie in several trees, one
///    extra root node "cgamesh_root" (identity) is placed above all skeleton roots.
///  - each mesh gets a glTF mesh with one triangle primitive per material its faces use
///    (Mesh::face_materials, in order of first use; one for a mesh without), all over the same
///    vertex accessors: POSITION (with
///    min/max), NORMAL (renormalised; dropped with a warning if one is zero or not finite),
///    TEXCOORD_0, _CGAMESH_GENERATED (FLOAT 0/1, Mesh::generated, when some vertex is
///    generated; load_model() reads it back), and for a skinned mesh JOINTS_0 (UNSIGNED_SHORT) and WEIGHTS_0 (FLOAT,
///    each row renormalised to sum 1, duplicate joints merged, zero-weight joints set to 0); indices UNSIGNED_SHORT
///    when the mesh has at most 65535 vertices, else UNSIGNED_INT. Vertices are written as they are, never merged.
///  - a mesh goes on node `mesh.node` itself when that node holds no mesh yet, so that a
///    load-write cycle keeps the node tree (count, names, transforms); otherwise on a node of its
///    own: for a skinned mesh a scene root without transform, for a static mesh a child of node
///    `mesh.node` without transform (static meshes come first among its children, in model
///    order, so a depth-first reader such as load_model() meets them in the model's order), or a
///    scene root when `mesh.node` is -1. A skinned mesh has one skin: joints = the palette's
///    nodes, inverseBindMatrices (last row exactly 0 0 0 1), skeleton = the joints' lowest
///    common ancestor.
///  - the materials that faces use (base colour, metallic-roughness, normal, occlusion and
///    emissive factors and textures, alpha mode and cutoff, double-sidedness; factors clamped
///    to [0, 1]), each PNG or JPEG texture's image embedded in the buffer once (a texture of
///    another type is dropped with a warning).
///  - one animation per clip that has a non-empty channel; one sampler per non-empty channel
///    (FLOAT times with min/max; VEC3/VEC4 outputs in the glTF layout, rotations renormalised).
///    A CUBICSPLINE channel with a single key is written as STEP (with a warning).
///  - .glb: one binary chunk. .gltf: the JSON, plus the buffer in `STEM.bin` in the same
///    directory unless options.embed_buffer, where STEM is the .gltf's stem with every
///    character outside [A-Za-z0-9._-] replaced by '_' (so the URI needs no percent-encoding,
///    which Assimp and tinygltf do not decode): "my model.gltf" -> "my_model.bin". The .gltf
///    and .bin are written all-or-nothing (atomic_file.hpp); an existing .bin is replaced.
/// @param[in] model    the model; its versor data (inverse_bind_versors) is not used
/// @param[in] out      output path, extension .glb or .gltf (any case)
/// @param[in] options  JSON formatting and buffer placement
/// @return warnings about what was dropped or changed (empty when the model was written as is)
/// @throws InvalidInputError for another extension, a model without meshes, a mesh without
///         vertices or faces, NaN/infinite data, attribute rows != vertices, face_materials
///         rows neither 0 nor #F, a face index out of range, skin joints/weights rows !=
///         vertices, palette and inverse_bind of different sizes, a palette entry outside the
///         skeleton or repeated, a skin joint index >= palette size, a negative weight or a vertex whose weights sum to 0,
///         `mesh.node` outside the skeleton, a channel on a joint outside the skeleton, two
///         channels on the same joint and path in one clip, negative or (in float) not strictly
///         increasing key times, a values size that does not match the key count, or a zero
///         rotation key, a key value too large for a float, or a name that is not valid UTF-8.
///         Nothing is written then.
/// @throws WriteError when the file cannot be written (nothing is left behind).
std::vector<std::string> write_gltf(const anim::RiggedModel& model, const std::filesystem::path& out,
                                    const GltfWriteOptions& options = {});

/// The files write_gltf() would write (the .glb, or the .gltf and its .bin), not written.
/// @param[out] warnings  if not null, what write_gltf() would return
/// @throws InvalidInputError as write_gltf().
[[nodiscard]] std::vector<EncodedFile> encode_gltf(const anim::RiggedModel& model, const std::filesystem::path& out,
                                                   const GltfWriteOptions& options = {},
                                                   std::vector<std::string>* warnings = nullptr);

}  // namespace cgamesh::io
