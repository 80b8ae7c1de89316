// Loads a rigged model, poses it half-way through its first clip, skins it with eq. (17), and
// checks a rotor sandwich against its rotation: what a first program against the package does.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <cgamesh/anim/pose.hpp>
#include <cgamesh/anim/skinning.hpp>
#include <cgamesh/cga/point_map.hpp>
#include <cgamesh/cga/versors.hpp>
#include <cgamesh/errors.hpp>
#include <cgamesh/io/model_loader.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer MODEL.glb\n");
    return 2;
  }
  try {
    using namespace cgamesh;
    const auto rotor = cga::rotor<double>(Eigen::Vector3d::UnitZ(), std::numbers::pi / 2);
    const Eigen::Vector3d x = cga::PointMap<double>(rotor).affine_matrix() * Eigen::Vector4d(1, 0, 0, 1);
    if ((x - Eigen::Vector3d::UnitY()).norm() > 1e-12) {
      std::fprintf(stderr, "a quarter turn about z took x to (%g, %g, %g)\n", x.x(), x.y(), x.z());
      return 1;
    }
    const anim::RiggedModel model = io::load_model(argv[1]);
    if (model.meshes.empty() || model.clips.empty()) {
      std::fprintf(stderr, "%s: no mesh or no clip\n", argv[1]);
      return 1;
    }
    const anim::Clip& clip = model.clips[0];
    const anim::Pose pose = anim::sample(model.skeleton, clip, 0.5 * clip.duration, anim::BlendMode::format);
    const mesh::Mesh& m = model.meshes[0];
    const auto palette = anim::make_palette(m, anim::global_versors(model.skeleton, pose),
                                            anim::global_matrices(model.skeleton, pose), anim::SkinningMode::cga);
    const mesh::RowMatrixXf<3> skinned = anim::skin(m, palette);
    if (skinned.rows() != m.vertex_count() || !skinned.allFinite()) return 1;
    std::printf("%s: %lld vertices skinned at t = %g, first at (%g, %g, %g)\n", argv[1],
                static_cast<long long>(skinned.rows()), 0.5 * clip.duration, skinned(0, 0), skinned(0, 1),
                skinned(0, 2));
    return 0;
  } catch (const cgamesh::Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 3;
  }
}
