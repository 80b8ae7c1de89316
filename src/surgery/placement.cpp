#include "cgamesh/surgery/placement.hpp"

namespace cgamesh::surgery {

Placement place(const anim::RiggedModel& model, const anim::Pose& pose) {
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  Placement out;
  for (const mesh::Mesh& m : model.meshes) {
    out.palettes.push_back(anim::make_palette(m, gv, gm, anim::SkinningMode::cga));
    out.positions.push_back(anim::skin(m, out.palettes.back()));
  }
  return out;
}

}  // namespace cgamesh::surgery
