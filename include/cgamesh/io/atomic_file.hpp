#pragma once
// All-or-nothing output files: every writer of cgamesh builds its bytes in memory, then hands
// them here. Each file is written to a temporary file in its target's directory (same file
// system), flushed to disk, and renamed onto the target; a set of files (a .gltf and its .bin)
// appears together or not at all.

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "cgamesh/errors.hpp"

namespace cgamesh::io {

/// One output file: where it goes and its whole content.
struct OutputFile {
  std::filesystem::path path;
  std::string_view bytes;
};

/// One encoded output file that owns its bytes (what a writer's encode_* function returns), so
/// several outputs (the two pieces of a cut) can be written together, all or nothing.
struct EncodedFile {
  std::filesystem::path path;
  std::string bytes;
};

/// Writes every file of `files` or none of them.
/// Each file first goes to a hidden temporary file `.NAME.tmp-XXXXXXXX` in its target's
/// directory and is fsync'ed; then the temporaries are renamed onto their targets in order.
/// If writing or renaming fails, every temporary file is removed and targets that were already
/// replaced get their previous content back (or are removed if they did not exist), so on an
/// exception the directories look as before. A target that is a symbolic link is replaced by
/// a regular file (the link's target is not written through).
/// @param[in] files  the files; their paths must differ
/// @throws WriteError when a file cannot be created, written or renamed (the message names the
///         path and the system error).
/// @throws InvalidInputError for an empty path, or the same path twice.
void write_files_atomically(std::span<const OutputFile> files);

/// write_files_atomically() for encoded files.
void write_files_atomically(std::span<const EncodedFile> files);

/// write_files_atomically() for one file.
/// @param[in] path   target path
/// @param[in] bytes  the whole content
/// @throws WriteError, InvalidInputError as write_files_atomically().
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace cgamesh::io
