#pragma once
// A model's surface in world space, as a static file (OBJ, PLY) holds it.

#include <vector>

#include "cgamesh/mesh/row_array.hpp"

namespace cgamesh::mesh {

/// Per mesh of a model, #V×3 world positions and #V×3 normals (or 0 rows, or no matrices at
/// all: no normals).
struct WorldSurface {
  std::vector<RowMatrixXf<3>> positions;
  std::vector<RowMatrixXf<3>> normals;
};

}  // namespace cgamesh::mesh
