#include "cgamesh/anim/morph.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cgamesh/errors.hpp"

namespace cgamesh::anim {

std::span<const float> morph_weights(const Pose& pose, const mesh::Mesh& mesh) noexcept {
  if (mesh.node >= 0 && static_cast<std::size_t>(mesh.node) < pose.morph_weights.size()) {
    const std::vector<float>& w = pose.morph_weights[static_cast<std::size_t>(mesh.node)];
    if (!w.empty() && w.size() == mesh.morph_targets.size()) return w;
  }
  return mesh.morph_weights;
}

void set_morph_weight(Pose& pose, const mesh::Mesh& mesh, std::size_t target, float weight) {
  if (target >= mesh.morph_targets.size())
    throw InvalidInputError("morph weights: mesh '" + mesh.name + "' has " + std::to_string(mesh.morph_targets.size()) +
                            " morph targets, no target " + std::to_string(target));
  if (!std::isfinite(weight))
    throw InvalidInputError("morph weights: the weight of '" + mesh.morph_targets[target].name + "' is NaN or infinite");
  if (mesh.node < 0)
    throw InvalidInputError("morph weights: mesh '" + mesh.name + "' hangs from no node, so a pose cannot weight it");
  const auto node = static_cast<std::size_t>(mesh.node);
  const std::span<const float> current = morph_weights(pose, mesh);
  std::vector<float> w(current.begin(), current.end());
  w.resize(mesh.morph_targets.size(), 0.0f);
  w[target] = weight;
  if (pose.morph_weights.size() <= node) pose.morph_weights.resize(node + 1);
  pose.morph_weights[node] = std::move(w);
}

void set_morph_weight(Pose& pose, std::span<const mesh::Mesh> meshes, std::string_view name, float weight) {
  bool found = false;
  std::string names;
  for (const mesh::Mesh& m : meshes)
    for (std::size_t k = 0; k < m.morph_targets.size(); ++k) {
      if (m.morph_targets[k].name == name) {
        set_morph_weight(pose, m, k, weight);
        found = true;
      }
      if (names.find("'" + m.morph_targets[k].name + "'") == std::string::npos)
        names += (names.empty() ? "" : ", ") + ("'" + m.morph_targets[k].name + "'");
    }
  if (!found)
    throw InvalidInputError("morph weights: no morph target is named '" + std::string(name) + "' (" +
                            (names.empty() ? std::string("the model has none") : "the model has " + names) + ")");
}

bool morphs(std::span<const float> weights) noexcept {
  return std::any_of(weights.begin(), weights.end(), [](float w) { return w != 0; });
}

void check_morph_weights(const mesh::Mesh& mesh, std::span<const float> weights) {
  if (!weights.empty() && weights.size() != mesh.morph_targets.size())
    throw InvalidInputError("morph weights: mesh '" + mesh.name + "' has " + std::to_string(mesh.morph_targets.size()) +
                            " morph targets, not " + std::to_string(weights.size()));
  for (const mesh::MorphTarget& t : mesh.morph_targets)
    if (t.positions.rows() != mesh.vertex_count() || (t.normals.rows() != 0 && t.normals.rows() != mesh.vertex_count()))
      throw InvalidInputError("morph weights: morph target '" + t.name + "' of mesh '" + mesh.name + "' has " +
                              std::to_string(t.positions.rows()) + " rows for " + std::to_string(mesh.vertex_count()) +
                              " vertices");
  for (std::size_t k = 0; k < weights.size(); ++k)
    if (!std::isfinite(weights[k]))
      throw InvalidInputError("morph weights: weight " + std::to_string(k) + " of mesh '" + mesh.name +
                              "' is NaN or infinite");
}

Eigen::Vector3f morph_offset(const mesh::Mesh& mesh, std::span<const float> weights, Eigen::Index v) {
  Eigen::Vector3f d = Eigen::Vector3f::Zero();
  for (std::size_t k = 0; k < weights.size() && k < mesh.morph_targets.size(); ++k)
    if (weights[k] != 0) d += weights[k] * mesh.morph_targets[k].positions.row(v).transpose();
  return d;
}

void morph_rows(const mesh::Mesh& mesh, std::span<const float> weights, Eigen::Index begin, Eigen::Index end,
                mesh::RowMatrixXf<3>& positions, mesh::RowMatrixXf<3>* normals) {
  check_morph_weights(mesh, weights);
  if (begin < 0 || begin > end || end > mesh.vertex_count())
    throw InvalidInputError("morph weights: vertex range [" + std::to_string(begin) + ", " + std::to_string(end) +
                            ") outside mesh '" + mesh.name + "' (" + std::to_string(mesh.vertex_count()) +
                            " vertices)");
  const Eigen::Index n = end - begin;
  positions = mesh.positions.middleRows(begin, n);
  if (mesh.normals.rows() == 0) normals = nullptr;
  if (normals) *normals = mesh.normals.middleRows(begin, n);
  bool normals_move = false;
  for (std::size_t k = 0; k < weights.size(); ++k) {
    if (weights[k] == 0) continue;
    const mesh::MorphTarget& t = mesh.morph_targets[k];
    positions += weights[k] * t.positions.middleRows(begin, n);
    if (normals && t.normals.rows() > 0) {
      *normals += weights[k] * t.normals.middleRows(begin, n);
      normals_move = true;
    }
  }
  if (normals_move)
    for (Eigen::Index r = 0; r < n; ++r) {
      const float len = normals->row(r).norm();
      normals->row(r) = len > 0 ? Eigen::RowVector3f(normals->row(r) / len) : mesh.normals.row(begin + r);
    }
}

}  // namespace cgamesh::anim
