#pragma once
// Loading rigged and static models with Assimp: glTF/GLB, COLLADA, FBX, DirectX .x, SMD, MD5,
// OBJ, PLY, STL and every other format Assimp reads.

#include <filesystem>

#include "cgamesh/anim/rigged_model.hpp"

namespace cgamesh::io {

struct LoadOptions {
  /// Ticks per second for clips whose file does not say (Assimp reports 0; a .x file without
  /// AnimTicksPerSecond): the loader warns naming the rate assumed.
  double default_ticks_per_second = 25.0;
};

/// Loads every triangle mesh, the node hierarchy (as the skeleton), skins and animation clips.
/// glTF's vertices are kept as the file indexes them; other formats' vertices that agree in
/// every attribute are joined (mesh::join_identical_vertices), so seams where a normal, UV or
/// skin weight differs stay split. Each vertex keeps its number in the file where the format's
/// numbering is known (Mesh::file_index: glTF, PLY, OBJ). Before Assimp reads it, a file of a format whose reader
/// can hang or allocate without bound is checked (SMD sections closed, MD5 braces balanced,
/// PLY, OFF and MD5 counts within the file's size). What readers hand over from files made
/// elsewhere is repaired, each with a warning: names that are not UTF-8 are read as Latin-1, a
/// child node a reader left empty is skipped, NaN normals become their faces' normals, and keys
/// before t = 0 are replaced by the pose at 0 (cubic-spline ones: FileError). Skins keep the 4 largest influences
/// per vertex, renormalised to sum 1; non-uniform scales in bind data or keys are kept in the
/// TRS data and matrices (cga and matrix skinning use them exactly) and approximated in the
/// versors (versor skinning; dqs blends them approximately too). Each approximation adds a
/// line to RiggedModel::warnings, as does a clip read at LoadOptions::default_ticks_per_second.
/// A clip lasts as long as its file declares (Clip::duration), even past its last key. Mirrored
/// nodes (negative determinant, e.g. a .x root frame swapping Y and Z) are made proper: the
/// reflection is pushed down the tree into conjugated child transforms and keys, inverse binds
/// and, where needed, the mesh data (reflected, with triangle winding reversed unless the file
/// wound it for the mirror), so world positions are the file's and every versor is even. Only a
/// mirrored node that a clip rotates or scales, or a mesh bound to joints on both sides of a
/// mirror, cannot be represented: FileError naming the node or mesh.
/// @param[in] path  model file
/// @throws FileError when the file is missing, unreadable, corrupt (also as found by the checks
///         above, naming the line), or holds no triangle mesh.
[[nodiscard]] anim::RiggedModel load_model(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace cgamesh::io
