// write_gltf: models built in code are written as .glb / .gltf, read back with tinygltf's
// loader (an independent reader) and compared field by field; invalid models must throw and
// leave nothing behind; the Khronos validator (tests/oracle/js) must report 0 errors.

#include "cgamesh/io/gltf_writer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "support/js_oracles.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using cgamesh::InvalidInputError;
using cgamesh::anim::Channel;
using cgamesh::anim::ChannelPath;
using cgamesh::anim::Interpolation;
using cgamesh::anim::RiggedModel;
using cgamesh::anim::Transform;
using cgamesh::io::GltfWriteOptions;
using cgamesh::io::write_gltf;

using cgamesh_test::TempDir;

Channel channel(int joint, ChannelPath path, Interpolation interpolation, std::vector<double> times,
                std::vector<double> values) {
  Channel c;
  c.joint = joint;
  c.path = path;
  c.interpolation = interpolation;
  c.times = std::move(times);
  c.values = std::move(values);
  return c;
}

Transform trs(const Eigen::Vector3d& t, const Eigen::Quaterniond& r, const Eigen::Vector3d& s) {
  Transform x;
  x.translation = t;
  x.rotation = r;
  x.scale = s;
  return x;
}

Eigen::Matrix4d global_rest(const cgamesh::anim::Skeleton& sk, int j) {
  Eigen::Matrix4d m = sk.rest()[j].matrix();
  for (int p = sk.parents()[j]; p >= 0; p = sk.parents()[p]) m = sk.rest()[p].matrix() * m;
  return m;
}

/// A two-bone cylinder along y (10 rings of 8 vertices), skinned to joints "bone1" and "bone2"
/// under a "root" with non-uniform scale; a static "hat" on bone2, a static "ground" at the
/// root; clips with LINEAR, STEP and CUBICSPLINE channels, an empty channel and an empty clip.
RiggedModel make_model() {
  RiggedModel model;
  cgamesh::anim::EditableSkeleton es;
  // Listed child-first: Skeleton::build reorders to root, bone1, bone2.
  es.joints.push_back({"bone2", 2, trs({0, 1, 0}, Eigen::Quaterniond::Identity(), {1, 1, 1})});
  es.joints.push_back(
      {"root", -1,
       trs({0.5, 0, -0.25}, Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), {1, 2, 1})});
  es.joints.push_back(
      {"bone1", 1, trs({0, 0.1, 0}, Eigen::Quaterniond(Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitZ())), {1, 1, 1})});
  model.skeleton = cgamesh::anim::Skeleton::build(es);

  cgamesh::mesh::Mesh cyl;
  cyl.name = "cylinder";
  constexpr int rings = 10, seg = 8;
  const int nv = rings * seg;
  cyl.positions.resize(nv, 3);
  cyl.normals.resize(nv, 3);
  cyl.uvs.resize(nv, 2);
  cyl.skin.joints.resize(nv, 4);
  cyl.skin.weights.resize(nv, 4);
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < seg; ++s) {
      const int v = r * seg + s;
      const double a = 2 * std::numbers::pi * s / seg;
      const double y = 2.0 * r / (rings - 1);
      cyl.positions.row(v) << static_cast<float>(0.3 * std::cos(a)), static_cast<float>(y),
          static_cast<float>(0.3 * std::sin(a));
      // Not unit length on purpose: the writer normalises.
      cyl.normals.row(v) << static_cast<float>(2 * std::cos(a)), 0.0f, static_cast<float>(2 * std::sin(a));
      cyl.uvs.row(v) << static_cast<float>(s) / seg, static_cast<float>(r) / (rings - 1);
      const float t = static_cast<float>(r) / (rings - 1);
      // Rows sum to 2 on odd rings (renormalised by the writer); slot 2 has joint 1 with weight 0.
      const float k = (r % 2 == 1) ? 2.0f : 1.0f;
      cyl.skin.joints.row(v) << 0, 1, 1, 0;
      cyl.skin.weights.row(v) << k * (1 - t), k * t, 0.0f, 0.0f;
    }
  cyl.faces.resize(Eigen::Index{2} * (rings - 1) * seg, 3);
  int f = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int s = 0; s < seg; ++s) {
      const int a = r * seg + s, b = r * seg + (s + 1) % seg, c = a + seg, d = b + seg;
      cyl.faces.row(f++) << a, c, b;
      cyl.faces.row(f++) << b, c, d;
    }
  const int bone1 = model.skeleton.find("bone1"), bone2 = model.skeleton.find("bone2");
  cyl.skin.palette = {bone1, bone2};
  for (int j : cyl.skin.palette) cyl.skin.inverse_bind.push_back(global_rest(model.skeleton, j).inverse());
  cyl.skin.inverse_bind[1](3, 0) = 1e-9;  // tiny noise in the last row: must come out exactly 0 0 0 1
  model.meshes.push_back(cyl);

  cgamesh::mesh::Mesh hat;
  hat.name = "hat";
  hat.positions.resize(3, 3);
  hat.positions << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  hat.faces.resize(1, 3);
  hat.faces << 0, 1, 2;
  hat.node = bone2;
  model.meshes.push_back(hat);

  cgamesh::mesh::Mesh ground;
  ground.name = "ground";
  ground.positions.resize(4, 3);
  ground.positions << -1, 0, -1, 1, 0, -1, 1, 0, 1, -1, 0, 1;
  ground.faces.resize(2, 3);
  ground.faces << 0, 2, 1, 0, 3, 2;
  model.meshes.push_back(ground);

  cgamesh::anim::Clip wave;
  wave.name = "wave";
  wave.channels.push_back(channel(bone1, ChannelPath::rotation, Interpolation::linear, {0, 0.5, 1},
                                  {0, 0, 0, 2, 0, 0, 0.5, 0.9, 0, 0, 1, 0}));  // first key not unit: normalised
  wave.channels.push_back(
      channel(bone1, ChannelPath::translation, Interpolation::step, {0, 0.25}, {0, 0.1, 0, 0.2, 0.1, 0}));
  wave.channels.push_back(channel(bone2, ChannelPath::scale, Interpolation::linear, {0, 1}, {1, 1, 1, 1.5, 0.5, 1}));
  const Eigen::Quaterniond q1(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()));
  wave.channels.push_back(channel(bone2, ChannelPath::rotation, Interpolation::cubic_spline, {0, 0.4, 1},
                                  {0.1, 0, 0,   0,   0,      0,      0,      1,      0,   0.1, 0, 0,     // key 0
                                   0,   0, 0.2, 0,   q1.x(), q1.y(), q1.z(), q1.w(), 0.3, 0,   0, 0,     // key 1
                                   0,   0, 0,   0.1, 0,      0,      0.6,    0.8,    0,   0,   0, 0}));  // key 2
  wave.channels.push_back(channel(0, ChannelPath::scale, Interpolation::linear, {}, {}));  // empty: skipped
  wave.duration = 1;
  model.clips.push_back(wave);

  cgamesh::anim::Clip idle;
  idle.name = "idle";
  idle.channels.push_back(
      channel(0, ChannelPath::translation, Interpolation::linear, {0, 2}, {0.5, 0, -0.25, 0.5, 0.1, -0.25}));
  idle.duration = 2;
  model.clips.push_back(idle);

  cgamesh::anim::Clip empty;
  empty.name = "empty";
  model.clips.push_back(empty);
  return model;
}

// ---- reading back -----------------------------------------------------------------------

tinygltf::Model load(const fs::path& file) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model m;
  std::string err, warn;
  const bool ok = file.extension() == ".glb" ? loader.LoadBinaryFromFile(&m, &err, &warn, file.string())
                                             : loader.LoadASCIIFromFile(&m, &err, &warn, file.string());
  EXPECT_TRUE(ok) << "tinygltf could not load " << file << ": " << err;
  EXPECT_TRUE(err.empty()) << err;
  EXPECT_TRUE(warn.empty()) << warn;
  return m;
}

int components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      ADD_FAILURE() << "unexpected accessor type " << type;
      return 0;
  }
}

/// All components of an accessor, in order (the buffer view's stride honoured).
template <class T>
std::vector<T> read(const tinygltf::Model& m, int accessor) {
  EXPECT_GE(accessor, 0);
  if (accessor < 0) return {};
  const tinygltf::Accessor& a = m.accessors[accessor];
  const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
  const tinygltf::Buffer& b = m.buffers[v.buffer];
  const int n = components(a.type);
  const std::size_t stride = v.byteStride != 0 ? v.byteStride : n * sizeof(T);
  EXPECT_EQ(static_cast<std::size_t>(tinygltf::GetComponentSizeInBytes(a.componentType)), sizeof(T));
  EXPECT_EQ(v.byteOffset % 4, 0u) << "buffer view not 4-byte aligned";
  EXPECT_LE(v.byteOffset + a.byteOffset + (a.count - 1) * stride + n * sizeof(T), b.data.size());
  EXPECT_LE(a.byteOffset + (a.count - 1) * stride + n * sizeof(T), v.byteLength);
  std::vector<T> out(a.count * n);
  for (std::size_t i = 0; i < a.count; ++i)
    std::memcpy(&out[i * n], b.data.data() + v.byteOffset + a.byteOffset + i * stride, n * sizeof(T));
  return out;
}

int node_named(const tinygltf::Model& m, const std::string& name) {
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    if (m.nodes[i].name == name) return static_cast<int>(i);
  return -1;
}

/// The node holding the glTF mesh named `name`, or -1.
int mesh_node(const tinygltf::Model& m, const std::string& name) {
  for (std::size_t n = 0; n < m.nodes.size(); ++n)
    if (m.nodes[n].mesh >= 0 && m.meshes[static_cast<std::size_t>(m.nodes[n].mesh)].name == name)
      return static_cast<int>(n);
  return -1;
}

int parent_of(const tinygltf::Model& m, int node) {
  int parent = -1;
  for (std::size_t i = 0; i < m.nodes.size(); ++i)
    for (int c : m.nodes[i].children)
      if (c == node) {
        EXPECT_EQ(parent, -1) << "node " << node << " has two parents";
        parent = static_cast<int>(i);
      }
  return parent;
}

/// Everything the reader sees must match `model` (from make_model()).
void check_model(const tinygltf::Model& g, const RiggedModel& model) {
  EXPECT_EQ(g.asset.version, "2.0");
  EXPECT_EQ(g.asset.generator, "cgamesh");
  const auto& sk = model.skeleton;

  // Nodes: joint i is node i, with its rest TRS and its parent.
  // The hat sits on bone2's own node; the cylinder and the ground (no node) get nodes of their own.
  ASSERT_EQ(g.nodes.size(), static_cast<std::size_t>(sk.size()) + 2);
  for (int j = 0; j < sk.size(); ++j) {
    const tinygltf::Node& n = g.nodes[j];
    SCOPED_TRACE("joint " + std::string(sk.names()[j]));
    EXPECT_EQ(n.name, sk.names()[j]);
    EXPECT_TRUE(n.matrix.empty());
    EXPECT_EQ(parent_of(g, j), sk.parents()[j]);
    const Transform& t = sk.rest()[j];
    const std::vector<double> tr = n.translation.empty() ? std::vector<double>{0, 0, 0} : n.translation;
    const std::vector<double> ro = n.rotation.empty() ? std::vector<double>{0, 0, 0, 1} : n.rotation;
    const std::vector<double> sc = n.scale.empty() ? std::vector<double>{1, 1, 1} : n.scale;
    const Eigen::Vector4d q = t.rotation.coeffs().normalized();
    for (int k = 0; k < 3; ++k) {
      EXPECT_DOUBLE_EQ(tr[k], t.translation[k]);
      EXPECT_DOUBLE_EQ(sc[k], t.scale[k]);
    }
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(ro[k], q[k], 1e-15);
  }
  const int root = sk.find("root"), bone1 = sk.find("bone1"), bone2 = sk.find("bone2");
  EXPECT_DOUBLE_EQ(g.nodes[root].scale.at(1), 2.0);  // non-uniform scale kept

  // Mesh nodes: skinned and ground at the scene root without transforms, hat on bone2.
  const int cyl = mesh_node(g, "cylinder"), hat = mesh_node(g, "hat"), ground = mesh_node(g, "ground");
  ASSERT_GE(cyl, sk.size());
  EXPECT_EQ(hat, bone2);
  ASSERT_GE(ground, sk.size());
  for (int n : {cyl, ground}) {
    EXPECT_TRUE(g.nodes[n].translation.empty() && g.nodes[n].rotation.empty() && g.nodes[n].scale.empty() &&
                g.nodes[n].matrix.empty());
    EXPECT_GE(g.nodes[n].mesh, 0);
    EXPECT_TRUE(g.nodes[n].children.empty());
  }
  EXPECT_EQ(parent_of(g, cyl), -1);
  EXPECT_EQ(parent_of(g, ground), -1);
  EXPECT_EQ(g.nodes[cyl].skin, 0);
  EXPECT_EQ(g.nodes[hat].skin, -1);
  ASSERT_EQ(g.scenes.size(), 1u);
  EXPECT_EQ(g.defaultScene, 0);
  std::vector<int> roots = g.scenes[0].nodes;
  std::sort(roots.begin(), roots.end());
  EXPECT_EQ(roots, (std::vector<int>{root, cyl, ground}));

  // Meshes.
  ASSERT_EQ(g.meshes.size(), 3u);
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const auto& src = model.meshes[i];
    const int node = mesh_node(g, src.name);
    ASSERT_GE(node, 0);
    const tinygltf::Mesh& gm = g.meshes[g.nodes[node].mesh];
    SCOPED_TRACE("mesh " + src.name);
    EXPECT_EQ(gm.name, src.name);
    ASSERT_EQ(gm.primitives.size(), 1u);
    const tinygltf::Primitive& p = gm.primitives[0];
    EXPECT_EQ(p.mode, TINYGLTF_MODE_TRIANGLES);
    const Eigen::Index nv = src.vertex_count();

    // POSITION: exact values and exact min/max.
    const int pa = p.attributes.at("POSITION");
    const tinygltf::Accessor& pos_acc = g.accessors[pa];
    EXPECT_EQ(pos_acc.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
    EXPECT_EQ(pos_acc.type, TINYGLTF_TYPE_VEC3);
    EXPECT_EQ(pos_acc.count, static_cast<std::size_t>(nv));
    EXPECT_EQ(g.bufferViews[pos_acc.bufferView].target, TINYGLTF_TARGET_ARRAY_BUFFER);
    const auto pos = read<float>(g, pa);
    for (Eigen::Index v = 0; v < nv; ++v)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(pos[3 * v + c], src.positions(v, c));
    ASSERT_EQ(pos_acc.minValues.size(), 3u);
    ASSERT_EQ(pos_acc.maxValues.size(), 3u);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(pos_acc.minValues[c], src.positions.col(c).minCoeff());
      EXPECT_EQ(pos_acc.maxValues[c], src.positions.col(c).maxCoeff());
    }

    // Indices: the faces, as unsigned short.
    const tinygltf::Accessor& ia = g.accessors[p.indices];
    EXPECT_EQ(ia.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
    EXPECT_EQ(ia.count, static_cast<std::size_t>(3 * src.face_count()));
    EXPECT_EQ(g.bufferViews[ia.bufferView].target, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    const auto idx = read<std::uint16_t>(g, p.indices);
    for (Eigen::Index f = 0; f < src.face_count(); ++f)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(idx[3 * f + c], src.faces(f, c));

    EXPECT_EQ(p.attributes.count("NORMAL"), src.normals.rows() > 0 ? 1u : 0u);
    EXPECT_EQ(p.attributes.count("TEXCOORD_0"), src.uvs.rows() > 0 ? 1u : 0u);
    EXPECT_EQ(p.attributes.count("JOINTS_0"), src.skin.empty() ? 0u : 1u);
    EXPECT_EQ(p.attributes.count("WEIGHTS_0"), src.skin.empty() ? 0u : 1u);
    if (src.normals.rows() > 0) {
      const auto n = read<float>(g, p.attributes.at("NORMAL"));
      for (Eigen::Index v = 0; v < nv; ++v) {
        const Eigen::Vector3f got(n[3 * v], n[3 * v + 1], n[3 * v + 2]);
        const Eigen::Vector3f want = src.normals.row(v).transpose().normalized();
        ASSERT_NEAR(got.norm(), 1.0f, 1e-6f);
        ASSERT_LT((got - want).norm(), 1e-6f);
      }
    }
    if (src.uvs.rows() > 0) {
      const auto uv = read<float>(g, p.attributes.at("TEXCOORD_0"));
      // glTF's v runs down the image: the file holds (u, 1 − v) of the OpenGL-style Mesh::uvs.
      for (Eigen::Index v = 0; v < nv; ++v) {
        ASSERT_EQ(uv[2 * v], src.uvs(v, 0));
        ASSERT_EQ(uv[2 * v + 1], 1.0f - src.uvs(v, 1));
      }
    }
    if (!src.skin.empty()) {
      const tinygltf::Accessor& ja = g.accessors[p.attributes.at("JOINTS_0")];
      const tinygltf::Accessor& wa = g.accessors[p.attributes.at("WEIGHTS_0")];
      EXPECT_EQ(ja.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
      EXPECT_EQ(ja.type, TINYGLTF_TYPE_VEC4);
      EXPECT_EQ(wa.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
      EXPECT_EQ(wa.type, TINYGLTF_TYPE_VEC4);
      const auto js = read<std::uint16_t>(g, p.attributes.at("JOINTS_0"));
      const auto ws = read<float>(g, p.attributes.at("WEIGHTS_0"));
      // The same influences per joint (in any slots), by decreasing weight, unused slots (0, 0).
      for (Eigen::Index v = 0; v < nv; ++v) {
        double sum = 0, src_sum = src.skin.weights.row(v).cast<double>().sum();
        std::map<int, double> want, got;
        for (int k = 0; k < 4; ++k) {
          if (src.skin.weights(v, k) > 0) want[src.skin.joints(v, k)] += src.skin.weights(v, k) / src_sum;
          const float w = ws[4 * v + k];
          sum += w;
          ASSERT_GE(w, 0.0f);
          if (k > 0) {
            ASSERT_LE(w, ws[4 * v + k - 1]) << "vertex " << v;
          }
          if (w == 0.0f) {
            ASSERT_EQ(js[4 * v + k], 0) << "vertex " << v << " slot " << k << " has zero weight";
          } else {
            got[js[4 * v + k]] += w;
          }
        }
        ASSERT_EQ(got.size(), want.size()) << "vertex " << v;
        for (const auto& [j, w] : want) ASSERT_NEAR(got[j], w, 1e-6) << "vertex " << v << " joint " << j;
        ASSERT_NEAR(sum, 1.0, 1e-6) << "vertex " << v;
      }

      // Skin: palette as node indices, inverse bind matrices with an exact last row.
      const tinygltf::Skin& s = g.skins.at(g.nodes[node].skin);
      EXPECT_EQ(s.joints, src.skin.palette);
      EXPECT_EQ(s.skeleton, bone1);  // the lowest common ancestor of bone1 and bone2
      const tinygltf::Accessor& ib = g.accessors[s.inverseBindMatrices];
      EXPECT_EQ(ib.type, TINYGLTF_TYPE_MAT4);
      EXPECT_EQ(ib.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
      EXPECT_EQ(ib.count, src.skin.palette.size());
      EXPECT_EQ(g.bufferViews[ib.bufferView].target, 0);
      const auto m = read<float>(g, s.inverseBindMatrices);
      for (std::size_t k = 0; k < src.skin.palette.size(); ++k) {
        const float* col = &m[16 * k];  // column-major
        EXPECT_EQ(col[3], 0.0f);
        EXPECT_EQ(col[7], 0.0f);
        EXPECT_EQ(col[11], 0.0f);
        EXPECT_EQ(col[15], 1.0f);
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c) EXPECT_EQ(col[4 * c + r], static_cast<float>(src.skin.inverse_bind[k](r, c)));
      }
    }
  }
  EXPECT_EQ(g.skins.size(), 1u);

  // Animations: clips with keys, samplers equal to the channels.
  ASSERT_EQ(g.animations.size(), 2u);  // "empty" is skipped
  for (const tinygltf::Animation& a : g.animations) {
    const int ci = model.find_clip(a.name);
    ASSERT_GE(ci, 0) << a.name;
    const auto& clip = model.clips[ci];
    std::vector<const Channel*> channels;
    for (const Channel& c : clip.channels)
      if (!c.times.empty()) channels.push_back(&c);
    ASSERT_EQ(a.channels.size(), channels.size());
    ASSERT_EQ(a.samplers.size(), channels.size());
    for (std::size_t k = 0; k < channels.size(); ++k) {
      const Channel& c = *channels[k];
      const tinygltf::AnimationChannel& gc = a.channels[k];
      const tinygltf::AnimationSampler& gs = a.samplers[gc.sampler];
      SCOPED_TRACE(a.name + " channel " + std::to_string(k));
      EXPECT_EQ(gc.target_node, c.joint);
      EXPECT_EQ(gc.target_path, c.path == ChannelPath::translation ? "translation"
                                : c.path == ChannelPath::rotation  ? "rotation"
                                                                   : "scale");
      EXPECT_EQ(gs.interpolation, c.interpolation == Interpolation::step     ? "STEP"
                                  : c.interpolation == Interpolation::linear ? "LINEAR"
                                                                             : "CUBICSPLINE");
      const tinygltf::Accessor& in = g.accessors[gs.input];
      EXPECT_EQ(in.type, TINYGLTF_TYPE_SCALAR);
      EXPECT_EQ(in.count, c.times.size());
      ASSERT_EQ(in.minValues.size(), 1u);
      ASSERT_EQ(in.maxValues.size(), 1u);
      EXPECT_EQ(in.minValues[0], static_cast<float>(c.times.front()));
      EXPECT_EQ(in.maxValues[0], static_cast<float>(c.times.back()));
      const auto times = read<float>(g, gs.input);
      for (std::size_t t = 0; t < c.times.size(); ++t) EXPECT_EQ(times[t], static_cast<float>(c.times[t]));
      const tinygltf::Accessor& out = g.accessors[gs.output];
      const int n = c.components();
      EXPECT_EQ(out.type, n == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3);
      const std::size_t per_key = c.interpolation == Interpolation::cubic_spline ? 3 : 1;
      EXPECT_EQ(out.count, c.times.size() * per_key);
      const auto values = read<float>(g, gs.output);
      ASSERT_EQ(values.size(), c.values.size());
      for (std::size_t e = 0; e < values.size() / n; ++e) {
        const bool is_value = per_key == 1 || e % 3 == 1;
        double len = 1;
        if (c.path == ChannelPath::rotation && is_value) {
          len = 0;
          for (int i = 0; i < 4; ++i) len += c.values[e * 4 + i] * c.values[e * 4 + i];
          len = std::sqrt(len);
          double got = 0;
          for (int i = 0; i < 4; ++i) got += double(values[e * 4 + i]) * values[e * 4 + i];
          EXPECT_NEAR(std::sqrt(got), 1.0, 1e-6) << "rotation key " << e << " not unit";
        }
        for (int i = 0; i < n; ++i) EXPECT_NEAR(values[e * n + i], c.values[e * n + i] / len, 1e-7);
      }
    }
  }

  // Buffer views: 4-byte aligned, vertex attributes with a stride, animation data without.
  for (const tinygltf::BufferView& v : g.bufferViews) {
    EXPECT_EQ(v.byteOffset % 4, 0u);
    if (v.target == TINYGLTF_TARGET_ARRAY_BUFFER)
      EXPECT_GE(v.byteStride, 4u);
    else
      EXPECT_EQ(v.byteStride, 0u);
  }
}

bool contains(const std::vector<std::string>& warnings, const std::string& part) {
  return std::any_of(warnings.begin(), warnings.end(),
                     [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

TEST(GltfWriter, GlbRoundTrip) {
  TempDir dir;
  const RiggedModel model = make_model();
  const auto warnings = write_gltf(model, dir.path() / "model.glb");
  EXPECT_TRUE(contains(warnings, "'empty'")) << "the empty clip should be reported";
  EXPECT_EQ(warnings.size(), 1u);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"model.glb"});
  const tinygltf::Model g = load(dir.path() / "model.glb");
  ASSERT_EQ(g.buffers.size(), 1u);
  EXPECT_TRUE(g.buffers[0].uri.empty());
  check_model(g, model);
}

/// Clip `x` of `model` and clip `y` of `back` give every joint (matched by name) the same local
/// transform at every `step` from 0 to `end`.
void expect_plays_alike(const RiggedModel& model, const cgamesh::anim::Clip& x, const RiggedModel& back,
                        const cgamesh::anim::Clip& y, double end, double step, const std::string& name) {
  for (double t = 0; t <= end; t += step) {
    const auto a = cgamesh::anim::sample(model.skeleton, x, t, cgamesh::anim::BlendMode::format);
    const auto b = cgamesh::anim::sample(back.skeleton, y, t, cgamesh::anim::BlendMode::format);
    for (int j = 0; j < model.skeleton.size(); ++j) {
      const int k = back.skeleton.find(model.skeleton.names()[static_cast<std::size_t>(j)]);
      ASSERT_GE(k, 0);
      const auto &p = a.local[static_cast<std::size_t>(j)], &q = b.local[static_cast<std::size_t>(k)];
      EXPECT_LT((p.translation - q.translation).norm(), 1e-6) << name << " t=" << t << " joint " << j;
      EXPECT_LT(p.rotation.angularDistance(q.rotation), 1e-5) << name << " t=" << t << " joint " << j;
      EXPECT_LT((p.scale - q.scale).norm(), 1e-6) << name << " t=" << t << " joint " << j;
    }
  }
}

// Our own loader reads back STEP and CUBICSPLINE samplers (Assimp alone loads them as LINEAR):
// the reloaded clip samples like the original between keys, joint by joint (matched by name).
TEST(GltfWriter, ReloadedClipKeepsStepAndCubicInterpolation) {
  TempDir dir;
  const RiggedModel model = make_model();
  for (const char* name : {"model.glb", "model.gltf"}) {
    (void)write_gltf(model, dir.path() / name);
    const RiggedModel back = cgamesh::io::load_model(dir.path() / name);
    ASSERT_EQ(back.clips.size(), 2u) << name << ": the empty clip is not written";
    const cgamesh::anim::Clip& wave = back.clips[0];
    ASSERT_EQ(wave.name, "wave");
    std::multiset<Interpolation> kinds;
    for (const Channel& ch : wave.channels) kinds.insert(ch.interpolation);
    EXPECT_EQ(kinds.count(Interpolation::step), 1u) << name;
    EXPECT_EQ(kinds.count(Interpolation::cubic_spline), 1u) << name;
    expect_plays_alike(model, model.clips[0], back, wave, 1.0, 1.0 / 32, name);
  }
}

// glTF has no clip length: a clip declared longer than its keys (as OGRE and FBX files declare
// them) is written with keys at its end holding each channel's last value, so that the reloaded
// clip is as long and plays as the original everywhere, LINEAR, STEP and CUBICSPLINE alike (the
// cubic channel's new last segment has zero tangents: it holds, not overshoots).
TEST(GltfWriter, ClipLongerThanItsKeysHoldsItsLastValuesToItsEnd) {
  TempDir dir;
  RiggedModel model = make_model();
  model.clips[0].duration = 3;  // "wave": keys up to t = 1
  // The cubic channel's last out-tangent, which nothing uses before the clip is lengthened.
  Channel& cubic = model.clips[0].channels[3];
  ASSERT_EQ(cubic.interpolation, Interpolation::cubic_spline);
  cubic.values[cubic.values.size() - 4] = 0.5;
  (void)write_gltf(model, dir.path() / "long.glb");
  const tinygltf::Model g = load(dir.path() / "long.glb");
  ASSERT_EQ(g.animations[0].name, "wave");
  for (const tinygltf::AnimationSampler& s : g.animations[0].samplers)
    EXPECT_EQ(g.accessors[static_cast<std::size_t>(s.input)].maxValues.at(0), 3.0) << s.interpolation;
  for (const tinygltf::AnimationSampler& s : g.animations[1].samplers)  // "idle" ends at its last key
    EXPECT_EQ(g.accessors[static_cast<std::size_t>(s.input)].maxValues.at(0), 2.0);
  const RiggedModel back = cgamesh::io::load_model(dir.path() / "long.glb");
  const cgamesh::anim::Clip& wave = back.clips.at(0);
  EXPECT_EQ(wave.duration, 3.0);
  EXPECT_EQ(back.clips.at(1).duration, 2.0);
  expect_plays_alike(model, model.clips[0], back, wave, 3.0, 1.0 / 16, "long");
}

TEST(GltfWriter, GltfWithSeparateBinRoundTrip) {
  TempDir dir;
  const RiggedModel model = make_model();
  write_gltf(model, dir.path() / "model.gltf");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"model.bin", "model.gltf"}));
  const tinygltf::Model g = load(dir.path() / "model.gltf");
  ASSERT_EQ(g.buffers.size(), 1u);
  EXPECT_EQ(g.buffers[0].uri, "model.bin");
  EXPECT_EQ(g.buffers[0].data.size(), fs::file_size(dir.path() / "model.bin"));
  check_model(g, model);
}

TEST(GltfWriter, GltfEmbeddedBufferAndUppercaseExtension) {
  TempDir dir;
  const RiggedModel model = make_model();
  GltfWriteOptions options;
  options.embed_buffer = true;
  options.pretty_json = false;
  write_gltf(model, dir.path() / "model.GLTF", options);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"model.GLTF"});
  const fs::path copy = dir.path() / "copy.gltf";  // tinygltf picks the format by extension
  fs::copy_file(dir.path() / "model.GLTF", copy);
  const tinygltf::Model g = load(copy);
  ASSERT_EQ(g.buffers.size(), 1u);
  EXPECT_EQ(g.buffers[0].uri.rfind("data:", 0), 0u);
  check_model(g, model);
}

TEST(GltfWriter, BinFileNameNeedsNoPercentEncoding) {
  TempDir dir;
  const RiggedModel model = make_model();
  write_gltf(model, dir.path() / "my model+1.gltf");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"my model+1.gltf", "my_model_1.bin"}));
  const tinygltf::Model g = load(dir.path() / "my model+1.gltf");
  ASSERT_EQ(g.buffers.size(), 1u);
  EXPECT_EQ(g.buffers[0].uri, "my_model_1.bin");
  check_model(g, model);
}

TEST(GltfWriter, OverwritesAndLeavesNoTemporaries) {
  TempDir dir;
  const RiggedModel model = make_model();
  const fs::path out = dir.path() / "model.gltf";
  { std::ofstream(out) << "old"; }
  { std::ofstream(dir.path() / "model.bin") << "old"; }
  write_gltf(model, out);
  write_gltf(model, out);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"model.bin", "model.gltf"}));
  check_model(load(out), model);
}

TEST(GltfWriter, ZeroNormalDropsNormalsWithWarning) {
  TempDir dir;
  RiggedModel model = make_model();
  model.meshes[0].normals.row(5).setZero();
  const auto warnings = write_gltf(model, dir.path() / "m.glb");
  EXPECT_TRUE(contains(warnings, "NORMAL not written"));
  const tinygltf::Model g = load(dir.path() / "m.glb");
  EXPECT_EQ(g.meshes[0].primitives[0].attributes.count("NORMAL"), 0u);
  EXPECT_EQ(g.meshes[0].primitives[0].attributes.count("TEXCOORD_0"), 1u);
}

TEST(GltfWriter, LargeMeshUsesUnsignedIntIndices) {
  TempDir dir;
  RiggedModel model;
  cgamesh::mesh::Mesh grid;
  grid.name = "grid";
  constexpr int n = 256;  // 65536 vertices: index 65535 would be the restart value for u16
  grid.positions.resize(Eigen::Index{n} * n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) grid.positions.row(i * n + j) << float(i), float(j), 0.0f;
  grid.faces.resize(Eigen::Index{2} * (n - 1) * (n - 1), 3);
  int f = 0;
  for (int i = 0; i + 1 < n; ++i)
    for (int j = 0; j + 1 < n; ++j) {
      const int a = i * n + j;
      grid.faces.row(f++) << a, a + n, a + 1;
      grid.faces.row(f++) << a + 1, a + n, a + n + 1;
    }
  model.meshes.push_back(grid);
  write_gltf(model, dir.path() / "grid.glb");
  const tinygltf::Model g = load(dir.path() / "grid.glb");
  ASSERT_EQ(g.meshes.size(), 1u);
  const tinygltf::Accessor& ia = g.accessors[g.meshes[0].primitives[0].indices];
  EXPECT_EQ(ia.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  const auto idx = read<std::uint32_t>(g, g.meshes[0].primitives[0].indices);
  ASSERT_EQ(idx.size(), static_cast<std::size_t>(3 * grid.face_count()));
  EXPECT_EQ(*std::max_element(idx.begin(), idx.end()), 65535u);
  EXPECT_EQ(g.nodes.size(), 1u);
  EXPECT_EQ(g.scenes.at(0).nodes, std::vector<int>{0});
}

TEST(GltfWriter, DuplicateJointInVertexIsMerged) {
  TempDir dir;
  RiggedModel model = make_model();
  auto& skin = model.meshes[0].skin;
  skin.joints.row(3) << 1, 0, 1, 0;
  skin.weights.row(3) << 0.25f, 0.5f, 0.25f, 0.0f;
  const auto warnings = write_gltf(model, dir.path() / "m.glb");
  EXPECT_TRUE(contains(warnings, "merged"));
  const tinygltf::Model g = load(dir.path() / "m.glb");
  const auto js = read<std::uint16_t>(g, g.meshes[0].primitives[0].attributes.at("JOINTS_0"));
  const auto ws = read<float>(g, g.meshes[0].primitives[0].attributes.at("WEIGHTS_0"));
  // Joint 1's two entries make 0.5, as much as joint 0's: a tie, which the smaller joint leads.
  EXPECT_EQ(js[12], 0);
  EXPECT_FLOAT_EQ(ws[12], 0.5f);
  EXPECT_EQ(js[13], 1);
  EXPECT_FLOAT_EQ(ws[13], 0.5f);
  EXPECT_EQ(js[14], 0);
  EXPECT_EQ(ws[14], 0.0f);
}

TEST(GltfWriter, SkinAcrossTwoTreesGetsACommonRoot) {
  TempDir dir;
  RiggedModel model = make_model();
  cgamesh::anim::EditableSkeleton es;
  es.joints.push_back({"a", -1, trs({1, 0, 0}, Eigen::Quaterniond::Identity(), {1, 1, 1})});
  es.joints.push_back({"b", -1, trs({-1, 0, 0}, Eigen::Quaterniond::Identity(), {1, 1, 1})});
  es.joints.push_back({"c", 1, trs({0, 1, 0}, Eigen::Quaterniond::Identity(), {1, 1, 1})});
  model.skeleton = cgamesh::anim::Skeleton::build(es);
  model.meshes.resize(1);
  model.meshes[0].skin.palette = {0, 2};
  model.clips.clear();
  const auto warnings = write_gltf(model, dir.path() / "m.glb");
  EXPECT_TRUE(contains(warnings, "cgamesh_root"));
  const tinygltf::Model g = load(dir.path() / "m.glb");
  const int root = node_named(g, "cgamesh_root");
  ASSERT_GE(root, 0);
  EXPECT_EQ(g.skins.at(0).skeleton, root);
  EXPECT_EQ(parent_of(g, 0), root);
  EXPECT_EQ(parent_of(g, 1), root);
  EXPECT_EQ(parent_of(g, 2), 1);
  std::vector<int> roots = g.scenes.at(0).nodes;
  std::sort(roots.begin(), roots.end());
  std::vector<int> want{node_named(g, "cylinder"), root};
  std::sort(want.begin(), want.end());
  EXPECT_EQ(roots, want);  // the skinned mesh's node and the new root
}

TEST(GltfWriter, SingleCubicKeyIsWrittenAsStep) {
  TempDir dir;
  RiggedModel model = make_model();
  model.clips[2].channels.push_back(
      channel(0, ChannelPath::scale, Interpolation::cubic_spline, {0.5}, {9, 9, 9, 1, 2, 3, 9, 9, 9}));
  const auto warnings = write_gltf(model, dir.path() / "m.glb");
  EXPECT_TRUE(contains(warnings, "written as STEP"));
  const tinygltf::Model g = load(dir.path() / "m.glb");
  ASSERT_EQ(g.animations.size(), 3u);
  const tinygltf::AnimationSampler& s = g.animations[2].samplers.at(0);
  EXPECT_EQ(s.interpolation, "STEP");
  EXPECT_EQ(read<float>(g, s.output), (std::vector<float>{1, 2, 3}));
}

// ---- errors: throw, and leave the directory as it was ----------------------------------------

template <class Mutate>
void expect_rejected(Mutate mutate, const std::string& name = "bad.glb") {
  for (const std::string& file : {name, std::string("bad.gltf")}) {
    TempDir dir;
    RiggedModel model = make_model();
    mutate(model);
    EXPECT_THROW(write_gltf(model, dir.path() / file), InvalidInputError) << file;
    EXPECT_TRUE(dir.entries().empty()) << file << ": the directory is not empty";
  }
}

TEST(GltfWriterErrors, UnknownExtension) {
  TempDir dir;
  EXPECT_THROW(write_gltf(make_model(), dir.path() / "model.obj"), InvalidInputError);
  EXPECT_THROW(write_gltf(make_model(), dir.path() / "model"), InvalidInputError);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(GltfWriterErrors, EmptyModel) {
  expect_rejected([](RiggedModel& m) { m.meshes.clear(); });
}

TEST(GltfWriterErrors, NanPosition) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].positions(7, 1) = std::nanf(""); });
}

TEST(GltfWriterErrors, FaceIndexOutOfRange) {
  expect_rejected([](RiggedModel& m) { m.meshes[1].faces(0, 2) = 3; });
}

TEST(GltfWriterErrors, NormalRowsMismatch) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].normals.conservativeResize(10, 3); });
}

TEST(GltfWriterErrors, PaletteJointOutsideSkeleton) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].skin.palette[1] = 3; });
}

TEST(GltfWriterErrors, PaletteJointRepeated) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].skin.palette[1] = m.meshes[0].skin.palette[0]; });
}

TEST(GltfWriterErrors, PaletteAndInverseBindSizesDiffer) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].skin.inverse_bind.pop_back(); });
}

TEST(GltfWriterErrors, WeightRowsMismatch) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].skin.weights.conservativeResize(5, 4); });
}

TEST(GltfWriterErrors, SkinJointIndexOutOfPalette) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].skin.joints(4, 3) = 2; });
}

TEST(GltfWriterErrors, ZeroWeightRow) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].skin.weights.row(4).setZero(); });
}

TEST(GltfWriterErrors, NegativeWeight) {
  expect_rejected([](RiggedModel& m) { m.meshes[0].skin.weights(4, 2) = -0.1f; });
}

TEST(GltfWriterErrors, StaticMeshNodeOutsideSkeleton) {
  expect_rejected([](RiggedModel& m) { m.meshes[1].node = 17; });
}

TEST(GltfWriterErrors, ChannelJointOutsideSkeleton) {
  expect_rejected([](RiggedModel& m) { m.clips[0].channels[0].joint = 3; });
}

TEST(GltfWriterErrors, DuplicateChannelTarget) {
  expect_rejected([](RiggedModel& m) { m.clips[0].channels.push_back(m.clips[0].channels[0]); });
}

TEST(GltfWriterErrors, KeyTimesNotIncreasing) {
  expect_rejected([](RiggedModel& m) { m.clips[0].channels[0].times = {0, 0.5, 0.5 + 1e-12}; });
}

TEST(GltfWriterErrors, ValueCountMismatch) {
  expect_rejected([](RiggedModel& m) { m.clips[0].channels[3].values.pop_back(); });
}

TEST(GltfWriterErrors, ZeroRotationKey) {
  expect_rejected([](RiggedModel& m) {
    auto& v = m.clips[0].channels[0].values;
    std::fill(v.begin(), v.begin() + 4, 0.0);
  });
}

TEST(GltfWriterErrors, NameNotUtf8) {
  expect_rejected([](RiggedModel& m) { m.meshes[1].name = "caf\xe9"; });
}

TEST(GltfWriterErrors, MissingDirectoryIsAWriteError) {
  TempDir dir;
  EXPECT_THROW(write_gltf(make_model(), dir.path() / "no" / "such" / "m.glb"), cgamesh::WriteError);
  EXPECT_THROW(write_gltf(make_model(), dir.path() / "no" / "such" / "m.gltf"), cgamesh::WriteError);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(GltfWriterErrors, GltfAndBinAppearTogetherOrNotAtAll) {
  TempDir dir;
  // The .gltf target is a directory: renaming onto it fails after the .bin was put in place.
  fs::create_directory(dir.path() / "m.gltf");
  { std::ofstream(dir.path() / "m.bin") << "previous"; }
  EXPECT_THROW(write_gltf(make_model(), dir.path() / "m.gltf"), cgamesh::WriteError);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"m.bin", "m.gltf"}));
  std::ifstream in(dir.path() / "m.bin");
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(content, "previous") << "the previous .bin must be restored";
}

// ---- Khronos glTF validator ---------------------------------------------------------------------

TEST(GltfWriterValidator, KhronosValidatorReportsNoErrors) {
  if (!cgamesh_test::validator_available())
    GTEST_SKIP() << "node or tests/oracle/js/node_modules is missing (npm ci there)";

  TempDir dir;
  RiggedModel model = make_model();
  // Also a single-key cubic channel and a cross-tree skin variant.
  model.clips[2].channels.push_back(
      channel(0, ChannelPath::scale, Interpolation::cubic_spline, {0.5}, {0, 0, 0, 1, 2, 3, 0, 0, 0}));
  RiggedModel two_trees = make_model();
  {
    cgamesh::anim::EditableSkeleton es;
    es.joints.push_back({"a", -1, trs({1, 0, 0}, Eigen::Quaterniond::Identity(), {1, 1, 1})});
    es.joints.push_back({"b", -1, trs({-1, 0, 0}, Eigen::Quaterniond::Identity(), {1, 1, 1})});
    es.joints.push_back({"c", 1, trs({0, 1, 0}, Eigen::Quaterniond::Identity(), {1, 1, 1})});
    two_trees.skeleton = cgamesh::anim::Skeleton::build(es);
    two_trees.meshes[0].skin.palette = {0, 2};
  }
  write_gltf(model, dir.path() / "model.glb");
  write_gltf(model, dir.path() / "model.gltf");
  write_gltf(two_trees, dir.path() / "two trees.gltf");
  for (const char* name : {"model.glb", "model.gltf", "two trees.gltf"}) {
    std::string text;
    const int status = cgamesh_test::validate_gltf(dir.path() / name, text);
    EXPECT_EQ(status, 0) << name << ":\n" << text;
    EXPECT_NE(text.find(" 0 error(s)"), std::string::npos) << text;
  }
}

}  // namespace
