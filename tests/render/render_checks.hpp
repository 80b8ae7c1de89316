#pragma once
// Checks on rendered pictures: silhouettes against a CPU projection of the same triangles.

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cgamesh/render/camera.hpp"
#include "cgamesh/render/image.hpp"
#include "cgamesh/render/scene.hpp"

namespace cgamesh_test {

/// width × height booleans, top row first.
struct Mask {
  int width = 0, height = 0;
  std::vector<char> on;

  [[nodiscard]] bool at(int x, int y) const { return on[static_cast<std::size_t>(y * width + x)] != 0; }
  [[nodiscard]] long count() const { return std::count(on.begin(), on.end(), 1); }
};

/// Pixels whose colour differs from `background` (RGB bytes) by more than `threshold` in sum.
inline Mask silhouette(const cgamesh::render::Image& im, const Eigen::Vector3i& background, int threshold = 60) {
  Mask m{im.width, im.height, std::vector<char>(static_cast<std::size_t>(im.width * im.height), 0)};
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const std::uint8_t* p = im.pixel(x, y);
      const int d = std::abs(p[0] - background.x()) + std::abs(p[1] - background.y()) + std::abs(p[2] - background.z());
      m.on[static_cast<std::size_t>(y * im.width + x)] = d > threshold ? 1 : 0;
    }
  return m;
}

/// The pixels whose centres the triangles of `meshes` (the faces for which keep(mesh, face)
/// holds) cover, projected on the CPU with the camera's matrices as OpenGL would.
template <class Keep>
Mask project(const std::vector<cgamesh::render::DrawMesh>& meshes, const cgamesh::render::Camera& camera, int width,
             int height, const cgamesh::render::Box& depth_box, Keep&& keep) {
  double near = 0, far = 0;
  cgamesh::render::depth_range(camera, depth_box, near, far);
  const Eigen::Matrix4d vp =
      cgamesh::render::projection_matrix(camera, static_cast<double>(width) / height, near, far) *
      cgamesh::render::view_matrix(camera);
  Mask m{width, height, std::vector<char>(static_cast<std::size_t>(width * height), 0)};
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto& d = meshes[i];
    std::vector<Eigen::Vector2d> win(static_cast<std::size_t>(d.positions.rows()));
    for (Eigen::Index v = 0; v < d.positions.rows(); ++v) {
      const Eigen::Vector4d c = vp * d.positions.row(v).transpose().cast<double>().homogeneous();
      // Window coordinates with y down (image rows).
      win[static_cast<std::size_t>(v)] = {(c.x() / c.w() + 1) / 2 * width, (1 - c.y() / c.w()) / 2 * height};
    }
    for (Eigen::Index f = 0; f < d.faces.rows(); ++f) {
      if (!keep(i, f)) continue;
      const Eigen::Vector2d a = win[static_cast<std::size_t>(d.faces(f, 0))],
                            b = win[static_cast<std::size_t>(d.faces(f, 1))],
                            c = win[static_cast<std::size_t>(d.faces(f, 2))];
      const auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
        return (q.x() - p.x()) * (r.y() - p.y()) - (q.y() - p.y()) * (r.x() - p.x());
      };
      const double area = edge(a, b, c);
      if (area == 0) continue;
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()})))),
                x1 = std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()})))),
                y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()})))),
                y1 = std::min(height - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const Eigen::Vector2d p(x + 0.5, y + 0.5);
          const double e0 = edge(b, c, p) / area, e1 = edge(c, a, p) / area, e2 = edge(a, b, p) / area;
          if (e0 >= 0 && e1 >= 0 && e2 >= 0) m.on[static_cast<std::size_t>(y * width + x)] = 1;
        }
    }
  }
  return m;
}

/// Intersection over union of two masks of one size.
inline double iou(const Mask& a, const Mask& b) {
  long both = 0, either = 0;
  for (std::size_t i = 0; i < a.on.size(); ++i) {
    both += a.on[i] && b.on[i];
    either += a.on[i] || b.on[i];
  }
  return either == 0 ? 1.0 : static_cast<double>(both) / static_cast<double>(either);
}

/// Columns and rows the mask touches: [x0, x1] × [y0, y1] (x0 > x1 when empty).
struct Extent {
  int x0, x1, y0, y1;
};
inline Extent extent(const Mask& m) {
  Extent e{m.width, -1, m.height, -1};
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x)
      if (m.at(x, y)) {
        e.x0 = std::min(e.x0, x);
        e.x1 = std::max(e.x1, x);
        e.y0 = std::min(e.y0, y);
        e.y1 = std::max(e.y1, y);
      }
  return e;
}

}  // namespace cgamesh_test
