#include "cgamesh/io/model_info.hpp"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/io/text_values.hpp"

namespace cgamesh::io {
namespace {

using Json = nlohmann::ordered_json;

void add(InfoBox& box, const mesh::RowMatrixXf<3>& p) {
  if (p.rows() == 0) return;
  box.min = box.min.cwiseMin(p.colwise().minCoeff().transpose());
  box.max = box.max.cwiseMax(p.colwise().maxCoeff().transpose());
}

Json vec_json(const Eigen::Vector3f& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json box_json(const InfoBox& b) { return {{"min", vec_json(b.min)}, {"max", vec_json(b.max)}}; }

}  // namespace

std::vector<std::vector<int>> joint_skins(const anim::RiggedModel& model) {
  const anim::Skeleton& sk = model.skeleton;
  std::vector<std::vector<int>> skins(static_cast<std::size_t>(sk.size()));
  for (std::size_t i = 0; i < model.meshes.size(); ++i)
    for (const int j : model.meshes[i].skin.palette)
      if (j >= 0 && j < sk.size()) skins[static_cast<std::size_t>(j)].push_back(static_cast<int>(i));
  return skins;
}

long skinned_joint_count(const anim::RiggedModel& model) {
  const auto skins = joint_skins(model);
  return std::count_if(skins.begin(), skins.end(), [](const auto& m) { return !m.empty(); });
}

long morph_weight_channels(const anim::Clip& clip) {
  return std::count_if(clip.channels.begin(), clip.channels.end(),
                       [](const anim::Channel& ch) { return ch.path == anim::ChannelPath::weights; });
}

ModelInfo model_info(const anim::RiggedModel& model) {
  const anim::Skeleton& sk = model.skeleton;
  const auto rest = posed_positions(model, anim::rest_pose(sk), anim::SkinningMode::matrix);
  ModelInfo info;
  info.skins = joint_skins(model);
  info.skinned_joints = skinned_joint_count(model);
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    info.vertices += m.vertex_count();
    info.triangles += m.face_count();
    MeshInfo mi;
    add(mi.box, rest[i]);
    add(mi.box_mesh_space, m.positions);
    add(info.box, rest[i]);
    info.meshes.push_back(mi);
  }
  return info;
}

std::string model_info_json(const anim::RiggedModel& model, const ModelInfo& info, const std::string& file) {
  const anim::Skeleton& sk = model.skeleton;
  Json meshes = Json::array();
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    Json targets = Json::array();
    for (std::size_t k = 0; k < m.morph_targets.size(); ++k)
      targets.push_back({{"name", m.morph_targets[k].name},
                         {"default_weight", k < m.morph_weights.size() ? m.morph_weights[k] : 0.0f},
                         {"normals", m.morph_targets[k].normals.rows() > 0}});
    meshes.push_back({{"name", m.name},
                      {"morph_targets", targets},
                      {"vertices", m.vertex_count()},
                      {"triangles", m.face_count()},
                      {"skinned", !m.skin.empty()},
                      {"skinned_joints", m.skin.palette.size()},
                      {"bounding_box", box_json(info.meshes[i].box)},
                      {"bounding_box_mesh_space", box_json(info.meshes[i].box_mesh_space)}});
  }
  Json skeleton = Json::array();
  for (int j = 0; j < sk.size(); ++j) {
    const int p = sk.parents()[j];
    skeleton.push_back({{"index", j},
                        {"name", sk.names()[j]},
                        {"parent", p},
                        {"parent_name", p < 0 ? Json(nullptr) : Json(sk.names()[p])},
                        {"skins", info.skins[static_cast<std::size_t>(j)]}});
  }
  Json clips = Json::array();
  for (std::size_t c = 0; c < model.clips.size(); ++c)
    clips.push_back({{"index", c},
                     {"name", model.clips[c].name},
                     {"duration", model.clips[c].duration},
                     {"morph_weight_channels", morph_weight_channels(model.clips[c])}});
  const Json out = {{"file", file},
                    {"pose", {{"kind", "bind"}}},
                    {"meshes", meshes},
                    {"vertices", info.vertices},
                    {"triangles", info.triangles},
                    {"nodes", sk.size()},
                    {"skinned_joints", info.skinned_joints},
                    {"skeleton", skeleton},
                    {"animations", clips},
                    {"max_influences", model.source_max_influences},
                    {"bounding_box", box_json(info.box)},
                    {"warnings", model.warnings}};
  return out.dump(2, ' ', false, Json::error_handler_t::replace);
}

}  // namespace cgamesh::io
