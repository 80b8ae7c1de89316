#include "cgamesh/surgery/placement.hpp"

#include "cgamesh/anim/morph.hpp"

namespace cgamesh::surgery {

std::vector<anim::SkinningPalette> palettes(const anim::RiggedModel& model, const anim::Pose& pose) {
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  std::vector<anim::SkinningPalette> out;
  for (const mesh::Mesh& m : model.meshes)
    out.push_back(anim::make_palette(m, gv, gm, anim::SkinningMode::cga, anim::morph_weights(pose, m)));
  return out;
}

Placement place(const anim::RiggedModel& model, const anim::Pose& pose) {
  Placement out;
  out.palettes = palettes(model, pose);
  for (std::size_t i = 0; i < model.meshes.size(); ++i)
    out.positions.push_back(anim::skin(model.meshes[i], out.palettes[i]));
  return out;
}

std::vector<mesh::RowMatrixXf<3>> placed_normals(const anim::RiggedModel& model, const anim::Pose& pose) {
  const std::vector<anim::SkinningPalette> p = palettes(model, pose);
  std::vector<mesh::RowMatrixXf<3>> out;
  for (std::size_t i = 0; i < model.meshes.size(); ++i)
    out.push_back(model.meshes[i].normals.rows() > 0 ? anim::skin_normals(model.meshes[i], p[i])
                                                     : mesh::RowMatrixXf<3>(0, 3));
  return out;
}

}  // namespace cgamesh::surgery
