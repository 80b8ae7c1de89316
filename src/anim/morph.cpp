#include "cgamesh/anim/morph.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cgamesh/errors.hpp"

namespace cgamesh::anim {

std::span<const float> morph_weights(const Pose& pose, const mesh::Mesh& mesh) noexcept {
  if (mesh.node >= 0 && static_cast<std::size_t>(mesh.node) < pose.morph_weights.size()) {
    const std::vector<float>& w = pose.morph_weights[static_cast<std::size_t>(mesh.node)];
    if (!w.empty() && w.size() == mesh.morph_targets.size()) return w;
  }
  return mesh.morph_weights;
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

mesh::Mesh morphed(const mesh::Mesh& mesh, std::span<const float> weights) {
  check_morph_weights(mesh, weights);
  mesh::Mesh out = mesh;
  out.morph_targets.clear();
  out.morph_weights.clear();
  bool normals_move = false;
  for (std::size_t k = 0; k < weights.size(); ++k) {
    if (weights[k] == 0) continue;
    const mesh::MorphTarget& t = mesh.morph_targets[k];
    out.positions += weights[k] * t.positions;
    if (t.normals.rows() > 0 && out.normals.rows() > 0) {
      out.normals += weights[k] * t.normals;
      normals_move = true;
    }
  }
  if (normals_move)
    for (Eigen::Index v = 0; v < out.normals.rows(); ++v) {
      const float n = out.normals.row(v).norm();
      out.normals.row(v) = n > 0 ? Eigen::RowVector3f(out.normals.row(v) / n) : mesh.normals.row(v);
    }
  return out;
}

}  // namespace cgamesh::anim
