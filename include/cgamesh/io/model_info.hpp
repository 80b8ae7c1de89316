#pragma once
// What `cgamesh info` reports about a model: meshes, joint hierarchy, clips, bind-pose boxes and
// warnings. Built once here, so the CLI and the Python module (`Model.info()`) report the same.

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/rigged_model.hpp"

namespace cgamesh::io {

/// An axis-aligned box (min > max when it holds no point).
struct InfoBox {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(INFINITY);
  Eigen::Vector3f max = Eigen::Vector3f::Constant(-INFINITY);
};

struct MeshInfo {
  InfoBox box;             ///< world space, bind pose (matrix skinning)
  InfoBox box_mesh_space;  ///< the stored rest positions
};

struct ModelInfo {
  std::vector<MeshInfo> meshes;         ///< per mesh of the model
  long vertices = 0, triangles = 0;     ///< over all meshes
  std::vector<std::vector<int>> skins;  ///< per joint, the meshes whose palette holds it
  long skinned_joints = 0;              ///< joints that skin some mesh
  InfoBox box;                          ///< every mesh in the bind pose, world space
};

/// Per joint of `model`'s skeleton, the meshes whose skin palette holds it (ascending).
[[nodiscard]] std::vector<std::vector<int>> joint_skins(const anim::RiggedModel& model);

/// The joints of `model` that skin some mesh (a skeleton also holds the nodes above and beside
/// them: `nodes` counts those too).
[[nodiscard]] long skinned_joint_count(const anim::RiggedModel& model);

/// The channels of `clip` that animate morph weights.
[[nodiscard]] long morph_weight_channels(const anim::Clip& clip);

/// The summary of `model` (bind-pose boxes from matrix skinning, eq. 16).
[[nodiscard]] ModelInfo model_info(const anim::RiggedModel& model);

/// `info --json`'s document for `model` read from `file`, as indented JSON text (names that are
/// not UTF-8 get U+FFFD): file, pose, meshes (each with its skinned_joints: the size of its skin
/// palette), vertices, triangles, nodes, skinned_joints, skeleton, animations, max_influences,
/// bounding_box, warnings.
[[nodiscard]] std::string model_info_json(const anim::RiggedModel& model, const ModelInfo& info,
                                          const std::string& file);

}  // namespace cgamesh::io
