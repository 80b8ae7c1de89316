#pragma once
// A local edit of one mesh — some faces replaced by new ones over old and new vertices: the
// form in which cut, tear and drill hand their work to a copy of the mesh or to a LiveModel
// (LiveModel::apply).

#include <array>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/mesh/vertex_source.hpp"

namespace cgamesh::surgery {

/// A vertex that a LocalEdit adds.
struct NewVertex {
  mesh::VertexSource source;                         ///< where it comes from (old mesh)
  Eigen::Vector3d placed = Eigen::Vector3d::Zero();  ///< its placed position
  /// The side of a separation (cut or tear) it is a copy for, ±1, or 0. Copies for different
  /// sides never weld in the index, though they may share a rest position.
  signed char side = 0;
  /// Its placed unit normal where it has one of its own (a hole's wall), else zero (blended
  /// from its origin like its other attributes).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  /// Whether it lies off the input surface (a blind hole's wall), so that its rest position can
  /// only come from its placed one (always solved, whatever RestPosition).
  bool off_surface = false;
};

/// A local edit of one mesh: some old faces replaced by new faces over extended vertex ids
/// (old vertices 0 … #V−1, then the new vertices #V + i). Each new face is linked to an old
/// face in one of two ways, the same for all faces of an edit: the removed face it lies in
/// (add_face_in), or the old face whose material it keeps (add_face_from).
class LocalEdit {
 public:
  /// An origin for add_face_from: a face of a cut surface (a cap, a hole's wall), which gets the
  /// cut-surface material (mesh::cut_surface_material_index).
  static constexpr int kCutSurface = -1;

  /// Adds a new vertex; returns its extended id.
  /// @param[in] old_vertex_count  #V of the mesh the edit applies to
  int add_vertex(const NewVertex& vertex, int old_vertex_count) {
    vertices_.push_back(vertex);
    return old_vertex_count + static_cast<int>(vertices_.size()) - 1;
  }

  /// Removes old face `f` (each at most once).
  void remove_face(int f) { removed_.push_back(f); }

  /// Adds a new face over extended ids that lies in the removed face `parent`: it may fill that
  /// face's slot in place and keeps its material.
  /// @throws std::logic_error when the edit already has faces added by add_face_from.
  void add_face_in(const std::array<int, 3>& corners, int parent) { add_face(corners, parent, Link::parent); }

  /// Adds a new face over extended ids that keeps the material of old face `origin`, or that
  /// gets the cut-surface material for kCutSurface; it goes into the slot of a removed face
  /// near it.
  /// @throws std::logic_error when the edit already has faces added by add_face_in.
  void add_face_from(const std::array<int, 3>& corners, int origin) { add_face(corners, origin, Link::origin); }

  /// Sets corner `corner` (0 … 2) of new face `face` to extended id `x`.
  void set_corner(std::size_t face, std::size_t corner, int x) { faces_[face][corner] = x; }

  /// Sets the source of new vertex `k` (0 … #new vertices − 1).
  void set_source(std::size_t k, const mesh::VertexSource& source) { vertices_[k].source = source; }

  /// Makes room for `vertices` more new vertices and `faces` more new faces, so that adding
  /// them does not reallocate.
  void reserve(std::size_t vertices, std::size_t faces) {
    vertices_.reserve(vertices_.size() + vertices);
    faces_.reserve(faces_.size() + faces);
    links_.reserve(faces_.capacity());
  }

  /// The new vertices: extended id #V + i for entry i.
  [[nodiscard]] std::span<const NewVertex> new_vertices() const noexcept { return vertices_; }
  /// The old faces removed, in the order they were removed.
  [[nodiscard]] std::span<const int> removed_faces() const noexcept { return removed_; }
  /// The new faces, three extended ids each.
  [[nodiscard]] std::span<const std::array<int, 3>> new_faces() const noexcept { return faces_; }
  /// Per new face: the removed face it lies in (add_face_in); empty when the faces were added
  /// by add_face_from.
  [[nodiscard]] std::span<const int> new_face_parents() const noexcept {
    return link_ == Link::parent ? std::span<const int>(links_) : std::span<const int>();
  }
  /// Per new face: the old face whose material it keeps, or kCutSurface (add_face_from); empty
  /// when the faces were added by add_face_in: then each keeps its parent's material.
  [[nodiscard]] std::span<const int> new_face_origins() const noexcept {
    return link_ == Link::origin ? std::span<const int>(links_) : std::span<const int>();
  }

 private:
  /// What links_ holds: the kind of the first face added decides it for the edit.
  enum class Link : unsigned char { none, parent, origin };

  void add_face(const std::array<int, 3>& corners, int link, Link kind) {
    if (link_ != kind) {
      if (link_ != Link::none) throw std::logic_error("surgery: an edit's new faces mix parents and origins");
      link_ = kind;
    }
    faces_.push_back(corners);
    links_.push_back(link);
  }

  std::vector<NewVertex> vertices_;
  std::vector<int> removed_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<int> links_;  ///< per new face: its parent or its origin, as link_ says
  Link link_ = Link::none;
};

}  // namespace cgamesh::surgery
