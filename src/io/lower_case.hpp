#pragma once
// Private to the I/O module: the one home of case folding for keywords (and, through
// io::lower_extension, file extensions).

#include <algorithm>
#include <cctype>
#include <string>

namespace cgamesh::io::detail {

/// `s` with ASCII letters in lower case.
[[nodiscard]] inline std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

}  // namespace cgamesh::io::detail
