#pragma once
// Private to the I/O module: the one home of case folding for keywords and file extensions.

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace cgamesh::io::detail {

/// `s` with ASCII letters in lower case.
[[nodiscard]] inline std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// The extension of `path` in lower case, with its dot (".glb"), or "".
[[nodiscard]] inline std::string lower_extension(const std::filesystem::path& path) {
  return lower(path.extension().string());
}

}  // namespace cgamesh::io::detail
