#pragma once
// Private to io: checks, before a file reaches Assimp, what is cheap to check and what some of
// Assimp's readers do not (they can loop forever or allocate without bound on such input).

#include <filesystem>

namespace cgamesh::io::detail {

/// Checks the structure of the text formats whose readers can hang (SMD: every section ends
/// with "end"; MD5: braces balance) and the counts a header declares against the file's size
/// (PLY elements, MD5 joints, meshes, vertices, triangles and weights; GLB total and chunk
/// lengths), and in glTF's JSON the required extensions (refused when Assimp cannot decode them)
/// and the inverse bind matrices of each skin (one per joint).
/// @throws FileError naming the file, the problem and its line (or the extensions, or the skin).
void preflight(const std::filesystem::path& path);

}  // namespace cgamesh::io::detail
