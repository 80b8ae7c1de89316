#pragma once
// Private to the I/O module: the one bound on text from a file or a reader that a message
// quotes (Assimp's parse errors can quote the rest of the file: 34 kB for one .x file).

#include <cstddef>
#include <string>
#include <string_view>

namespace cgamesh::io::detail {

/// The most bytes of quoted text a message holds.
inline constexpr std::size_t kExcerptBytes = 200;

/// `text` itself when it has at most kExcerptBytes bytes, else its first kExcerptBytes (not
/// splitting a UTF-8 character) followed by "… (N more bytes)".
[[nodiscard]] inline std::string excerpt(std::string_view text) {
  if (text.size() <= kExcerptBytes) return std::string(text);
  std::size_t cut = kExcerptBytes;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return std::string(text.substr(0, cut)) + "… (" + std::to_string(text.size() - cut) + " more bytes)";
}

}  // namespace cgamesh::io::detail
