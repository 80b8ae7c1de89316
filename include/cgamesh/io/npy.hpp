#pragma once
// NumPy .npy files of float64 matrices (the format numpy.save writes and numpy.load reads), for
// arrays a user computes once and keeps, such as cage coordinates.

#include <filesystem>
#include <string>

#include <Eigen/Core>

namespace cgamesh::io {

/// Writes `values` as a .npy file: format 1.0, little-endian float64, C order, shape rows×cols.
/// Atomic (atomic_file.hpp).
/// @throws WriteError when the file cannot be written.
void write_npy(const std::filesystem::path& path, const Eigen::MatrixXd& values);

/// Reads a 2-D float64 .npy file in C order (format 1.0, 2.0 or 3.0).
/// @param[in] path  the file
/// @param[in] what  what the file holds, for messages ("coordinates")
/// @throws FileError "cannot read the WHAT PATH" when it cannot be read, or "WHAT PATH: ..." when it
///         is not a .npy file, not float64, not C order, not 2-D, or truncated.
[[nodiscard]] Eigen::MatrixXd read_npy(const std::filesystem::path& path, const std::string& what);

}  // namespace cgamesh::io
