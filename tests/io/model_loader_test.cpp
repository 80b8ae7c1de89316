#include "cgamesh/io/model_loader.hpp"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/gltf_writer.hpp"

#include "anim/model_fixtures.hpp"
#include "support/gltf_edit.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;
namespace fs = std::filesystem;

void expect_valid_skin(const mesh::Mesh& m) {
  ASSERT_FALSE(m.skin.empty()) << m.name;
  ASSERT_EQ(m.skin.weights.rows(), m.vertex_count());
  ASSERT_EQ(m.skin.inverse_bind.size(), m.skin.palette.size());
  ASSERT_EQ(m.skin.inverse_bind_versors.size(), m.skin.palette.size());
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    EXPECT_NEAR(m.skin.weights.row(i).sum(), 1.0f, 1e-6f) << m.name << " vertex " << i;
    for (int k = 0; k < 4; ++k) {
      EXPECT_GE(m.skin.weights(i, k), 0.0f);
      if (k > 0) {
        EXPECT_LE(m.skin.weights(i, k), m.skin.weights(i, k - 1));
      }
      EXPECT_LT(m.skin.joints(i, k), m.skin.palette.size());
    }
  }
  for (Eigen::Index f = 0; f < m.face_count(); ++f)
    for (int c = 0; c < 3; ++c) ASSERT_LT(m.faces(f, c), m.vertex_count());
}

TEST(ModelLoader, GltfSamples) {
  struct Expect {
    fs::path path;
    Eigen::Index vertices, faces;
    double duration;
  };
  // Vertex counts are those of the files' accessors: no vertex is merged across seams.
  for (const Expect& e : {Expect{cgamesh_test::asset("RiggedSimple.glb"), 96, 188, 2.0833},
                          Expect{cgamesh_test::asset("RiggedFigure.glb"), 370, 256, 1.25},
                          Expect{cgamesh_test::demo_model(), 3273, 4672, 2.0}}) {
    SCOPED_TRACE(e.path.string());
    const anim::RiggedModel m = io::load_model(e.path);
    ASSERT_EQ(m.meshes.size(), 1u);
    EXPECT_EQ(m.meshes[0].vertex_count(), e.vertices);
    EXPECT_EQ(m.meshes[0].face_count(), e.faces);
    EXPECT_EQ(m.meshes[0].normals.rows(), e.vertices);
    ASSERT_EQ(m.clips.size(), 1u);
    EXPECT_NEAR(m.clips[0].duration, e.duration, 1e-3);
    expect_valid_skin(m.meshes[0]);
    for (int j = 0; j < m.skeleton.size(); ++j) EXPECT_LT(m.skeleton.parents()[j], j);
  }
}

// Importers that give one vertex per face corner (OBJ, .x, SMD) would make triangle soups:
// vertices equal in every attribute are joined, seams (another UV) stay split.
TEST(ModelLoader, SoupsAreJoinedAndSeamsKept) {
  const anim::RiggedModel cow = io::load_model(cgamesh_test::asset("cow.obj"));  // positions only
  EXPECT_EQ(cow.meshes.at(0).vertex_count(), 2903);
  EXPECT_EQ(cow.meshes.at(0).face_count(), 5804);
  // spot.obj has UVs: one vertex per distinct "v/vt" corner of its faces.
  std::ifstream in(cgamesh_test::asset("spot.obj"));
  std::set<std::string> corners;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("f ", 0) != 0) continue;
    std::istringstream words(line.substr(2));
    for (std::string corner; words >> corner;) corners.insert(corner);
  }
  const anim::RiggedModel spot = io::load_model(cgamesh_test::asset("spot.obj"));
  EXPECT_EQ(spot.meshes.at(0).vertex_count(), static_cast<Eigen::Index>(corners.size()));
  EXPECT_GT(corners.size(), 2930u) << "seams: more corners than positions";
  // A skinned .x soup: far fewer vertices than corners, each still a valid skin.
  const anim::RiggedModel wuson = io::load_model(cgamesh_test::assimp_model("X/Testwuson.X"));
  const mesh::Mesh& w = wuson.meshes.at(0);
  EXPECT_LT(w.vertex_count(), w.face_count());
  expect_valid_skin(w);
}

// LightWave and NFF map textures by projection (cylindrical, spherical, planar), not by UVs:
// loaded without coordinates, the earth rendered grey and was written as invalid glTF.
TEST(ModelLoader, ProjectedTextureMappingsBecomeTextureCoordinates) {
  for (const char* name : {"LWO/LWO2/MappingModes/earth_cylindrical_x.lwo", "LWO/LWO2/MappingModes/earth_planar_y.lwo",
                           "NFF/NFF/ManyEarthsNotJustOne.nff"}) {
    SCOPED_TRACE(name);
    const fs::path file = cgamesh_test::assimp_model(name);
    if (!fs::exists(file)) GTEST_SKIP() << "assimp-testmodels not installed";
    const anim::RiggedModel model = io::load_model(file);
    for (const mesh::Mesh& m : model.meshes) {
      ASSERT_EQ(m.uvs.rows(), m.vertex_count());
      EXPECT_TRUE(m.uvs.allFinite());
      EXPECT_GT((m.uvs.colwise().maxCoeff() - m.uvs.colwise().minCoeff()).minCoeff(), 0.5f) << "spread over the image";
    }
  }
}

TEST(ModelLoader, AssimpTestModelsInOtherFormats) {
  const fs::path x = cgamesh_test::assimp_model("X/BCN_Epileptic.X");
  const fs::path fbx = cgamesh_test::assimp_model("FBX/animation_with_skeleton.fbx");
  if (!fs::exists(x) || !fs::exists(fbx)) GTEST_SKIP() << "assimp-testmodels not installed";
  const anim::RiggedModel bcn = io::load_model(x);
  EXPECT_EQ(bcn.meshes.size(), 3u);
  EXPECT_EQ(bcn.clips.size(), 1u);
  for (const auto& m : bcn.meshes) expect_valid_skin(m);

  // This FBX has up to 6 influences per vertex and non-uniform scales: loaded, approximated, said.
  const anim::RiggedModel f = io::load_model(fbx);
  EXPECT_EQ(f.source_max_influences, 6);
  expect_valid_skin(f.meshes[0]);
  bool said_influences = false, said_scale = false;
  for (const auto& w : f.warnings) {
    said_influences |= w.find("more than 4 influences") != std::string::npos;
    said_scale |= w.find("non-uniform scale") != std::string::npos;
  }
  EXPECT_TRUE(said_influences);
  EXPECT_TRUE(said_scale);

  for (const char* other :
       {"X/Testwuson.X", "SMD/WusonSMD.smd", "MD5/SimpleCube.md5mesh", "glTF2/simple_skin/simple_skin.gltf"}) {
    const anim::RiggedModel m = io::load_model(cgamesh_test::assimp_model(other));
    EXPECT_FALSE(m.meshes.empty()) << other;
  }
}

// Static formats load as meshes that follow their node; COLLADA archives (.zae) load too.
TEST(ModelLoader, StaticFormatsAndZae) {
  const fs::path obj = cgamesh_test::assimp_model("OBJ/WusonOBJ.obj");
  if (!fs::exists(obj)) GTEST_SKIP() << "assimp-testmodels not installed";
  for (const char* f : {"OBJ/WusonOBJ.obj", "PLY/Wuson.ply", "STL/Wuson.stl", "Collada/duck.zae"}) {
    SCOPED_TRACE(f);
    const anim::RiggedModel m = io::load_model(cgamesh_test::assimp_model(f));
    ASSERT_FALSE(m.meshes.empty());
    for (const auto& mesh : m.meshes) {
      EXPECT_GT(mesh.face_count(), 0);
      EXPECT_TRUE(mesh.skin.empty());
      EXPECT_GE(mesh.node, 0);
      EXPECT_TRUE(mesh.positions.allFinite());
    }
  }
}

TEST(ModelLoader, BadFilesThrowFileError) {
  const fs::path dir = fs::temp_directory_path() / "cgamesh_loader_test";
  fs::create_directories(dir);
  EXPECT_THROW((void)io::load_model(dir / "missing.glb"), FileError);

  const fs::path not_a_model = dir / "notes.glb";
  std::ofstream(not_a_model) << "this is not a model\n";
  EXPECT_THROW((void)io::load_model(not_a_model), FileError);

  // The first 6000 bytes of a real GLB: the binary chunk is cut off.
  const fs::path truncated = dir / "truncated.glb";
  {
    std::ifstream in(cgamesh_test::asset("RiggedSimple.glb"), std::ios::binary);
    std::string bytes(6000, '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    std::ofstream(truncated, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  EXPECT_THROW((void)io::load_model(truncated), FileError);

  // Debian's assimp-testmodels: faces "0", "220", "4" over 3 vertices; Assimp makes two
  // triangles over one vertex of them.
  const fs::path invalid_off = "/usr/share/assimp/models/OFF/invalid.off";
  ASSERT_TRUE(fs::exists(invalid_off)) << "scripts/install-deps.sh installs assimp-testmodels";
  EXPECT_THROW((void)io::load_model(invalid_off), FileError);
  // A mesh of degenerate triangles beside a real one is left out with a warning.
  const fs::path mixed = dir / "mixed.obj";
  std::ofstream(mixed) << "o real\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no broken\nv 5 5 5\nf 4 4 4\n";
  const anim::RiggedModel m = io::load_model(mixed);
  EXPECT_EQ(m.meshes.size(), 1u);
  EXPECT_TRUE(std::any_of(m.warnings.begin(), m.warnings.end(),
                          [](const std::string& w) { return w.find("three distinct corners") != std::string::npos; }));
  fs::remove_all(dir);
}

/// The message of the FileError that loading `path` throws ("" and a failure when it loads).
std::string load_error(const fs::path& path) {
  try {
    (void)io::load_model(path);
  } catch (const FileError& e) {
    return e.what();
  }
  ADD_FAILURE() << path << " loaded";
  return "";
}

// Issue #33 item 7: messages a person can read. Assimp's parse error of this .x file quotes the
// rest of the file (34 kB); the message quotes an excerpt and says how much it left out.
TEST(ModelLoader, AReadersMessageIsQuotedAsAShortExcerpt) {
  const std::string message = load_error(cgamesh_test::asset("testentities_cool_guy.x"));
  EXPECT_LT(message.size(), 500u) << message.size();
  EXPECT_NE(message.find("testentities_cool_guy.x"), std::string::npos) << message;
  EXPECT_NE(message.find("… ("), std::string::npos) << message;
  EXPECT_NE(message.find(" more bytes)"), std::string::npos) << message;
}

// Required extensions that cannot be decoded are named (Assimp said "missing the uri").
TEST(ModelLoader, UnsupportedRequiredExtensionsAreNamed) {
  const std::string message = load_error(cgamesh_test::asset("pirate_meshopt.glb"));
  EXPECT_NE(message.find("EXT_meshopt_compression"), std::string::npos) << message;
  EXPECT_NE(message.find("KHR_mesh_quantization"), std::string::npos) << message;
  EXPECT_EQ(message.find("uri"), std::string::npos) << message;
  // Draco, which Debian's Assimp decodes, is not refused for being required.
  cgamesh_test::TempDir dir;
  tinygltf::Model m = cgamesh_test::read_glb(cgamesh_test::asset("RiggedSimple.glb"));
  m.extensionsUsed = {"KHR_draco_mesh_compression", "KHR_texture_transform"};
  m.extensionsRequired = m.extensionsUsed;
  EXPECT_NO_THROW((void)io::load_model(cgamesh_test::write_glb(std::move(m), dir / "required.glb")));
}

// A file of animation alone (a motion-capture .bvh) is said to be one.
TEST(ModelLoader, AnimationWithoutAMeshIsNamed) {
  const fs::path bvh = "/usr/share/assimp/models/BVH/01_01.bvh";
  if (!fs::exists(bvh)) GTEST_SKIP() << bvh << " is not installed (assimp-testmodels)";
  const std::string message = load_error(bvh);
  EXPECT_NE(message.find("holds animation (1 clip) but no mesh"), std::string::npos) << message;
}

// glTF 2.0 §5.28: a skin's inverseBindMatrices hold one matrix per joint. Fewer is refused,
// naming the skin (Assimp read past the accessor).
TEST(ModelLoader, TooFewInverseBindMatricesAreRefused) {
  cgamesh_test::TempDir dir;
  tinygltf::Model m = cgamesh_test::read_glb(cgamesh_test::asset("RiggedSimple.glb"));
  ASSERT_FALSE(m.skins.empty());
  tinygltf::Skin& skin = m.skins[0];
  ASSERT_GE(skin.inverseBindMatrices, 0);
  auto& accessor = m.accessors[static_cast<std::size_t>(skin.inverseBindMatrices)];
  ASSERT_EQ(accessor.count, skin.joints.size());
  accessor.count -= 1;
  skin.name = "the skin";
  const std::string joints = std::to_string(skin.joints.size());
  const std::string message = load_error(cgamesh_test::write_glb(std::move(m), dir / "short_ibm.glb"));
  EXPECT_NE(message.find("skin 0 'the skin' has " + joints + " joints"), std::string::npos) << message;
  EXPECT_NE(message.find("inverseBindMatrices"), std::string::npos) << message;
}

// A zero scale key (a byte flip in a real file) is a broken file when loading, whatever the
// command does with the clip afterwards; a directory is named as one.
TEST(ModelLoader, ZeroScaleKeyAndDirectoryAreNamed) {
  cgamesh_test::TempDir dir;
  tinygltf::Model m = cgamesh_test::read_glb(cgamesh_test::demo_model());
  bool zeroed = false;
  for (const tinygltf::AnimationChannel& c : m.animations[0].channels) {
    if (c.target_path != "scale") continue;
    const tinygltf::Accessor& a =
        m.accessors[static_cast<std::size_t>(m.animations[0].samplers[static_cast<std::size_t>(c.sampler)].output)];
    const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
    float* key = reinterpret_cast<float*>(m.buffers[static_cast<std::size_t>(v.buffer)].data.data() + v.byteOffset +
                                          a.byteOffset);
    key[1] = 0;  // the first key's y factor
    zeroed = true;
    break;
  }
  ASSERT_TRUE(zeroed) << "CesiumMan has no scale channel";
  const fs::path file = cgamesh_test::write_glb(std::move(m), dir / "zero_scale.glb");
  try {
    (void)io::load_model(file);
    FAIL() << "loaded";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("a zero or mirroring scale has no versor"), std::string::npos) << e.what();
  }
  fs::create_directories(dir / "model.glb");
  try {
    (void)io::load_model(dir / "model.glb");
    FAIL() << "loaded";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
}

// Keys before t = 0 (LightWave scenes have them; glTF forbids them) start the clip at 0 with the
// pose it has there: CesiumMan's clip moved 0.5 s earlier plays, from 0, as the original from 0.5.
TEST(ModelLoader, KeysBeforeZeroStartTheClipAtZero) {
  cgamesh_test::TempDir dir;
  constexpr double kShift = 0.5;
  tinygltf::Model m = cgamesh_test::read_glb(cgamesh_test::demo_model());
  std::set<int> inputs;
  for (const tinygltf::AnimationSampler& s : m.animations[0].samplers) inputs.insert(s.input);
  for (const int i : inputs) {
    tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(i)];
    const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
    float* t = reinterpret_cast<float*>(m.buffers[static_cast<std::size_t>(v.buffer)].data.data() + v.byteOffset +
                                        a.byteOffset);
    for (std::size_t k = 0; k < a.count; ++k) t[k] -= static_cast<float>(kShift);
    for (double& x : a.minValues) x -= kShift;
    for (double& x : a.maxValues) x -= kShift;
  }
  const anim::RiggedModel original = io::load_model(cgamesh_test::demo_model());
  const anim::RiggedModel early = io::load_model(cgamesh_test::write_glb(std::move(m), dir / "early.glb"));
  bool warned = false;
  for (const std::string& w : early.warnings) warned = warned || w.find("keys before t = 0") != std::string::npos;
  EXPECT_TRUE(warned);
  for (const anim::Channel& ch : early.clips[0].channels) {
    ASSERT_FALSE(ch.times.empty());
    EXPECT_EQ(ch.times.front(), 0.0);
    EXPECT_EQ(ch.values.size(), ch.times.size() * static_cast<std::size_t>(ch.components()));
  }
  for (const double t : {0.0, 0.013, 0.25, 1.0}) {
    const anim::Pose a = anim::sample(early.skeleton, early.clips[0], t, anim::BlendMode::format);
    const anim::Pose b = anim::sample(original.skeleton, original.clips[0], t + kShift, anim::BlendMode::format);
    for (std::size_t j = 0; j < a.local.size(); ++j) {
      EXPECT_LT((a.local[j].translation - b.local[j].translation).norm(), 1e-5) << "t " << t << " joint " << j;
      EXPECT_GT(std::abs(a.local[j].rotation.dot(b.local[j].rotation)), 1 - 1e-6) << "t " << t << " joint " << j;
      EXPECT_LT((a.local[j].scale - b.local[j].scale).norm(), 1e-5) << "t " << t << " joint " << j;
    }
  }
  EXPECT_NO_THROW((void)io::encode_gltf(early, dir / "written.glb"));
}

// What Assimp's readers hand over for files from elsewhere: an OBJ's Latin-1 material names are
// read as such (and can be written: glTF needs UTF-8); RAW's reader leaves a child node empty,
// which is skipped, not followed; Q3D's earth has NaN normals, which are made from its faces.
TEST(ModelLoader, LatinOneNamesAnEmptyChildNodeAndNanNormals) {
  const fs::path obj = cgamesh_test::assimp_model("OBJ/regr01.obj");
  const fs::path raw = cgamesh_test::assimp_model("RAW/WithColor.raw");
  if (!fs::exists(obj) || !fs::exists(raw)) GTEST_SKIP() << "assimp-testmodels not installed";
  const auto said = [](const anim::RiggedModel& m, const std::string& what) {
    for (const std::string& w : m.warnings)
      if (w.find(what) != std::string::npos) return true;
    return false;
  };
  cgamesh_test::TempDir dir;
  const anim::RiggedModel regr = io::load_model(obj);
  bool danish = false;
  for (const mesh::Material& m : regr.materials) danish = danish || m.name == "Terraind\u00e6k";
  EXPECT_TRUE(danish);
  EXPECT_TRUE(said(regr, "are read as Latin-1"));
  EXPECT_NO_THROW((void)io::encode_gltf(regr, dir / "regr01.glb"));

  const anim::RiggedModel r = io::load_model(raw);
  EXPECT_FALSE(r.meshes.empty());
  EXPECT_TRUE(said(r, "the reader left child 1 of 2 empty; skipped"));

  const anim::RiggedModel earth = io::load_model(cgamesh_test::assimp_model("Q3D/earth.q3o"));
  for (const mesh::Mesh& m : earth.meshes) {
    ASSERT_EQ(m.normals.rows(), m.vertex_count());
    EXPECT_TRUE(m.normals.allFinite()) << m.name;
  }
  EXPECT_TRUE(said(earth, "4 of 5139 normals were NaN or infinite"));
}
}  // namespace

namespace {

// Found by the field sweep: pab_skeleton.fbx's normals point into the body on 2798 of 2811
// faces, and it rendered dark. A cube whose normals point inward is the same in small.
TEST(ModelLoader, NormalsIntoTheBodyAreTurnedOutward) {
  cgamesh_test::TempDir dir;
  const auto write_cube = [&](const std::string& name, float sign) {
    std::ofstream out(dir / name);
    for (int i = 0; i < 8; ++i) out << "v " << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    out << "vn " << sign << " 0 0\nvn 0 " << sign << " 0\nvn 0 0 " << sign << "\n"
        << "vn " << -sign << " 0 0\nvn 0 " << -sign << " 0\nvn 0 0 " << -sign << "\n";
    // Outward winding; normal k for +axis faces, k+3 for -axis faces.
    const int faces[12][4] = {{1, 3, 2, 6}, {2, 3, 4, 6}, {5, 6, 7, 3}, {6, 8, 7, 3}, {1, 2, 5, 5}, {2, 6, 5, 5},
                              {3, 7, 4, 2}, {4, 7, 8, 2}, {1, 5, 3, 4}, {3, 5, 7, 4}, {2, 4, 6, 1}, {4, 8, 6, 1}};
    for (const auto& f : faces)
      out << "f " << f[0] << "//" << f[3] << " " << f[1] << "//" << f[3] << " " << f[2] << "//" << f[3] << "\n";
  };
  write_cube("outward.obj", 1);
  write_cube("inward.obj", -1);
  const auto turned = [](const anim::RiggedModel& m) {
    return std::any_of(m.warnings.begin(), m.warnings.end(),
                       [](const std::string& w) { return w.find("turned outward") != std::string::npos; });
  };
  const anim::RiggedModel out = io::load_model(dir / "outward.obj"), in = io::load_model(dir / "inward.obj");
  EXPECT_FALSE(turned(out));
  EXPECT_TRUE(turned(in));
  // Both load with normals along their faces' winding.
  for (const anim::RiggedModel* m : {&out, &in}) {
    const mesh::Mesh& c = m->meshes[0];
    for (Eigen::Index f = 0; f < c.face_count(); ++f) {
      const Eigen::Vector3f a = c.positions.row(c.faces(f, 0)), b = c.positions.row(c.faces(f, 1)),
                            d = c.positions.row(c.faces(f, 2));
      EXPECT_GT((b - a).cross(d - a).dot(Eigen::Vector3f(c.normals.row(c.faces(f, 0)))), 0) << f;
    }
  }
}

}  // namespace

namespace {

// Found by the field sweep: 3DS files from Windows name their textures in another case
// ("DWARF.JPG" for dwarf.jpg), and they were not found.
TEST(ModelLoader, TexturesAreFoundWhateverTheCaseOfTheirName) {
  cgamesh_test::TempDir dir;
  fs::create_directories(dir / "maps");
  { std::ofstream(dir / "maps" / "skin.png", std::ios::binary) << "not decoded by the loader"; }
  { std::ofstream(dir / "quad.mtl") << "newmtl skin\nKd 1 1 1\nmap_Kd Maps\\SKIN.PNG\n"; }
  {
    std::ofstream(dir / "quad.obj") << "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl skin\n"
                                       "f 1/1 2/2 3/3\n";
  }
  const anim::RiggedModel m = io::load_model(dir / "quad.obj");
  ASSERT_EQ(m.textures.size(), 1u);
  EXPECT_EQ(m.textures[0].bytes->size(), std::string("not decoded by the loader").size());
  EXPECT_TRUE(std::any_of(m.warnings.begin(), m.warnings.end(),
                          [](const std::string& w) { return w.find("is read from 'skin.png'") != std::string::npos; }));
}

}  // namespace
