// write_model: the file a model becomes is chosen by its extension, the same for every front end.

#include "cgamesh/io/model_writer.hpp"

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/text_values.hpp"

#include "anim/model_fixtures.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;

TEST(ModelWriter, RiggedFormatsByExtensionInAnyCase) {
  for (const char* p : {"a.glb", "b.GLTF", "dir.x/c.Glb"}) EXPECT_TRUE(io::is_rigged_format(p)) << p;
  for (const char* p : {"a.obj", "b.ply", "glb", "a.glb.obj", "noext"}) EXPECT_FALSE(io::is_rigged_format(p)) << p;
}

TEST(ModelWriter, GltfKeepsTheRigAndAsksForNoSurface) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::demo_model());
  cgamesh_test::TempDir dir;
  int asked = 0;
  (void)io::write_model(m, dir.path() / "out.GLB", [&] {
    ++asked;
    return mesh::WorldSurface{};
  });
  EXPECT_EQ(asked, 0);
  const anim::RiggedModel back = io::load_model(dir.path() / "out.GLB");
  EXPECT_EQ(back.clips.size(), m.clips.size());
  EXPECT_EQ(back.meshes[0].vertex_count(), m.meshes[0].vertex_count());
  EXPECT_EQ(back.meshes[0].skin.palette.size(), m.meshes[0].skin.palette.size());
}

TEST(ModelWriter, ObjAndPlyHoldTheSurfaceGiven) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::demo_model());
  const anim::Pose pose = anim::sample(m.skeleton, m.clips[0], 1.0, anim::BlendMode::format);
  const io::PosedFrame frame = io::posed_frame(m, pose, anim::SkinningMode::cga);
  cgamesh_test::TempDir dir;
  for (const char* name : {"out.obj", "out.PLY"}) {
    (void)io::write_model(m, dir.path() / name, [&]() -> mesh::WorldSurface { return frame; });
    const anim::RiggedModel back = io::load_model(dir.path() / name);
    ASSERT_EQ(back.meshes.size(), 1u) << name;
    // The loader joins identical vertices: the boxes and the faces say the surface is the one given.
    const mesh::RowMatrixXf<3>& p = back.meshes[0].positions;
    EXPECT_LT((p.colwise().minCoeff() - frame.positions[0].colwise().minCoeff()).cwiseAbs().maxCoeff(), 1e-5f) << name;
    EXPECT_LT((p.colwise().maxCoeff() - frame.positions[0].colwise().maxCoeff()).cwiseAbs().maxCoeff(), 1e-5f) << name;
    EXPECT_EQ(back.meshes[0].face_count(), m.meshes[0].face_count()) << name;
  }
}

TEST(ModelWriter, AnotherExtensionIsRefusedAndNothingWritten) {
  const anim::RiggedModel m = io::load_model(cgamesh_test::demo_model());
  cgamesh_test::TempDir dir;
  for (const char* name : {"out.fbx", "out", "out.stl"}) {
    try {
      (void)io::write_model(m, dir.path() / name, [] { return mesh::WorldSurface{}; });
      ADD_FAILURE() << name << " was written";
    } catch (const InvalidInputError& e) {
      EXPECT_NE(std::string(e.what()).find(".glb, .gltf, .obj or .ply"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << name;
  }
}

}  // namespace
