#pragma once
// What the renderer draws: placed triangle meshes with their colours, and overlays (lines and
// points). Plain data; the renderer owns no model logic (model_scene.hpp builds a Scene from a
// rigged model).

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/render/camera.hpp"
#include "cgamesh/render/image.hpp"

namespace cgamesh::render {

/// One placed triangle mesh.
struct DrawMesh {
  mesh::RowMatrixXf<3> positions;  ///< #V×3 world-space positions
  mesh::RowMatrixXf<3> normals;    ///< #V×3 world-space normals (smooth shading), or 0 rows (flat)
  mesh::RowMatrixXf<3> colors;     ///< #V×3 RGB in [0, 1] per vertex, or 0 rows (base colour)
  mesh::RowMatrixXf<2> uvs;        ///< #V×2 texture coordinates (OpenGL: v = 0 at the bottom), or 0 rows
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> faces;  ///< #F×3 vertex indices
  Eigen::Vector4f base_color{0.72f, 0.72f, 0.70f, 1.0f};         ///< multiplies colours and texture
  std::shared_ptr<const Image> texture;                          ///< base colour texture (with uvs), or null
};

/// Line segments drawn over the meshes (a skeleton, a tool outline).
struct LineSet {
  std::vector<Eigen::Vector3f> points;  ///< 2 × #segments world-space end points
  Eigen::Vector3f color{1, 1, 1};
  float width_pixels = 2;
  bool on_top = true;  ///< drawn without depth test, so hidden parts stay visible
};

/// Round dots drawn over the meshes (joints, picked points).
struct PointSet {
  std::vector<Eigen::Vector3f> points;  ///< world-space positions
  Eigen::Vector3f color{1, 1, 1};
  float size_pixels = 7;
  bool on_top = true;
};

struct Scene {
  std::vector<DrawMesh> meshes;
  std::vector<LineSet> lines;
  std::vector<PointSet> points;

  /// The box of every mesh vertex and overlay point.
  [[nodiscard]] Box bounds() const;
};

}  // namespace cgamesh::render
