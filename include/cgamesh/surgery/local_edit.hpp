#pragma once
// A local edit of one mesh — some faces replaced by new ones over old and new vertices: the
// form in which cut, tear and drill hand their work to a copy of the mesh or to a LiveModel
// (LiveModel::apply).

#include <array>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/mesh/vertex_source.hpp"

namespace cgamesh::surgery {

/// A local edit of one mesh: some old faces replaced by new faces over extended vertex ids
/// (old vertices 0 … #V−1, then the new vertices #V + i).
struct LocalEdit {
  std::vector<mesh::VertexSource> new_vertices;  ///< where each new vertex comes from (old mesh)
  std::vector<Eigen::Vector3d> new_placed;       ///< placed position of each new vertex
  /// Per new vertex: the side of a separation (cut or tear) it is a copy for, ±1, or 0. Copies
  /// for different sides never weld in the index, though they may share a rest position.
  std::vector<signed char> new_side;
  /// Per new vertex: its placed unit normal where it has one of its own (a hole's wall), else
  /// zero (blended from its origin like its other attributes).
  std::vector<Eigen::Vector3d> new_normal;
  /// Per new vertex: whether it lies off the input surface (a blind hole's wall), so that its
  /// rest position can only come from its placed one (always solved, whatever RestPosition).
  std::vector<char> new_off_surface;
  std::vector<int> removed_faces;             ///< old faces dropped (each once)
  std::vector<std::array<int, 3>> new_faces;  ///< over extended ids
  /// Per new face: the removed face it lies in, when every new face has one (it may fill that
  /// face's slot in place); empty otherwise.
  std::vector<int> new_face_parent;
  /// A new_face_origin entry for a face of a cut surface (a cap, a hole's wall).
  static constexpr int kCutSurface = -1;
  /// Per new face: the old face whose material it keeps (the one it lies in), or kCutSurface
  /// for a face that gets the cut-surface material (mesh::cut_surface_material_index). Empty:
  /// each new face keeps its new_face_parent's material, or without parents the mesh's.
  std::vector<int> new_face_origin;

  /// Adds a new vertex; returns its extended id.
  int add_vertex(const mesh::VertexSource& source, const Eigen::Vector3d& placed, int old_vertex_count,
                 signed char side = 0, const Eigen::Vector3d& normal = Eigen::Vector3d::Zero(),
                 bool off_surface = false) {
    new_vertices.push_back(source);
    new_placed.push_back(placed);
    new_side.push_back(side);
    new_normal.push_back(normal);
    new_off_surface.push_back(off_surface ? 1 : 0);
    return old_vertex_count + static_cast<int>(new_vertices.size()) - 1;
  }
};

}  // namespace cgamesh::surgery
