#pragma once
// Private to the I/O module: the file's own numbering of each loaded vertex (Mesh::file_index).

#include <filesystem>
#include <vector>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::io::detail {

/// Sets Mesh::file_index of the meshes Assimp read from `path`, before any joining:
/// - glTF: Assimp keeps each primitive's vertices as the accessors order them: the identity;
/// - PLY: the identity when the file gives one mesh with the vertex count its header declares
///   (Assimp keeps the vertex element's order, unreferenced vertices included);
/// - OBJ: Assimp gives one vertex per face corner, so each is matched to the file's `v` lines by
///   position: the nearest within 1e-6 × the largest coordinate (Assimp's number parser and
///   strtof differ by an ulp), the first `v` line among equals;
/// - other formats, or a mesh with a vertex that matches no `v` line: left with 0 rows.
void number_file_vertices(const std::filesystem::path& path, std::vector<mesh::Mesh>& meshes);

}  // namespace cgamesh::io::detail
