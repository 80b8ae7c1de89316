#pragma once
// A bounding-volume hierarchy over the triangles of a placed (posed) mesh: the spatial index
// that lets surgery find the faces a plane, a scalpel or a drill touches without visiting the
// whole mesh.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::mesh {

/// Where a segment crosses a triangle.
struct SegmentHit {
  int face = -1;
  double t = 0;                     ///< segment parameter in [0, 1]: point = a + t (b - a)
  Eigen::Vector3d barycentric;      ///< weights of the face's three corners
};

class TriangleBvh {
 public:
  using Faces = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

  TriangleBvh() = default;
  /// Builds the tree (median splits along the longest axis, up to 4 faces per leaf).
  /// @param[in] positions  #V×3 placed vertex positions
  /// @param[in] faces      #F×3 vertex indices
  /// @throws InvalidInputError for an index out of range or a non-finite position.
  TriangleBvh(const RowMatrixXf<3>& positions, const Faces& faces);

  [[nodiscard]] int face_count() const noexcept { return static_cast<int>(order_.size()); }
  /// Length of the diagonal of the box around every face (0 when empty).
  [[nodiscard]] double diagonal() const noexcept {
    return nodes_.empty() ? 0.0 : static_cast<double>((nodes_.front().hi - nodes_.front().lo).norm());
  }

  /// Appends to `out` every face whose bounding box meets the slab |n·x − d| ≤ tolerance: all
  /// faces the plane n·x = d may touch (and a few more).
  void faces_near_plane(const Eigen::Vector3d& n, double d, double tolerance, std::vector<int>& out) const;
  /// Appends to `out` every face whose bounding box meets the box [lo, hi].
  void faces_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>& out) const;
  /// Every face the closed segment [a, b] crosses, sorted by t (Möller–Trumbore in double).
  [[nodiscard]] std::vector<SegmentHit> segment_hits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;

 private:
  struct Node {
    Eigen::Vector3f lo, hi;
    std::int32_t first = 0;  ///< leaf: first index into order_; inner: right child (left is next)
    std::int32_t count = 0;  ///< faces in a leaf; 0 for an inner node
  };
  template <class Overlaps, class Visit>
  void traverse(Overlaps&& overlaps, Visit&& visit) const;
  int build(int begin, int end, std::vector<Eigen::Vector3f>& centroids);

  std::vector<Node> nodes_;
  std::vector<int> order_;                 ///< face indices in leaf order
  std::vector<Eigen::Vector3f> corners_;   ///< 3 per face, by face index
};

}  // namespace cgamesh::mesh
