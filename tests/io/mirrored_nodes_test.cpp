// Mirrored nodes (negative determinant): the loader pushes the reflection down the tree, so
// that every versor is even and world positions are the file's. The files are made here from
// shipped models by putting a mirroring root node above their scene (tinygltf), so the
// expected world positions are the original's, reflected.
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/text_values.hpp"

#include "anim/model_fixtures.hpp"
#include "support/gltf_edit.hpp"
#include "support/js_oracles.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;
namespace fs = std::filesystem;
using anim::SkinningMode;

// A reflection across x = 0 turned about z, with an offset: det = -1, no axis-aligned shortcut.
Eigen::Matrix4d mirror_matrix() {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix() * Eigen::Vector3d(-1, 1, 1).asDiagonal();
  m.topRightCorner<3, 1>() << 0.5, -0.25, 2;
  return m;
}

/// `in` (.glb) with a new root node holding `mirror` above every root of its scene.
fs::path with_mirror_root(const fs::path& in, const fs::path& out, const Eigen::Matrix4d& mirror) {
  tinygltf::Model m = cgamesh_test::read_glb(in);
  tinygltf::Node root;
  root.name = "mirror";
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) root.matrix.push_back(mirror(r, c));  // column-major
  tinygltf::Scene& scene = m.scenes[static_cast<std::size_t>(std::max(m.defaultScene, 0))];
  root.children = scene.nodes;
  m.nodes.push_back(root);
  scene.nodes = {static_cast<int>(m.nodes.size()) - 1};
  return cgamesh_test::write_glb(std::move(m), out);
}

/// World positions of every mesh, in `mode`.
std::vector<mesh::RowMatrixXf<3>> world(const anim::RiggedModel& model, const anim::Pose& pose, SkinningMode mode) {
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  std::vector<mesh::RowMatrixXf<3>> out;
  for (const mesh::Mesh& m : model.meshes) out.push_back(anim::skin(m, anim::make_palette(m, gv, gm, mode)));
  return out;
}

/// Six times the signed volume of a mesh: positive when its faces are wound outwards.
double signed_volume(const mesh::RowMatrixXf<3>& v, const mesh::Mesh& m) {
  double sum = 0;
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3d a = v.row(m.faces(f, 0)).cast<double>(), b = v.row(m.faces(f, 1)).cast<double>(),
                          c = v.row(m.faces(f, 2)).cast<double>();
    sum += a.dot(b.cross(c));
  }
  return sum;
}

void expect_reflected(const std::vector<mesh::RowMatrixXf<3>>& original, const std::vector<mesh::RowMatrixXf<3>>& got,
                      const Eigen::Matrix4d& mirror) {
  ASSERT_EQ(original.size(), got.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(original[i].rows(), got[i].rows());
    const double diag = (original[i].colwise().maxCoeff() - original[i].colwise().minCoeff()).norm();
    for (Eigen::Index v = 0; v < got[i].rows(); ++v) {
      const Eigen::Vector3d expected =
          mirror.topLeftCorner<3, 3>() * original[i].row(v).transpose().cast<double>() + mirror.topRightCorner<3, 1>();
      ASSERT_LE((got[i].row(v).transpose().cast<double>() - expected).norm(), 1e-5 * diag)
          << "mesh " << i << " v " << v;
    }
  }
}

// A static mesh under a mirroring node: world positions are the reflected ones, in every
// skinning mode, and its faces still face outwards (the loader reverses their winding).
TEST(MirroredNodes, StaticMeshBelowAMirrorKeepsWorldPositionsAndOutside) {
  cgamesh_test::TempDir dir;
  const anim::RiggedModel cow = io::load_model(cgamesh_test::asset("cow.obj"));
  (void)io::write_gltf(cow, dir / "cow.glb");
  const anim::RiggedModel plain = io::load_model(dir / "cow.glb");
  const anim::RiggedModel mirrored =
      io::load_model(with_mirror_root(dir / "cow.glb", dir / "mirrored.glb", mirror_matrix()));
  const anim::Pose rest = anim::rest_pose(plain.skeleton);
  const auto expected = world(plain, rest, SkinningMode::matrix);
  for (const SkinningMode mode : {SkinningMode::cga, SkinningMode::versor, SkinningMode::matrix, SkinningMode::dqs}) {
    SCOPED_TRACE(static_cast<int>(mode));
    const auto got = world(mirrored, anim::rest_pose(mirrored.skeleton), mode);
    expect_reflected(expected, got, mirror_matrix());
    EXPECT_GT(signed_volume(expected[0], plain.meshes[0]) * signed_volume(got[0], mirrored.meshes[0]), 0);
  }
}

// An animated, skinned model below a mirroring root: every joint's keys are conjugated, and
// the skin follows the reflected skeleton at every time, in every mode.
TEST(MirroredNodes, AnimatedSkinBelowAMirrorIsTheReflectedAnimation) {
  cgamesh_test::TempDir dir;
  const anim::RiggedModel plain = io::load_model(cgamesh_test::demo_model());
  const anim::RiggedModel mirrored =
      io::load_model(with_mirror_root(cgamesh_test::demo_model(), dir / "mirrored.glb", mirror_matrix()));
  ASSERT_FALSE(mirrored.clips.empty());
  for (const double t : {0.0, 0.5, 1.3}) {
    SCOPED_TRACE(t);
    const auto expected =
        world(plain, anim::sample(plain.skeleton, plain.clips[0], t, anim::BlendMode::format), SkinningMode::matrix);
    const anim::Pose pose = anim::sample(mirrored.skeleton, mirrored.clips[0], t, anim::BlendMode::format);
    for (const SkinningMode mode : {SkinningMode::cga, SkinningMode::matrix})
      expect_reflected(expected, world(mirrored, pose, mode), mirror_matrix());
  }
}

// The Blender .x exporter's root frame swaps Y and Z; the cube below it loaded as a failure.
TEST(MirroredNodes, DirectXRootFrameSwappingAxesLoads) {
  const fs::path x = cgamesh_test::assimp_model("X/test_cube_text.x");
  if (!fs::exists(x)) GTEST_SKIP() << "assimp-testmodels not installed";
  const anim::RiggedModel model = io::load_model(x);
  ASSERT_EQ(model.meshes.size(), 1u);
  const auto got = world(model, anim::rest_pose(model.skeleton), SkinningMode::cga);
  EXPECT_GT(signed_volume(got[0], model.meshes[0]), 0);  // a cube, wound outwards
  EXPECT_NEAR(got[0].cwiseAbs().maxCoeff(), 1.0, 1e-5);
}

/// Six times the signed volume of every face, and the share of faces whose winding agrees
/// with their corners' normals, as Assimp's own PreTransformVertices export of `file` holds them.
std::pair<double, double> assimp_pretransformed(const fs::path& file) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_PreTransformVertices);
  if (scene == nullptr) throw std::runtime_error(importer.GetErrorString());
  double volume = 0, agree = 0, faces = 0;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const aiMesh& m = *scene->mMeshes[i];
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3) continue;
      const aiVector3D a = m.mVertices[face.mIndices[0]], b = m.mVertices[face.mIndices[1]],
                       c = m.mVertices[face.mIndices[2]];
      volume += (a ^ b) * c;
      const aiVector3D n = m.mNormals[face.mIndices[0]] + m.mNormals[face.mIndices[1]] + m.mNormals[face.mIndices[2]];
      agree += ((b - a) ^ (c - a)) * n > 0 ? 1 : 0;
      ++faces;
    }
  }
  return {volume, agree / faces};
}

/// The share of faces of `m` posed at `v` whose winding agrees with their posed normals `n`.
double winding_agrees_with_normals(const mesh::RowMatrixXf<3>& v, const mesh::RowMatrixXf<3>& n, const mesh::Mesh& m) {
  double agree = 0;
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const Eigen::RowVector3f a = v.row(m.faces(f, 0)), b = v.row(m.faces(f, 1)), c = v.row(m.faces(f, 2));
    const Eigen::RowVector3f normal = n.row(m.faces(f, 0)) + n.row(m.faces(f, 1)) + n.row(m.faces(f, 2));
    agree += (b - a).cross(c - a).dot(normal) > 0 ? 1 : 0;
  }
  return agree / static_cast<double>(m.face_count());
}

// Blender's DirectX exporter puts a mirroring root frame (Y and Z swapped) above the skinned
// mesh and winds the mesh's faces for it, as its normals show: the surface comes out as Assimp's
// own pre-transformed export has it (outward, every face wound with its normals), at rest, in a
// glTF written from it and in what three.js poses from that glTF.
TEST(MirroredNodes, DirectXMeshWoundForItsMirrorComesOutAsAssimpExportsIt) {
  const fs::path x = fs::path(CGAMESH_TEST_ASSETS) / "testentities_lava_flan.x";
  const auto [assimp_volume, assimp_agree] = assimp_pretransformed(x);
  ASSERT_GT(assimp_volume, 0);
  ASSERT_EQ(assimp_agree, 1.0);

  const anim::RiggedModel model = io::load_model(x);
  ASSERT_EQ(model.meshes.size(), 1u);
  const io::PosedFrame frame = io::posed_frame(model, anim::rest_pose(model.skeleton), SkinningMode::cga);
  EXPECT_NEAR(signed_volume(frame.positions[0], model.meshes[0]), assimp_volume, 1e-4 * assimp_volume);
  EXPECT_EQ(winding_agrees_with_normals(frame.positions[0], frame.normals[0], model.meshes[0]), 1.0);

  cgamesh_test::TempDir dir;
  const fs::path glb = dir / "flan.glb";
  (void)io::write_gltf(model, glb);
  const anim::RiggedModel again = io::load_model(glb);
  const io::PosedFrame reloaded = io::posed_frame(again, anim::rest_pose(again.skeleton), SkinningMode::cga);
  EXPECT_NEAR(signed_volume(reloaded.positions[0], again.meshes[0]), assimp_volume, 1e-4 * assimp_volume);
  EXPECT_EQ(winding_agrees_with_normals(reloaded.positions[0], reloaded.normals[0], again.meshes[0]), 1.0);
  if (!cgamesh_test::three_available()) GTEST_SKIP() << "three.js oracle not installed";
  const nlohmann::json three = cgamesh_test::three_reference(glb, {0.0});
  const auto& p = three["meshes"][0]["posed"]["0"];
  mesh::RowMatrixXf<3> shown(static_cast<Eigen::Index>(p.size() / 3), 3);
  for (Eigen::Index i = 0; i < shown.rows(); ++i)
    for (Eigen::Index k = 0; k < 3; ++k) shown(i, k) = p[static_cast<std::size_t>(3 * i + k)].get<float>();
  EXPECT_NEAR(signed_volume(shown, again.meshes[0]), assimp_volume, 1e-4 * assimp_volume);
}

// A mirrored node that a clip rotates cannot be made proper by a fixed reflection: a clear
// error naming the node.
TEST(MirroredNodes, RotatedMirrorNodeIsAnErrorNamingIt) {
  cgamesh_test::TempDir dir;
  const fs::path file = with_mirror_root(cgamesh_test::demo_model(), dir / "mirrored.glb", mirror_matrix());
  tinygltf::Model m = cgamesh_test::read_glb(file);
  for (tinygltf::AnimationChannel& c : m.animations[0].channels)
    if (c.target_path == "rotation") {
      c.target_node = static_cast<int>(m.nodes.size()) - 1;  // the mirror root
      break;
    }
  (void)cgamesh_test::write_glb(std::move(m), dir / "rotated.glb");
  try {
    (void)io::load_model(dir / "rotated.glb");
    FAIL() << "loaded";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("node 'mirror' mirrors"), std::string::npos) << e.what();
  }
}

}  // namespace
