#include "cgamesh/io/file_extension.hpp"

#include "lower_case.hpp"

namespace cgamesh::io {

std::string lower_extension(const std::filesystem::path& path) { return detail::lower(path.extension().string()); }

}  // namespace cgamesh::io
