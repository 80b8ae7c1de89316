#pragma once
// A triangle mesh with per-corner-split attributes and an optional skin.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/row_array.hpp"

namespace cgamesh::mesh {

/// Per-vertex skin weights: up to four (joint, weight) pairs per vertex.
/// Invariants after loading: weights >= 0, each row sums to 1, sorted by decreasing weight,
/// unused slots have weight 0 and joint 0.
struct Skin {
  /// #V x 4 indices into `palette`.
  RowArray<std::uint16_t, 4> joints;
  /// #V x 4 weights.
  RowMatrixXf<4> weights;
  /// #J skeleton joint index of each palette entry (glTF skin.joints, Assimp's bones).
  std::vector<int> palette;
  /// #J inverse bind matrices (mesh space -> joint space at bind time), as in the file.
  std::vector<Eigen::Matrix4d> inverse_bind;
  /// #J the same as versors B_n (paper eq. 17); geometric-mean scale where a matrix has
  /// non-uniform scale (the loader warns; cga skinning then uses `inverse_bind`).
  std::vector<cga::Versor<double>> inverse_bind_versors;

  [[nodiscard]] bool empty() const noexcept { return palette.empty(); }
};

/// One morph target (blend shape, glTF's mesh.primitives[].targets): displacements of the rest
/// mesh's vertices. At weight w the mesh is rest + w Δ, summed over its targets, before skinning
/// (the glTF order).
struct MorphTarget {
  std::string name;          ///< the file's name (glTF mesh.extras.targetNames); loaded unnamed: "target_K"
  RowMatrixXf<3> positions;  ///< #V x 3 displacement of each rest position
  RowMatrixXf<3> normals;    ///< #V x 3 displacement of each normal, or 0 rows
};

/// A triangle mesh. Vertices are never merged across seams: two vertices at the same place
/// with different joints, normals or UVs stay two. Its arrays keep spare capacity (RowArray), so
/// that surgery in place adds vertices and faces without copying the mesh.
struct Mesh {
  std::string name;
  RowMatrixXf<3> positions;  ///< #V x 3 rest (bind-pose) positions in mesh space
  RowMatrixXf<3> normals;    ///< #V x 3 unit normals, or 0 rows
  RowMatrixXf<2> uvs;        ///< #V x 2 texture coordinates (set 0; OpenGL's v = 0 at the image bottom), or 0 rows
  Faces faces;               ///< #F x 3 vertex indices
  /// #V 1 where an operation made the vertex (a point on an old edge or face: cut, tear, drill,
  /// subdivision), 0 where it comes from the file or is a copy of such a vertex; 0 rows when
  /// no operation made any. glTF files keep it as the attribute _CGAMESH_GENERATED.
  RowArray<std::uint8_t, 1> generated;
  /// #V the vertex's number in the file it was loaded from, so that messages and spec handles
  /// can use the numbers a user sees in other tools: glTF the accessor element, PLY the vertex
  /// element, OBJ the `v` line (from 0, so `f` index − 1). Vertices split from one file vertex
  /// (seams) share it; a vertex an operation made has −1, a copy keeps its origin's. 0 rows
  /// when the format's numbering is not known (Assimp gives one vertex per face corner for the
  /// others) — vertices are then named by their index here.
  RowArray<int, 1> file_index;
  Skin skin;  ///< empty for a static mesh
  /// Skeleton node the mesh hangs from, or -1: a static mesh is placed by it; a skinned mesh
  /// is placed by its joints alone, and its node is kept so that a written file keeps its tree.
  int node = -1;
  /// Morph targets, each with #V rows; a new vertex of an operation gets the blend of its
  /// sources' displacements, as its UVs.
  std::vector<MorphTarget> morph_targets;
  /// #targets default weights (glTF mesh.weights, or the node's): what a pose without a clip
  /// that animates them uses. Empty when the mesh has no targets.
  std::vector<float> morph_weights;
  int material = -1;  ///< index into RiggedModel::materials, or -1 (none)
  /// #F per-face material (index into RiggedModel::materials, or -1), for a mesh whose faces
  /// differ (surgery gives its caps and hole walls the cut-surface material); 0 rows when every
  /// face has `material`. glTF files keep it as one primitive per material.
  RowArray<int, 1> face_materials;

  [[nodiscard]] Eigen::Index vertex_count() const noexcept { return positions.rows(); }
  [[nodiscard]] Eigen::Index face_count() const noexcept { return faces.rows(); }
  /// The number by which messages name vertex v (0 <= v < #V): file_index[v] when the file's
  /// numbering is known and v has one, else v.
  [[nodiscard]] int vertex_label(Eigen::Index v) const noexcept {
    return file_index.rows() > 0 && file_index[v] >= 0 ? file_index[v] : static_cast<int>(v);
  }
  /// The material of face f (0 <= f < #F).
  [[nodiscard]] int face_material(Eigen::Index f) const noexcept {
    return face_materials.rows() > 0 ? face_materials[f] : material;
  }
  /// Makes room for `vertices` vertices and `faces` faces in all, so that growing to them copies
  /// no array: every per-vertex array the mesh has, `generated` and `face_materials` (which an
  /// operation may add) included.
  void reserve(Eigen::Index vertices, Eigen::Index faces_in_all) {
    const auto reserve_if_present = [](auto& rows, Eigen::Index n) {
      if (rows.rows() > 0) rows.reserve(n);
    };
    positions.reserve(vertices);
    reserve_if_present(normals, vertices);
    reserve_if_present(uvs, vertices);
    generated.reserve(vertices);
    reserve_if_present(file_index, vertices);
    reserve_if_present(skin.joints, vertices);
    reserve_if_present(skin.weights, vertices);
    for (MorphTarget& t : morph_targets) {
      t.positions.reserve(vertices);
      reserve_if_present(t.normals, vertices);
    }
    faces.reserve(faces_in_all);
    face_materials.reserve(faces_in_all);
  }
};

}  // namespace cgamesh::mesh
