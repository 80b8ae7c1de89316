#pragma once
// Wavefront OBJ read line by line, for the files whose numbering matters: the positions of the
// `v` lines in file order and the polygons of the `f` lines (a cage whose vertices a spec indexes
// as written; the file vertices a loaded mesh is matched to). Models themselves are loaded
// through Assimp (model_loader.hpp).

#include <filesystem>
#include <string>

#include <Eigen/Core>

namespace cgamesh::io {

/// An OBJ's vertices and faces as written.
struct ObjPolygons {
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertices;  ///< #V×3, vertex j the file's j-th `v` line
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces;  ///< #F×3, 0-based; polygons fanned into triangles
};

struct ObjReadOptions {
  /// true: a malformed `v` or `f` line throws. false: a coordinate that cannot be read is NaN (the
  /// line keeps its place, so later lines keep their numbers) and `f` lines are not read.
  bool strict = true;
  std::string what = "OBJ";  ///< what the file is, for messages ("cage")
};

/// Reads `v x y z` and `f a b c ...` lines (indices 1-based or negative, counting back from the
/// last vertex so far; `a/t/n` forms accepted); other lines are ignored.
/// @param[in] path     the OBJ file
/// @param[in] options  strictness, and the file's name in messages
/// @throws FileError "cannot read the WHAT PATH" (also for a directory); strict: "WHAT PATH:LINE: ..."
///         for a `v` line without 3 finite numbers, an `f` index that is not a number or not a
///         vertex so far, or an `f` line of fewer than 3 corners.
[[nodiscard]] ObjPolygons read_obj(const std::filesystem::path& path, const ObjReadOptions& options = {});

}  // namespace cgamesh::io
