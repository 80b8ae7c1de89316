#pragma once
// Writing one posed frame as a static mesh file (OBJ or PLY), e.g. the output of skinning.

#include <filesystem>
#include <span>

#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::io {

/// Writes the meshes with the given (posed) positions and normals and each mesh's faces as one
/// file. The meshes' own positions and normals are rest-pose data and are not used (pass posed
/// normals, e.g. posed_frame() of text_values.hpp); nor are skins and skeleton.
///  - `.obj`: a comment line, then per mesh an `o NAME` group (whitespace in the name replaced
///    by '_', "meshI" when empty), its `v x y z` lines, its `vt u v` lines when the mesh has
///    texture coordinates, its `vn x y z` lines when it has normals, and its faces `f a b c`,
///    `f a/a b/b c/c` (texture coordinates), `f a//a b//b c//c` (normals) or
///    `f a/a/a b/b/b c/c/c` (both), with 1-based indices of v, vt and vn each counted over the
///    whole file. Floats are printed with 9 significant digits, so they read back exactly.
///  - `.ply`: binary_little_endian 1.0; `element vertex` with float x y z, and float nx ny nz
///    when every mesh with vertices has normals (one vertex element holds all meshes: when only
///    some have normals, none are written), `element face` with `list uchar int
///    vertex_indices`; all meshes concatenated, indices offset accordingly.
/// The extension is matched case-insensitively. The file is written atomically
/// (atomic_file.hpp).
/// @param[in] meshes     the meshes (faces, names and texture coordinates are used)
/// @param[in] positions  one #V_i×3 matrix per mesh: the posed vertex positions
/// @param[in] out        output path, extension .obj or .ply
/// @param[in] normals    empty (no normals written), or one matrix per mesh: #V_i×3 posed
///                       normals, or 0 rows for a mesh without normals
/// @throws InvalidInputError for another extension, no meshes, positions.size() !=
///         meshes.size(), a positions matrix whose row count differs from its mesh's vertex
///         count, normals neither empty nor one per mesh, a normals matrix with rows other than
///         0 or #V, NaN/infinite positions, normals or texture coordinates, texture coordinate
///         rows other than 0 or #V, a face index out of range, or more than 2^31 - 1 vertices
///         in total. Nothing is written then.
/// @throws WriteError when the file cannot be written (nothing is left behind).
void write_mesh(std::span<const mesh::Mesh> meshes, std::span<const mesh::RowMatrixXf<3>> positions,
                const std::filesystem::path& out, std::span<const mesh::RowMatrixXf<3>> normals = {});

/// The file write_mesh() would write, not written.
/// @throws InvalidInputError as write_mesh().
[[nodiscard]] EncodedFile encode_mesh(std::span<const mesh::Mesh> meshes,
                                      std::span<const mesh::RowMatrixXf<3>> positions, const std::filesystem::path& out,
                                      std::span<const mesh::RowMatrixXf<3>> normals = {});

}  // namespace cgamesh::io
