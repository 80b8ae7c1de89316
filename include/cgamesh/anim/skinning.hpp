#pragma once
// Skinning: posed world-space vertices from a skin and the global joint transforms.
// Four modes over the same data (paper section 4.1, eq. 16-17):
//   cga    - eq. (17): C[m] = sum_n w down((M_n B_n) c[m] (M_n B_n)^-1), each term down-projected
//            before summing. The sandwich by a fixed versor is a linear map (cga/point_map.hpp),
//            built once per joint and frame, so the per-vertex cost is that of matrix LBS.
//   versor - blend the versors sum_n w (M_n B_n), renormalise, one sandwich: the CGA analogue of
//            dual-quaternion skinning, which also carries dilations.
//   matrix - 4x4 linear blend skinning (eq. 16), the baseline.
//   dqs    - dual-quaternion skinning, the baseline; joint scale and shear are blended linearly
//            and applied first (Kavan et al. 2008), so scaled rigs keep their size.
// A joint map M_n B_n that is no similarity (non-uniform scale or shear in a joint's global
// matrix or inverse bind) has no versor: cga takes its exact matrix, so cga and matrix are exact
// on any rig; versor and dqs approximate such rigs (exact_displacement() says by how much).

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"

namespace cgamesh::detail {
struct PackedPalette;
}  // namespace cgamesh::detail

namespace cgamesh::anim {

enum class SkinningMode { cga, versor, matrix, dqs };

/// Which code runs the per-vertex work. Every kernel computes the same thing (tested equal to
/// `scalar` within float rounding); `automatic` takes the fastest the processor has.
///   scalar - one vertex at a time, the reference.
///   vector - blocks of 8 vertices laid out across vector lanes (structure of arrays), built
///            for the baseline x86-64 instruction set (SSE2): runs on any x86-64.
///   avx2   - the same blocks compiled for AVX2 and FMA, chosen at run time when present.
///   avx512 - the same blocks compiled for AVX-512 (F, VL, DQ, BW) on 256-bit vectors: twice the
///            registers of avx2, no 512-bit instruction (so no clock slowdown); chosen at run
///            time when present.
enum class SkinningKernel { automatic, scalar, vector, avx2, avx512 };

/// True when `kernel` can run on this processor (`automatic`, `scalar`, `vector`: always).
[[nodiscard]] bool kernel_available(SkinningKernel kernel) noexcept;

/// How the `vector`, `avx2` and `avx512` kernels write the skinned rows (`scalar` always caches).
///   automatic - streaming when a frame moves more than streaming_bytes() (48 bytes a vertex
///               read and written, 24 more with normals), caching otherwise.
///   caching   - ordinary stores: the rows stay in the cache for whoever reads them next.
///   streaming - non-temporal stores: the rows go straight to memory, without the processor
///               first reading the lines they overwrite (on a mesh far larger than the caches
///               that read is a fifth of a frame's memory traffic).
enum class SkinningStores { automatic, caching, streaming };

/// streaming_bytes() when the system does not report its caches: more than the last-level cache
/// of most processors holds.
inline constexpr std::size_t kStreamingBytes = std::size_t{32} << 20;

/// A frame's bytes from which `automatic` streams: the size of the last-level cache as the
/// system reports it (a frame larger than that cannot stay in it, so caching its rows only costs
/// the reads of the lines they overwrite), else kStreamingBytes. Virtual machines may report a
/// large share of the host's cache: then larger frames stay cached, as measured there.
[[nodiscard]] std::size_t streaming_bytes() noexcept;

/// How skin() and skin_into() split and run the work.
struct SkinningOptions {
  int threads = 0;  ///< threads to split over (0: all hardware threads; small meshes run inline)
  SkinningKernel kernel = SkinningKernel::automatic;
  SkinningStores stores = SkinningStores::automatic;
};

/// What one frame's skinning of one mesh needs per palette entry (built per frame, small):
/// make_palette() builds it.
struct SkinningPalette {
  SkinningMode mode = SkinningMode::cga;
  std::vector<Eigen::Matrix<float, 3, 4>> affine;      ///< cga, matrix: x -> A x + b
  std::vector<cga::Versor<float>> versors;             ///< versor: M_n B_n
  std::vector<cga::Motor<float>> motors;               ///< versor, when no joint dilates: M_n B_n
  std::vector<Eigen::Matrix<float, 8, 1>> dual_quats;  ///< dqs: real (x y z w), dual (x y z w)
  /// dqs: scale/shear S_n of each M_n B_n = [R t] S_n, applied before the dual quaternions
  /// (Kavan et al. 2008, two-phase skinning); empty when every joint is rigid.
  std::vector<Eigen::Matrix3f> scales;
  /// The mesh's morph-target weights this frame (morph_weights()), applied to the rest mesh
  /// before skinning in every mode (glTF's order); empty or all 0: the rest mesh as it is.
  std::vector<float> morph_weights;

 private:
  // The entries above in the vector kernels' layout, built by make_palette(): the kernels'
  // business alone (layout and access in src/anim/packed_palette.hpp).
  friend struct detail::PackedPalette;
  std::vector<float> packed_;
  int packed_stride_ = 0;
};

/// Builds the palette of `mesh` for one frame. A mesh without a skin follows its node.
/// @param[in] globals_cga     #joints global versors M_n (global_versors())
/// @param[in] globals_matrix  #joints global matrices (global_matrices()); used by matrix/dqs,
///                            and by cga for the entries that are no similarity
/// @param[in] morph_weights   empty, or #targets weights of the mesh's morph targets
///                            (morph_weights(pose, mesh))
/// @throws InvalidInputError when a palette entry names a joint outside the spans, or as
///         check_morph_weights().
[[nodiscard]] SkinningPalette make_palette(const mesh::Mesh& mesh, std::span<const cga::Versor<double>> globals_cga,
                                           std::span<const Eigen::Matrix4d> globals_matrix, SkinningMode mode,
                                           std::span<const float> morph_weights = {});

/// Whether every palette entry of `mesh` maps by a similarity at this pose: the global matrices
/// of its joints and its inverse binds have no non-uniform scale or shear (to
/// kUniformScaleTolerance). Otherwise cga and matrix skinning stay exact, versor and dqs
/// approximate.
/// @param[in] globals_matrix  #joints global matrices (global_matrices())
/// @throws InvalidInputError when a palette entry names a joint outside globals_matrix.
[[nodiscard]] bool maps_by_similarities(const mesh::Mesh& mesh, std::span<const Eigen::Matrix4d> globals_matrix);

/// The largest distance, in model units, from a row of `positions` to the same vertex skinned
/// exactly at the pose of `globals_matrix` (matrix mode; cga gives the same): how far versor or
/// dqs skinning puts a rig that is not made of similarities (maps_by_similarities()). The blend
/// counts too: on any rig versor and dqs blend otherwise than linearly, by design.
/// @param[in] globals_matrix  #joints global matrices (global_matrices())
/// @param[in] positions       #V×3 posed positions of `mesh` (skin() in any mode)
/// @param[in] morph_weights   the morph weights `positions` were skinned with
/// @throws InvalidInputError when `positions` does not have #V rows, or as make_palette().
[[nodiscard]] double exact_displacement(const mesh::Mesh& mesh, std::span<const Eigen::Matrix4d> globals_matrix,
                                        const mesh::RowMatrixXf<3>& positions,
                                        std::span<const float> morph_weights = {});

/// Skins vertices [begin, end) of `mesh` into the same rows of `positions` (#V×3) and, when
/// `normals` is not null, its normals into the rows of `*normals` (#V×3; as skin_normals()):
/// one job, on the calling thread.
/// @throws InvalidInputError when `kernel` cannot run here (kernel_available()), [begin, end) is
///         not inside [0, #V], `positions` (or `normals`, or the mesh's normals, when normals are
///         asked for) does not have #V rows, or the palette is not one made for this mesh (its
///         entry count differs). Nothing is written then.
void skin_range(const mesh::Mesh& mesh, const SkinningPalette& palette, Eigen::Index begin, Eigen::Index end,
                mesh::RowMatrixXf<3>& positions, mesh::RowMatrixXf<3>* normals = nullptr,
                SkinningKernel kernel = SkinningKernel::automatic, SkinningStores stores = SkinningStores::automatic);

/// Skins every vertex into caller-owned arrays, resized when their row count differs: a
/// renderer that keeps them from frame to frame allocates nothing per frame.
/// @param[out] positions  #V×3 posed positions
/// @param[out] normals    null, or #V×3 posed unit normals (as skin_normals(); 0 rows when the
///                        mesh has none), skinned in the same pass as the positions
/// @throws InvalidInputError when the mesh's normals are neither 0 nor #V rows, or `kernel`
///         cannot run here.
void skin_into(const mesh::Mesh& mesh, const SkinningPalette& palette, mesh::RowMatrixXf<3>& positions,
               mesh::RowMatrixXf<3>* normals = nullptr, const SkinningOptions& options = {});

/// Skins every vertex, split into jobs over `threads` threads (0: all hardware threads).
[[nodiscard]] mesh::RowMatrixXf<3> skin(const mesh::Mesh& mesh, const SkinningPalette& palette, int threads = 0);

/// The blended map Σ wₙ Aₙ of vertex i as one affine x ↦ A x + b (3×4): what eq. (17) does to
/// that vertex (morphed, when the palette has morph weights) in a `cga` or `matrix` palette (a
/// static mesh: its node's map).
/// @param[in] palette  make_palette(mesh, ...) in mode cga or matrix
/// @param[in] i        vertex index, 0 <= i < #V
[[nodiscard]] Eigen::Matrix<double, 3, 4> blended_affine(const mesh::Mesh& mesh, const SkinningPalette& palette,
                                                         Eigen::Index i);

/// Skinned unit normals of every vertex (#V×3; 0 rows when the mesh has no normals), turned by
/// the linear part of each vertex's blended transform: cga, matrix — the cofactor of Σ w Aₙ
/// (exact for any invertible map, non-uniform scale included); versor — the blended versor's
/// sandwich of the Euclidean vector n (a dilator leaves directions unchanged); dqs — the
/// cofactor of the blended scale, then the blended rotation. A degenerate result (zero blended map) keeps the rest
/// normal.
/// The positions are skinned in the same pass and dropped: to have both, call skin_into().
/// @param[in] palette  make_palette(mesh, ...) in any mode
[[nodiscard]] mesh::RowMatrixXf<3> skin_normals(const mesh::Mesh& mesh, const SkinningPalette& palette,
                                                int threads = 0);

/// Eq. (17) written literally, one sandwich and down-projection per vertex and influence, in
/// double: the reference the fast modes are tested against (slow). Versors only: on a rig that
/// is not made of similarities it approximates as versor skinning does. No morph targets.
[[nodiscard]] mesh::RowMatrixXf<3> skin_cga_reference(const mesh::Mesh& mesh,
                                                      std::span<const cga::Versor<double>> globals_cga);

}  // namespace cgamesh::anim
