// Materials through load → write → load: every field of a glTF metallic-roughness material
// (factors, the five textures with their images, normal scale, occlusion strength, emissive,
// alpha mode and cutoff, double-sidedness), one image per texture embedded in the .glb, and
// meshes whose faces have several materials (one primitive each, one Mesh again on loading).

#include "cgamesh/mesh/material.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "support/js_oracles.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using namespace cgamesh;
using cgamesh_test::TempDir;

/// A 1×1 RGBA PNG of colour k (k < 5): five distinct, valid images.
std::vector<unsigned char> png(int k) {
  // Compressed pixel and CRC of each image's IDAT chunk; the rest is the same for all.
  static const std::array<std::array<unsigned char, 15>, 5> idat{{
      {0x63, 0xf8, 0xcf, 0xc0, 0xf0, 0x1f, 0x00, 0x05, 0x00, 0x01, 0xff, 0x56, 0xc7, 0x2f, 0x0d},
      {0x63, 0x68, 0x68, 0xf8, 0xff, 0x1f, 0x00, 0x06, 0x82, 0x02, 0xff, 0x6c, 0xe0, 0x43, 0x23},
      {0x63, 0x60, 0x38, 0x91, 0xf2, 0x1f, 0x00, 0x04, 0x24, 0x02, 0x2c, 0xcb, 0x30, 0xf2, 0xc6},
      {0x63, 0xf8, 0xff, 0x9f, 0xe1, 0x3f, 0x00, 0x07, 0xfd, 0x02, 0xfe, 0x79, 0xca, 0xd7, 0xa4},
      {0x63, 0x88, 0x8a, 0x8a, 0xfa, 0x0f, 0x00, 0x04, 0x2e, 0x02, 0x0e, 0x40, 0x88, 0xf2, 0xeb},
  }};
  std::vector<unsigned char> out{0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00,
                                 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
                                 0x00, 0x01, 0x08, 0x06, 0x00, 0x00, 0x00, 0x1f, 0x15, 0xc4, 0x89,
                                 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda};
  const auto& d = idat[static_cast<std::size_t>(k)];
  out.insert(out.end(), d.begin(), d.end());
  for (unsigned char b : {0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82}) out.push_back(b);
  return out;
}

/// Builds a glTF model buffer view by buffer view.
struct GltfBuilder {
  tinygltf::Model gm;
  GltfBuilder() {
    gm.asset.version = "2.0";
    gm.buffers.resize(1);
  }
  int view(const void* bytes, std::size_t size, int target) {
    auto& data = gm.buffers[0].data;
    while (data.size() % 4 != 0) data.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = data.size();
    v.byteLength = size;
    v.target = target;
    const auto* b = static_cast<const unsigned char*>(bytes);
    data.insert(data.end(), b, b + size);
    gm.bufferViews.push_back(v);
    return static_cast<int>(gm.bufferViews.size()) - 1;
  }
  int accessor(const void* bytes, std::size_t size, int component, int type, std::size_t count, int target,
               std::vector<double> min = {}, std::vector<double> max = {}) {
    tinygltf::Accessor a;
    a.bufferView = view(bytes, size, target);
    a.componentType = component;
    a.type = type;
    a.count = count;
    a.minValues = std::move(min);
    a.maxValues = std::move(max);
    gm.accessors.push_back(a);
    return static_cast<int>(gm.accessors.size()) - 1;
  }
  int texture(const std::vector<unsigned char>& bytes, const std::string& name) {
    tinygltf::Image image;
    image.name = name;
    image.mimeType = "image/png";
    image.bufferView = view(bytes.data(), bytes.size(), 0);
    gm.images.push_back(image);
    tinygltf::Texture t;
    t.source = static_cast<int>(gm.images.size()) - 1;
    gm.textures.push_back(t);
    return static_cast<int>(gm.textures.size()) - 1;
  }
  void write(const fs::path& path) {
    tinygltf::TinyGLTF writer;
    ASSERT_TRUE(writer.WriteGltfSceneToFile(&gm, path.string(), true, true, false, true));
  }
};

/// One textured triangle whose material uses every field, images 0 … 4 as base colour, normal,
/// metallic-roughness, emissive and occlusion textures.
fs::path full_material_file(const fs::path& dir) {
  GltfBuilder b;
  const std::array<float, 9> positions{0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::array<float, 6> uvs{0, 0, 1, 0, 0, 1};
  const std::array<std::uint16_t, 3> indices{0, 1, 2};
  tinygltf::Primitive p;
  p.mode = TINYGLTF_MODE_TRIANGLES;
  p.attributes["POSITION"] = b.accessor(positions.data(), sizeof positions, TINYGLTF_COMPONENT_TYPE_FLOAT,
                                        TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, {0, 0, 0}, {1, 1, 0});
  p.attributes["TEXCOORD_0"] = b.accessor(uvs.data(), sizeof uvs, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 3,
                                          TINYGLTF_TARGET_ARRAY_BUFFER);
  p.indices = b.accessor(indices.data(), sizeof indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                         3, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  p.material = 0;
  tinygltf::Material m;
  m.name = "full";
  m.pbrMetallicRoughness.baseColorFactor = {0.5, 0.6, 0.7, 0.8};
  m.pbrMetallicRoughness.baseColorTexture.index = b.texture(png(0), "base");
  m.normalTexture.index = b.texture(png(1), "normal");
  m.normalTexture.scale = 0.5;
  m.pbrMetallicRoughness.metallicFactor = 0.25;
  m.pbrMetallicRoughness.roughnessFactor = 0.75;
  m.pbrMetallicRoughness.metallicRoughnessTexture.index = b.texture(png(2), "metallic_roughness");
  m.emissiveTexture.index = b.texture(png(3), "emissive");
  m.emissiveFactor = {0.1, 0.2, 0.3};
  m.occlusionTexture.index = b.texture(png(4), "occlusion");
  m.occlusionTexture.strength = 0.7;
  m.alphaMode = "MASK";
  m.alphaCutoff = 0.3;
  m.doubleSided = true;
  b.gm.materials.push_back(m);
  tinygltf::Mesh mesh;
  mesh.name = "triangle";
  mesh.primitives.push_back(p);
  b.gm.meshes.push_back(mesh);
  tinygltf::Node node;
  node.name = "node";
  node.mesh = 0;
  b.gm.nodes.push_back(node);
  b.gm.scenes.resize(1);
  b.gm.scenes[0].nodes = {0};
  b.gm.defaultScene = 0;
  const fs::path path = dir / "full_material.glb";
  b.write(path);
  return path;
}

/// The bytes of texture `t` of `model`, or empty for none.
std::vector<std::uint8_t> texture_bytes(const anim::RiggedModel& model, int t) {
  if (t < 0 || t >= static_cast<int>(model.textures.size())) return {};
  const auto bytes = model.textures[static_cast<std::size_t>(t)].data();
  return {bytes.begin(), bytes.end()};
}

/// Every field of the material of test file full_material_file.
void expect_full_material(const anim::RiggedModel& model) {
  ASSERT_EQ(model.meshes.size(), 1u);
  const int index = model.meshes[0].material;
  ASSERT_GE(index, 0);
  const mesh::Material& m = model.materials[static_cast<std::size_t>(index)];
  EXPECT_EQ(m.name, "full");
  EXPECT_TRUE(m.base_color.isApprox(Eigen::Vector4f(0.5f, 0.6f, 0.7f, 0.8f), 1e-6f)) << m.base_color.transpose();
  EXPECT_FLOAT_EQ(m.metallic, 0.25f);
  EXPECT_FLOAT_EQ(m.roughness, 0.75f);
  EXPECT_FLOAT_EQ(m.normal_scale, 0.5f);
  EXPECT_FLOAT_EQ(m.occlusion_strength, 0.7f);
  EXPECT_TRUE(m.emissive.isApprox(Eigen::Vector3f(0.1f, 0.2f, 0.3f), 1e-6f)) << m.emissive.transpose();
  EXPECT_EQ(m.alpha_mode, mesh::AlphaMode::mask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_EQ(texture_bytes(model, m.base_color_texture), png(0));
  EXPECT_EQ(texture_bytes(model, m.normal_texture), png(1));
  EXPECT_EQ(texture_bytes(model, m.metallic_roughness_texture), png(2));
  EXPECT_EQ(texture_bytes(model, m.emissive_texture), png(3));
  EXPECT_EQ(texture_bytes(model, m.occlusion_texture), png(4));
  for (const mesh::TextureImage& t : model.textures) EXPECT_EQ(t.mime_type, "image/png") << t.name;
}

tinygltf::Model read_glb(const fs::path& path) {
  tinygltf::TinyGLTF reader;
  reader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                           void*) { return true; },
                        nullptr);
  tinygltf::Model gm;
  std::string err, warn;
  EXPECT_TRUE(reader.LoadBinaryFromFile(&gm, &err, &warn, path.string())) << err;
  return gm;
}

/// The bytes of image i of a glTF model (embedded through a buffer view).
std::vector<unsigned char> image_bytes(const tinygltf::Model& gm, int i) {
  const tinygltf::BufferView& v =
      gm.bufferViews.at(static_cast<std::size_t>(gm.images.at(static_cast<std::size_t>(i)).bufferView));
  const auto& data = gm.buffers.at(static_cast<std::size_t>(v.buffer)).data;
  return {data.begin() + static_cast<std::ptrdiff_t>(v.byteOffset),
          data.begin() + static_cast<std::ptrdiff_t>(v.byteOffset + v.byteLength)};
}

TEST(Materials, LoadKeepsEveryGltfMaterialField) {
  TempDir dir;
  expect_full_material(io::load_model(full_material_file(dir.path())));
}

TEST(Materials, WriteKeepsEveryMaterialFieldAndEmbedsEachImageOnce) {
  TempDir dir;
  const anim::RiggedModel original = io::load_model(full_material_file(dir.path()));
  for (const char* name : {"written.glb", "written.gltf"}) {
    SCOPED_TRACE(name);
    const fs::path out = dir.path() / name;
    EXPECT_TRUE(io::write_gltf(original, out).empty());
    expect_full_material(io::load_model(out));
  }
  // The file itself, read by tinygltf: one material, five images embedded as they were.
  const tinygltf::Model gm = read_glb(dir.path() / "written.glb");
  ASSERT_EQ(gm.materials.size(), 1u);
  ASSERT_EQ(gm.images.size(), 5u);
  const tinygltf::Material& m = gm.materials[0];
  const auto image_of = [&](int texture) {
    return image_bytes(gm, gm.textures.at(static_cast<std::size_t>(texture)).source);
  };
  EXPECT_EQ(image_of(m.pbrMetallicRoughness.baseColorTexture.index), png(0));
  EXPECT_EQ(image_of(m.normalTexture.index), png(1));
  EXPECT_EQ(image_of(m.pbrMetallicRoughness.metallicRoughnessTexture.index), png(2));
  EXPECT_EQ(image_of(m.emissiveTexture.index), png(3));
  EXPECT_EQ(image_of(m.occlusionTexture.index), png(4));
  EXPECT_EQ(m.alphaMode, "MASK");
  EXPECT_NEAR(m.alphaCutoff, 0.3, 1e-7);
  EXPECT_NEAR(m.normalTexture.scale, 0.5, 1e-7);
  EXPECT_NEAR(m.occlusionTexture.strength, 0.7, 1e-7);
  ASSERT_EQ(m.emissiveFactor.size(), 3u);
  EXPECT_NEAR(m.emissiveFactor[2], 0.3, 1e-7);
  EXPECT_TRUE(m.doubleSided);
}

// glTF allows no texture on a primitive without TEXCOORD_0 (the validator's
// MESH_PRIMITIVE_TOO_FEW_TEXCOORDS): such a mesh gets the material without its textures, and
// a mesh with coordinates sharing it keeps them.
TEST(Materials, AMeshWithoutTextureCoordinatesIsWrittenWithoutTheTextures) {
  TempDir dir;
  anim::RiggedModel model = io::load_model(full_material_file(dir.path()));
  mesh::Mesh bare = model.meshes[0];
  bare.uvs.resize(0, 2);
  bare.name = "bare";
  model.meshes.push_back(bare);
  const fs::path out = dir.path() / "written.glb";
  const std::vector<std::string> warnings = io::write_gltf(model, out);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("no texture coordinates"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("'full'"), std::string::npos) << warnings[0];
  if (cgamesh_test::validator_available()) {
    std::string log;
    EXPECT_EQ(cgamesh_test::validate_gltf(out, log), 0) << log;
  }
  const tinygltf::Model gm = read_glb(out);
  ASSERT_EQ(gm.materials.size(), 2u);
  const auto material_of = [&](std::size_t mesh) {
    return gm.materials.at(static_cast<std::size_t>(gm.meshes.at(mesh).primitives.at(0).material));
  };
  EXPECT_EQ(material_of(0).pbrMetallicRoughness.baseColorTexture.index, 0);
  EXPECT_EQ(material_of(1).pbrMetallicRoughness.baseColorTexture.index, -1);
  EXPECT_EQ(material_of(1).normalTexture.index, -1);
  EXPECT_EQ(material_of(1).name, "full");
}

/// Two triangles sharing an edge, with UVs, faces of materials `a` and `b`.
anim::RiggedModel two_material_quad(int a, int b) {
  anim::RiggedModel model;
  anim::EditableSkeleton es;
  es.joints.push_back({"root", -1, {}});
  model.skeleton = anim::Skeleton::build(es);
  mesh::Mesh m;
  m.name = "quad";
  m.node = 0;
  m.positions.resize(4, 3);
  m.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  m.uvs.resize(4, 2);
  m.uvs << 0, 0, 1, 0, 0, 1, 1, 1;
  m.faces.resize(2, 3);
  m.faces << 0, 1, 2, 1, 3, 2;
  m.material = a;
  m.face_materials.resize(2);
  m.face_materials << a, b;
  model.meshes.push_back(m);
  mesh::Material red, blue;
  red.name = "red";
  red.base_color << 1, 0, 0, 1;
  blue.name = "blue";
  blue.base_color << 0, 0, 1, 1;
  model.materials = {red, blue};
  return model;
}

TEST(Materials, FacesWithSeveralMaterialsWriteOnePrimitiveEachAndLoadAsOneMesh) {
  TempDir dir;
  const anim::RiggedModel model = two_material_quad(0, 1);
  const fs::path out = dir.path() / "quad.glb";
  EXPECT_TRUE(io::write_gltf(model, out).empty());
  const tinygltf::Model gm = read_glb(out);
  ASSERT_EQ(gm.meshes.size(), 1u);
  ASSERT_EQ(gm.meshes[0].primitives.size(), 2u);
  ASSERT_EQ(gm.materials.size(), 2u);
  for (std::size_t p = 0; p < 2; ++p) {
    const tinygltf::Primitive& prim = gm.meshes[0].primitives[p];
    EXPECT_EQ(gm.materials.at(static_cast<std::size_t>(prim.material)).name, p == 0 ? "red" : "blue");
    EXPECT_EQ(prim.attributes, gm.meshes[0].primitives[0].attributes) << "the primitives share their vertices";
    EXPECT_EQ(gm.accessors.at(static_cast<std::size_t>(prim.indices)).count, 3u);
  }
  const anim::RiggedModel back = io::load_model(out);
  ASSERT_EQ(back.meshes.size(), 1u);
  const mesh::Mesh& m = back.meshes[0];
  EXPECT_EQ(m.name, "quad");
  EXPECT_EQ(m.vertex_count(), 4);
  EXPECT_EQ(m.faces, model.meshes[0].faces);
  ASSERT_EQ(m.face_materials.rows(), 2);
  EXPECT_EQ(back.materials.at(static_cast<std::size_t>(m.face_material(0))).name, "red");
  EXPECT_EQ(back.materials.at(static_cast<std::size_t>(m.face_material(1))).name, "blue");
  EXPECT_TRUE(m.uvs.isApprox(model.meshes[0].uvs));

  // One material on every face: one primitive, and no face materials on loading.
  const fs::path same = dir.path() / "same.glb";
  (void)io::write_gltf(two_material_quad(1, 1), same);
  EXPECT_EQ(read_glb(same).meshes[0].primitives.size(), 1u);
  EXPECT_EQ(io::load_model(same).meshes[0].face_materials.rows(), 0);
}

TEST(Materials, FaceMaterialRowsMustMatchTheFaces) {
  anim::RiggedModel model = two_material_quad(0, 1);
  model.meshes[0].face_materials.resize(3);
  TempDir dir;
  EXPECT_THROW((void)io::write_gltf(model, dir.path() / "bad.glb"), InvalidInputError);
}

TEST(Materials, CutSurfaceMaterialIsAddedOnceAndFoundByName) {
  std::vector<mesh::Material> materials(2);
  const int index = mesh::cut_surface_material_index(materials);
  EXPECT_EQ(index, 2);
  ASSERT_EQ(materials.size(), 3u);
  const mesh::Material& cut = materials[2];
  EXPECT_EQ(cut.name, mesh::kCutSurfaceMaterialName);
  EXPECT_TRUE(cut.base_color.isApprox(Eigen::Vector4f(0.6f, 0.1f, 0.1f, 1.0f)));
  EXPECT_EQ(cut.base_color_texture, -1);
  EXPECT_FALSE(cut.double_sided);
  EXPECT_EQ(mesh::cut_surface_material_index(materials), 2);
  EXPECT_EQ(materials.size(), 3u);
}

}  // namespace
