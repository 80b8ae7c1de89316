#pragma once
// A bounding-volume hierarchy over the triangles of a placed (posed) mesh: the spatial index
// that lets surgery find the faces a plane, a scalpel or a drill touches without visiting the
// whole mesh.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::mesh {

/// Where a segment crosses a triangle.
struct SegmentHit {
  int face = -1;
  double t = 0;                 ///< segment parameter in [0, 1]: point = a + t (b - a)
  Eigen::Vector3d barycentric;  ///< weights of the face's three corners
};

class TriangleBvh {
 public:
  using Faces = mesh::Faces;

  TriangleBvh() = default;
  /// Builds the tree (median splits along the longest axis, up to 4 faces per leaf).
  /// @param[in] positions  #V×3 placed vertex positions
  /// @param[in] faces      #F×3 vertex indices
  /// @throws InvalidInputError for an index out of range or a non-finite position.
  TriangleBvh(const RowMatrixXf<3>& positions, const Faces& faces);

  [[nodiscard]] int face_count() const noexcept { return static_cast<int>(leaf_of_.size()); }
  /// Corners of the root box, around every face (after edits it may be larger: boxes only grow);
  /// meaningless when face_count() is 0.
  [[nodiscard]] Eigen::Vector3d lower() const noexcept {
    return nodes_.empty() ? Eigen::Vector3d::Zero().eval() : nodes_.front().lo.cast<double>().eval();
  }
  [[nodiscard]] Eigen::Vector3d upper() const noexcept {
    return nodes_.empty() ? Eigen::Vector3d::Zero().eval() : nodes_.front().hi.cast<double>().eval();
  }
  /// Length of the diagonal of the box around every face (0 when empty).
  [[nodiscard]] double diagonal() const noexcept {
    return nodes_.empty() ? 0.0 : static_cast<double>((nodes_.front().hi - nodes_.front().lo).norm());
  }

  /// Appends to `out` every face that meets the slab |n·x − d| ≤ tolerance (a corner in it, or
  /// corners on both sides): the faces the plane n·x = d crosses or comes within `tolerance` of.
  void faces_near_plane(const Eigen::Vector3d& n, double d, double tolerance, std::vector<int>& out) const;
  /// Appends to `out` every face whose bounding box meets the box [lo, hi].
  void faces_in_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<int>& out) const;
  /// Appends to `out` every face with a point within `radius` of the segment [a, b], and a few
  /// more: those whose bounding box passes two necessary tests (the box grown by `radius` meets
  /// the segment; the ball around the box comes within `radius` of it). What a capsule or a
  /// finite cylinder about the segment can touch, found in time proportional to the region.
  void faces_near_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius,
                          std::vector<int>& out) const;
  /// Every face the closed segment [a, b] crosses, sorted by t (Möller–Trumbore in double).
  [[nodiscard]] std::vector<SegmentHit> segment_hits(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;

  // Local edits, for surgery in place: each costs at most O(tree depth), so the tree follows an
  // edited mesh without a rebuild. Boxes only grow (a box that is too large costs a little time
  // in a query, never a face missed); the tree is not rebalanced.

  /// Room for `faces` faces in all without reallocating (append() grows the arrays otherwise).
  void reserve(int faces);
  /// Face `f` now has the placed corners `corners`.
  void replace(int f, const std::array<Eigen::Vector3f, 3>& corners);
  /// Adds a face with id face_count(), in the leaf of face `near` (a face next to it).
  void append(const std::array<Eigen::Vector3f, 3>& corners, int near);
  /// Removes face `f`; the last face takes its id (as a swap-remove of the face rows does).
  void erase(int f);

 private:
  struct Node {
    Eigen::Vector3f lo, hi;
    std::int32_t first = 0;  ///< leaf: first index into order_; inner: right child (left is next)
    std::int32_t count = 0;  ///< faces in a leaf; 0 for an inner node
  };
  /// Calls visit(f, corners) for every face f in a leaf whose box passes overlaps(lo, hi), with
  /// `corners` pointing at its 3 placed corners.
  template <class Overlaps, class Visit>
  void traverse(Overlaps&& overlaps, Visit&& visit) const;
  int build(int begin, int end, int parent, std::vector<Eigen::Vector3f>& centroids);
  /// Grows the boxes of `leaf` and its ancestors to hold `corners`.
  void grow(int leaf, const std::array<Eigen::Vector3f, 3>& corners);
  void set_corners(int f, const std::array<Eigen::Vector3f, 3>& corners);
  /// Points the neighbours of appended face f in its leaf's list (`previous`, `next`) at f.
  void link_appended(int f, int previous, int next);

  std::vector<Node> nodes_;
  std::vector<int> parent_;               ///< per node: its parent, −1 for the root
  std::vector<int> order_;                ///< face indices in leaf order; −1 for an erased face
  std::vector<Eigen::Vector3f> corners_;  ///< 3 per face, by face index
  /// 3 per slot of order_ (a copy of corners_ for the faces built into leaves): a leaf's corners
  /// lie side by side, so a query reads a few adjacent cache lines per leaf, not one per face.
  std::vector<Eigen::Vector3f> slot_corners_;
  std::vector<int> leaf_of_;  ///< per face: the leaf holding it
  std::vector<int> slot_of_;  ///< per face: its index in order_, or −1 when appended
  // Faces added after the build: per leaf a doubly linked list (checked after the leaf's faces
  // in order_), so that appending and erasing allocate nothing.
  std::vector<int> first_appended_;     ///< per node: its first appended face, or −1
  std::vector<int> next_appended_;      ///< per face: the next appended face of its leaf, or −1
  std::vector<int> previous_appended_;  ///< per face: the previous one, or −1 for the first
};

}  // namespace cgamesh::mesh
