#include "cgamesh/render/model_scene.hpp"

#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/material.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/placement.hpp"

#include "anim/model_fixtures.hpp"
#include "support/jpeg.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace render = cgamesh::render;
namespace anim = cgamesh::anim;
namespace surgery = cgamesh::surgery;

render::Scene scene_of(const anim::RiggedModel& model, const render::ModelSceneOptions& o,
                       std::vector<std::string>* w = nullptr) {
  const render::ModelInstance in{&model, anim::rest_pose(model.skeleton)};
  return render::model_scene(std::span(&in, 1), o, w);
}

bool near(const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return (a - b).norm() < 1e-5f; }

TEST(ModelScene, ColourModesFollowTheirData) {
  const auto model = cgamesh::io::load_model(cgamesh_test::demo_model());
  const cgamesh::mesh::Mesh& m = model.meshes[0];
  const int j = m.skin.palette[m.skin.joints(0, 0)];
  render::ModelSceneOptions o;
  o.color = render::ColorMode::joint;
  o.joint = model.skeleton.names()[static_cast<std::size_t>(j)];
  const render::Scene s = scene_of(model, o);
  ASSERT_EQ(s.meshes.size(), 1u);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    float w = 0;
    for (int k = 0; k < 4; ++k)
      if (m.skin.palette[m.skin.joints(v, k)] == j) w += m.skin.weights(v, k);
    ASSERT_TRUE(near(s.meshes[0].colors.row(v).transpose(), render::heat_color(w))) << v;
  }
  o.color = render::ColorMode::height;
  const render::Scene h = scene_of(model, o);
  Eigen::Index top = 0, bottom = 0;
  h.meshes[0].positions.col(1).maxCoeff(&top);
  h.meshes[0].positions.col(1).minCoeff(&bottom);
  EXPECT_TRUE(near(h.meshes[0].colors.row(top).transpose(), render::heat_color(1)));
  EXPECT_TRUE(near(h.meshes[0].colors.row(bottom).transpose(), render::heat_color(0)));
  o.color = render::ColorMode::normal;
  const render::Scene n = scene_of(model, o);
  EXPECT_TRUE(n.meshes[0].colors.isApprox(((n.meshes[0].normals.array() + 1) / 2).matrix()));
}

TEST(ModelScene, MaterialModeUsesTheBaseColourTexture) {
  const auto model = cgamesh::io::load_model(cgamesh_test::demo_model());
  // CesiumMan has one textured material (Assimp adds a default one after it).
  ASSERT_EQ(model.textures.size(), 1u);
  ASSERT_GE(model.meshes[0].material, 0);
  ASSERT_LT(model.meshes[0].material, static_cast<int>(model.materials.size()));
  EXPECT_EQ(model.materials[static_cast<std::size_t>(model.meshes[0].material)].base_color_texture, 0);
  EXPECT_EQ(model.textures[0].mime_type, "image/jpeg");
  std::vector<std::string> warnings;
  const render::Scene s = scene_of(model, {}, &warnings);
  EXPECT_TRUE(warnings.empty());
  ASSERT_TRUE(s.meshes[0].texture);
  EXPECT_GT(s.meshes[0].texture->width, 0);
  EXPECT_EQ(s.meshes[0].uvs.rows(), model.meshes[0].vertex_count());
  // A texture that does not decode is a warning, and the mesh is drawn without it.
  auto broken = model;
  broken.textures[0].bytes = std::make_shared<const std::vector<std::uint8_t>>(10, 7);
  const render::Scene b = scene_of(broken, {}, &warnings);
  EXPECT_FALSE(b.meshes[0].texture);
  ASSERT_EQ(warnings.size(), 1u) << warnings.back();
}

TEST(ModelScene, TexturesThatLibjpegRepairsAreDrawnWithItsWarning) {
  // CesiumMan's texture encoded progressive, with stray bytes before each scan (as "dwarf.jpg",
  // which browsers and Assimp's viewer show): the texture of a triangle in an OBJ.
  const auto cesium = cgamesh::io::load_model(cgamesh_test::demo_model());
  const render::Image source = render::decode_image(cesium.textures.at(0).data(), "CesiumMan");
  const std::vector<std::uint8_t> progressive = cgamesh_test::encode_jpeg(source, true);
  const std::vector<std::uint8_t> damaged = cgamesh_test::with_stray_bytes_before_scans(progressive, 4);
  const cgamesh_test::TempDir dir;
  std::ofstream(dir / "dwarf.jpg", std::ios::binary)
      .write(reinterpret_cast<const char*>(damaged.data()), static_cast<std::streamsize>(damaged.size()));
  std::ofstream(dir / "dwarf.mtl") << "newmtl skin\nKd 1 1 1\nmap_Kd dwarf.jpg\n";
  std::ofstream(dir / "dwarf.obj") << "mtllib dwarf.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                      "usemtl skin\nf 1/1 2/2 3/3\n";
  const auto model = cgamesh::io::load_model(dir / "dwarf.obj");
  ASSERT_EQ(model.textures.size(), 1u);
  std::vector<std::string> warnings;
  const render::Scene s = scene_of(model, {}, &warnings);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_TRUE(s.meshes[0].texture) << (warnings.empty() ? "" : warnings[0]);
  // The pixels of the undamaged file, and those are the source's within JPEG's loss.
  const render::Image& texture = *s.meshes[0].texture;
  EXPECT_EQ(texture.rgba, render::decode_image(progressive, "clean").rgba);
  ASSERT_EQ(texture.rgba.size(), source.rgba.size());
  double error = 0;
  for (std::size_t i = 0; i < source.rgba.size(); ++i) error += std::abs(int{texture.rgba[i]} - int{source.rgba[i]});
  EXPECT_LT(error / static_cast<double>(source.rgba.size()), 2.0);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].rfind("texture 'dwarf.jpg': Corrupt JPEG data: 4 extraneous bytes before marker 0xda", 0), 0u)
      << warnings[0];
}

TEST(ModelScene, MaterialModeDrawsTheCapsOfACutInTheCutSurfaceColour) {
  const auto model = cgamesh::io::load_model(cgamesh_test::demo_model());
  const surgery::Placement placed =
      surgery::place(model, anim::sample(model.skeleton, model.clips[0], 0.7, anim::BlendMode::format));
  const surgery::ModelCut c =
      surgery::cut(model, placed, cgamesh::cga::plane<double>({0.3, 1, 0.1}, 0.75), {.cap = true});
  ASSERT_GT(c.cap_triangles, 0);
  for (const anim::RiggedModel& piece : c.pieces) {
    const render::Scene s = scene_of(piece, {});
    Eigen::Index textured = 0, red = 0;
    for (const render::DrawMesh& d : s.meshes) {
      if (d.texture) textured += d.faces.rows();
      if (!d.texture && d.base_color.isApprox(cgamesh::mesh::cut_surface_material().base_color)) red += d.faces.rows();
    }
    Eigen::Index faces = 0;
    for (const auto& m : piece.meshes) faces += m.face_count();
    EXPECT_GT(red, 0);
    EXPECT_EQ(textured + red, faces);
  }
}

TEST(ModelScene, PiecesAndNewVerticesOfACutSurviveAGltfRoundTrip) {
  const auto model = cgamesh::io::load_model(cgamesh_test::demo_model());
  const auto placement = surgery::place(model, anim::rest_pose(model.skeleton));
  const surgery::ModelCut c = surgery::cut(model, placement, cgamesh::cga::plane<double>({0, 1, 0}, 0.9));
  cgamesh_test::TempDir dir;
  std::vector<anim::RiggedModel> read;
  for (int p = 0; p < 2; ++p) {
    const auto& mesh = c.pieces[static_cast<std::size_t>(p)].meshes[0];
    const auto& origins = c.origins[static_cast<std::size_t>(p)][0];
    ASSERT_EQ(mesh.generated.rows(), mesh.vertex_count());
    for (std::size_t v = 0; v < origins.size(); ++v)
      ASSERT_EQ(mesh.generated[static_cast<Eigen::Index>(v)], origins[v].count() > 1 ? 1 : 0) << v;
    const auto path = dir.path() / ("piece" + std::to_string(p) + ".glb");
    static_cast<void>(cgamesh::io::write_gltf(c.pieces[static_cast<std::size_t>(p)], path));
    read.push_back(cgamesh::io::load_model(path));
    EXPECT_EQ(read.back().meshes[0].generated, mesh.generated) << "piece " << p;
  }
  std::vector<render::ModelInstance> both;
  for (const auto& r : read) both.push_back({&r, anim::rest_pose(r.skeleton)});
  render::ModelSceneOptions o;
  o.color = render::ColorMode::piece;
  const render::Scene s = render::model_scene(both, o);
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_FALSE(near(s.meshes[0].colors.row(0).transpose(), s.meshes[1].colors.row(0).transpose()));
  o.color = render::ColorMode::generated;
  const render::Scene g = render::model_scene(both, o);
  std::set<std::array<float, 3>> colours;
  for (Eigen::Index v = 0; v < g.meshes[0].colors.rows(); ++v)
    colours.insert({g.meshes[0].colors(v, 0), g.meshes[0].colors(v, 1), g.meshes[0].colors(v, 2)});
  EXPECT_EQ(colours.size(), 2u) << "new and old vertices should take two colours";
}

TEST(ModelScene, SkeletonOverlayHasAJointPerSkinJoint) {
  const auto model = cgamesh::io::load_model(cgamesh_test::demo_model());
  render::ModelSceneOptions o;
  o.skeleton = true;
  const render::Scene s = scene_of(model, o);
  ASSERT_FALSE(s.points.empty());
  EXPECT_EQ(s.points.back().points.size(), model.meshes[0].skin.palette.size());
  ASSERT_FALSE(s.lines.empty());
  EXPECT_GT(s.lines.back().points.size(), 10u);
}

TEST(ModelScene, BadRequestsAreErrors) {
  const auto model = cgamesh::io::load_model(cgamesh_test::demo_model());
  render::ModelSceneOptions o;
  o.color = render::ColorMode::joint;
  o.joint = "no such joint";
  EXPECT_THROW(static_cast<void>(scene_of(model, o)), cgamesh::InvalidInputError);
  const render::ModelInstance null{nullptr, {}};
  EXPECT_THROW(static_cast<void>(render::model_scene(std::span(&null, 1), {})), cgamesh::InvalidInputError);
  std::string joint;
  EXPECT_EQ(render::parse_color_mode("joint:hip", joint), render::ColorMode::joint);
  EXPECT_EQ(joint, "hip");
  EXPECT_EQ(render::parse_color_mode("new", joint), render::ColorMode::generated);
  EXPECT_THROW(static_cast<void>(render::parse_color_mode("joint:", joint)), cgamesh::InvalidInputError);
  EXPECT_THROW(static_cast<void>(render::parse_color_mode("rainbow", joint)), cgamesh::InvalidInputError);
}

}  // namespace
