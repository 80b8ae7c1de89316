// Materials and texture coordinates through surgery: CesiumMan cut with caps and drilled with
// walls (as copies and in place) keeps its textured material, the caps and walls get the
// cut-surface material (and only they), a written .glb embeds the texture image unchanged and
// gives the cut surface its own primitive; new vertices get texture coordinates blended like
// their weights.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/material.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/tear.hpp"

#include "anim/model_fixtures.hpp"
#include "support/temp_dir.hpp"
#include "surgery/surgery_fixtures.hpp"

namespace {

namespace fs = std::filesystem;
using namespace cgamesh;
using V3 = Eigen::Vector3d;

/// CesiumMan (one textured material) placed mid-animation, as the oracle tests place it.
class SurgeryMaterials : public ::testing::Test {
 protected:
  const anim::RiggedModel model_ = io::load_model(cgamesh_test::demo_model());
  const surgery::Placement placement_ =
      surgery::place(model_, anim::sample(model_.skeleton, model_.clips[0], 0.7, anim::BlendMode::format));
  const cga::Vector<double> plane_ = cga::plane<double>({0.3, 1, 0.1}, 0.75);

  void SetUp() override {
    ASSERT_EQ(model_.meshes.size(), 1u);
    ASSERT_GE(model_.meshes[0].material, 0);
    ASSERT_EQ(model_.textures.size(), 1u);
    ASSERT_EQ(material(model_, model_.meshes[0].material).base_color_texture, 0);
  }
  [[nodiscard]] V3 torso() const { return cgamesh_test::torso_centre(placement_.positions[0]); }

  static const mesh::Material& material(const anim::RiggedModel& m, int i) {
    return m.materials.at(static_cast<std::size_t>(i));
  }
  /// The faces of mesh `m` with the cut-surface material, as ids.
  static std::vector<Eigen::Index> cut_surface_faces(const anim::RiggedModel& model, const mesh::Mesh& m) {
    std::vector<Eigen::Index> out;
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      const int i = m.face_material(f);
      if (i >= 0 && material(model, i).name == mesh::kCutSurfaceMaterialName) out.push_back(f);
    }
    return out;
  }
  /// Every face not of the cut surface keeps CesiumMan's own material.
  void expect_other_faces_keep_the_model_material(const anim::RiggedModel& model, const mesh::Mesh& m) const {
    const std::vector<Eigen::Index> cut = cut_surface_faces(model, m);
    for (Eigen::Index f = 0; f < m.face_count(); ++f)
      if (!std::binary_search(cut.begin(), cut.end(), f)) {
        ASSERT_EQ(material(model, m.face_material(f)).name, material(model_, model_.meshes[0].material).name) << f;
        EXPECT_EQ(material(model, m.face_material(f)).base_color_texture, 0) << f;
      }
    ASSERT_EQ(model.textures.size(), model_.textures.size());
    EXPECT_EQ(model.textures[0].bytes, model_.textures[0].bytes) << "the image is shared, not copied";
  }

  /// Writes `model` as .glb and checks the file with tinygltf: the original texture image
  /// embedded unchanged, one primitive per material, the cut surface's with `cut_faces` faces
  /// and the documented colour.
  void expect_written_file(const anim::RiggedModel& model, std::size_t cut_faces) const {
    cgamesh_test::TempDir dir;
    const fs::path out = dir.path() / "result.glb";
    (void)io::write_gltf(model, out);
    tinygltf::TinyGLTF reader;
    reader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*,
                             int, void*) { return true; },
                          nullptr);
    tinygltf::Model gm;
    std::string err, warn;
    ASSERT_TRUE(reader.LoadBinaryFromFile(&gm, &err, &warn, out.string())) << err;
    ASSERT_EQ(gm.images.size(), 1u);
    const tinygltf::BufferView& view = gm.bufferViews.at(static_cast<std::size_t>(gm.images[0].bufferView));
    const auto& data = gm.buffers.at(0).data;
    const std::vector<std::uint8_t> image(
        data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset),
        data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset + view.byteLength));
    EXPECT_EQ(image, *model_.textures[0].bytes) << "the texture image must be embedded as it was";
    ASSERT_EQ(gm.materials.size(), cut_faces > 0 ? 2u : 1u);
    std::size_t written_cut_faces = 0;
    for (const tinygltf::Mesh& mesh : gm.meshes)
      for (const tinygltf::Primitive& p : mesh.primitives) {
        ASSERT_GE(p.material, 0);
        const tinygltf::Material& mat = gm.materials[static_cast<std::size_t>(p.material)];
        if (mat.name != mesh::kCutSurfaceMaterialName) {
          EXPECT_EQ(mat.pbrMetallicRoughness.baseColorTexture.index, 0);
          continue;
        }
        written_cut_faces += gm.accessors.at(static_cast<std::size_t>(p.indices)).count / 3;
        EXPECT_EQ(mat.pbrMetallicRoughness.baseColorTexture.index, -1);
        EXPECT_NEAR(mat.pbrMetallicRoughness.baseColorFactor[0], 0.6, 1e-7);
        EXPECT_NEAR(mat.pbrMetallicRoughness.baseColorFactor[1], 0.1, 1e-7);
        EXPECT_FALSE(mat.doubleSided);
      }
    EXPECT_EQ(written_cut_faces, cut_faces);
    // Loaded again: one mesh per mesh, the same faces with the same materials.
    const anim::RiggedModel back = io::load_model(out);
    ASSERT_EQ(back.meshes.size(), model.meshes.size());
    for (std::size_t k = 0; k < model.meshes.size(); ++k) {
      EXPECT_EQ(back.meshes[k].vertex_count(), model.meshes[k].vertex_count());
      EXPECT_EQ(cut_surface_faces(back, back.meshes[k]).size(), cut_surface_faces(model, model.meshes[k]).size());
    }
  }
};

TEST_F(SurgeryMaterials, CapsOfACutGetTheCutSurfaceMaterial) {
  const surgery::ModelCut c = surgery::cut(model_, placement_, plane_, {.cap = true});
  ASSERT_GT(c.cap_triangles, 0);
  const auto [n, d] = cga::plane_parameters(plane_);
  std::size_t caps = 0;
  for (std::size_t p = 0; p < 2; ++p) {
    SCOPED_TRACE("piece " + std::to_string(p));
    const anim::RiggedModel& piece = c.pieces[p];
    std::size_t piece_caps = 0;
    for (std::size_t k = 0; k < piece.meshes.size(); ++k) {
      const mesh::Mesh& m = piece.meshes[k];
      const std::vector<Eigen::Index> cut = cut_surface_faces(piece, m);
      // Cap faces lie in the plane (placed), and come after the piece's surface faces.
      for (const Eigen::Index f : cut)
        for (int corner = 0; corner < 3; ++corner)
          EXPECT_NEAR(n.dot(c.placed[p][k].row(m.faces(f, corner)).cast<double>().transpose()), d, 1e-5);
      expect_other_faces_keep_the_model_material(piece, m);
      piece_caps += cut.size();
    }
    caps += piece_caps;
    expect_written_file(piece, piece_caps);
  }
  EXPECT_EQ(caps, static_cast<std::size_t>(c.cap_triangles));
}

TEST_F(SurgeryMaterials, WallsOfADrilledHoleGetTheCutSurfaceMaterial) {
  const V3 c = torso(), z(0, 0, 0.5);
  const double r = 0.04;
  const surgery::ModelDrill d = surgery::drill(model_, placement_, c - z, c + z, r, {.wall = true});
  ASSERT_GT(d.wall_triangles, 0);
  ASSERT_EQ(d.model.meshes.size(), 1u);
  const std::vector<Eigen::Index> wall = cut_surface_faces(d.model, d.model.meshes[0]);
  EXPECT_EQ(wall.size(), static_cast<std::size_t>(d.wall_triangles));
  expect_other_faces_keep_the_model_material(d.model, d.model.meshes[0]);
  // Without a wall no material is added.
  const surgery::ModelDrill open = surgery::drill(model_, placement_, c - z, c + z, r);
  EXPECT_EQ(open.model.materials.size(), model_.materials.size());
  EXPECT_EQ(open.model.meshes[0].face_materials.rows(), 0);
  expect_written_file(d.model, wall.size());
}

TEST_F(SurgeryMaterials, InPlaceWallsKeepTheirMaterialThroughLaterOperations) {
  surgery::LiveModel live(model_, placement_);
  const V3 c = torso(), z(0, 0, 0.5);
  const surgery::LiveDrill first = surgery::drill(live, c - z, c + z, 0.04, {.wall = true});
  ASSERT_GT(first.wall_triangles, 0);
  const auto count = [&] { return cut_surface_faces(live.model(), live.model().meshes[0]).size(); };
  EXPECT_EQ(count(), static_cast<std::size_t>(first.wall_triangles));
  const std::size_t materials = live.model().materials.size();
  EXPECT_EQ(materials, model_.materials.size() + 1);
  // A second hole: its walls are added, the material is not.
  const V3 x(0.08, 0, 0);
  const surgery::LiveDrill second = surgery::drill(live, c + x - z, c + x + z, 0.02, {.wall = true});
  EXPECT_EQ(live.model().materials.size(), materials);
  EXPECT_EQ(count(), static_cast<std::size_t>(first.wall_triangles + second.wall_triangles));
  // Every cut-surface face lies on one of the two drills' cylinders (axes along z).
  const auto on_a_wall = [&](const V3& p) {
    const auto distance = [&](const V3& axis, double r) {
      return std::abs(std::hypot(p.x() - axis.x(), p.y() - axis.y()) - r);
    };
    return std::min(distance(c, 0.04), distance(c + x, 0.02)) < 1e-4;
  };
  const mesh::Mesh& m = live.model().meshes[0];
  for (const Eigen::Index f : cut_surface_faces(live.model(), m))
    for (int corner = 0; corner < 3; ++corner)
      EXPECT_TRUE(on_a_wall(live.placement().positions[0].row(m.faces(f, corner)).cast<double>().transpose())) << f;
  // A cut through the first hole splits wall faces: their pieces keep the cut-surface material.
  const std::size_t before = count();
  (void)surgery::cut(live, cga::plane<double>(V3(1, 0, 0), c.x()));
  EXPECT_GT(count(), before);
  EXPECT_EQ(m.face_materials.rows(), m.face_count());
  expect_other_faces_keep_the_model_material(live.model(), m);
  expect_written_file(live.model(), count());
}

/// Each vertex with an origin on an old edge or face has the texture coordinates of that point:
/// the origin's weights applied to its vertices' UVs.
void expect_blended_uvs(const mesh::Mesh& old, const mesh::Mesh& m, const std::vector<mesh::VertexSource>& origins,
                        Eigen::Index first) {
  ASSERT_EQ(m.uvs.rows(), m.vertex_count());
  int blended = 0;
  for (std::size_t k = 0; k < origins.size(); ++k) {
    const mesh::VertexSource& o = origins[k];
    if (o.count() < 2) continue;
    Eigen::RowVector2f uv = Eigen::RowVector2f::Zero();
    for (int s = 0; s < o.count(); ++s)
      uv += o.weight[static_cast<std::size_t>(s)] * old.uvs.row(o.vertex[static_cast<std::size_t>(s)]);
    EXPECT_LE((m.uvs.row(first + static_cast<Eigen::Index>(k)) - uv).norm(), 1e-6f) << k;
    ++blended;
  }
  EXPECT_GT(blended, 0);
}

TEST_F(SurgeryMaterials, NewVerticesGetBlendedTextureCoordinates) {
  const mesh::Mesh& old = model_.meshes[0];
  {
    SCOPED_TRACE("cut");
    const surgery::ModelCut c = surgery::cut(model_, placement_, plane_, {.cap = true});
    for (std::size_t p = 0; p < 2; ++p) expect_blended_uvs(old, c.pieces[p].meshes[0], c.origins[p][0], 0);
  }
  {
    SCOPED_TRACE("drill");
    const surgery::ModelDrill d =
        surgery::drill(model_, placement_, torso() - V3(0, 0, 0.5), torso() + V3(0, 0, 0.5), 0.04, {.wall = true});
    expect_blended_uvs(old, d.model.meshes[0], d.origins[0], 0);
  }
  {
    SCOPED_TRACE("tear");
    const V3 c = torso(), z(0, 0, 0.5);
    const std::vector<surgery::Scalpel> steps{{c + z, c}, {c + V3(-0.03, 0.06, 0) + z, c + V3(-0.03, 0.06, 0)}};
    const surgery::ModelTear t = surgery::tear(model_, placement_, steps);
    expect_blended_uvs(old, t.model.meshes[0], t.origins, 0);
  }
  {
    SCOPED_TRACE("cut and drill in place");
    surgery::LiveModel live(model_, placement_);
    const surgery::LiveCut c = surgery::cut(live, plane_);
    ASSERT_EQ(c.changes.size(), 1u);
    expect_blended_uvs(old, live.model().meshes[0], c.changes[0].origins, c.changes[0].first_new_vertex);
    const mesh::Mesh after_cut = live.model().meshes[0];
    const surgery::LiveDrill d = surgery::drill(live, torso() - V3(0, 0, 0.5), torso() + V3(0, 0, 0.5), 0.04);
    ASSERT_EQ(d.changes.size(), 1u);
    expect_blended_uvs(after_cut, live.model().meshes[0], d.changes[0].origins, d.changes[0].first_new_vertex);
  }
}

}  // namespace
