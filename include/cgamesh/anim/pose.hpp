#pragma once
// Sampling clips into poses, user edits on top, and global joint transforms (paper sections 3
// and 4.1: t_{i,k} = T R S, M_{n,k} composed down the hierarchy).

#include <span>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/clip.hpp"
#include "cgamesh/anim/skeleton.hpp"
#include "cgamesh/anim/transform.hpp"
#include "cgamesh/cga/multivector.hpp"

namespace cgamesh::anim {

/// How keys are blended between key times.
enum class BlendMode {
  format,  ///< what the file says: glTF LINEAR lerps translation/scale and slerps rotation; STEP; CUBICSPLINE
  linear,  ///< linear blend of the key versors, renormalised (paper: generated keyframes)
  log      ///< logarithmic blend m1 exp(a log(m1^-1 m2)) (paper: file keyframes)
};

/// Local transform of every joint, as TRS and as versor (the same transform; the versor has the
/// geometric-mean scale when the TRS scale is non-uniform).
struct Pose {
  std::vector<Transform> local;
  std::vector<cga::Versor<double>> local_versors;
  /// Per joint, the morph weights a clip gives the meshes on that joint; empty (or an empty
  /// entry): their default weights (Mesh::morph_weights). See morph_weights().
  std::vector<std::vector<float>> morph_weights;
};

/// A user edit of one joint, applied in the joint's own frame after the clip:
/// L' = L T(translation) R(axis, angle) D(scale).
struct JointEdit {
  int joint = -1;
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double angle = 0;  ///< radians
  double scale = 1;  ///< uniform, relative to the parent bone; > 0
};

/// The rest (bind) pose.
[[nodiscard]] Pose rest_pose(const Skeleton& skeleton);

/// Samples `clip` at `time` seconds (clamped to [0, duration]); joints without channels keep
/// their rest transform.
/// @throws InvalidInputError for a channel on a joint outside the skeleton, or a NaN time.
[[nodiscard]] Pose sample(const Skeleton& skeleton, const Clip& clip, double time, BlendMode mode);

/// Applies user edits on top of a pose.
/// @throws InvalidInputError for an unknown joint, a zero axis with non-zero angle, or scale <= 0.
void apply_edits(Pose& pose, std::span<const JointEdit> edits);

/// Global versors M_n = M_parent L_n (eq. 14 composition), one per joint. A joint at or below a
/// non-uniform local scale has no versor: it gets the one nearest its exact global matrix (that
/// matrix's polar rotation and volume-keeping scale; the matrix itself when it is a similarity),
/// and cga skinning uses the exact matrix instead (make_palette()).
[[nodiscard]] std::vector<cga::Versor<double>> global_versors(const Skeleton& skeleton, const Pose& pose);
/// Global matrices (exact TRS, the matrix pipeline), one per joint.
[[nodiscard]] std::vector<Eigen::Matrix4d> global_matrices(const Skeleton& skeleton, const Pose& pose);

}  // namespace cgamesh::anim
