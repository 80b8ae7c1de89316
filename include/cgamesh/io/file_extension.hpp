#pragma once
// The one way cgamesh reads a file's format from its name: the extension, lower-cased.

#include <filesystem>
#include <string>

namespace cgamesh::io {

/// The extension of `path` with its dot, in lower case (ASCII): "Man.GLB" -> ".glb"; "" for
/// none.
[[nodiscard]] std::string lower_extension(const std::filesystem::path& path);

}  // namespace cgamesh::io
