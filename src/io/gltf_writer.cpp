#include "cgamesh/io/gltf_writer.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <new>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/mesh/influences.hpp"

#include "gltf_extras_reader.hpp"
#include "cgamesh/io/file_extension.hpp"

namespace cgamesh::io {
namespace {

namespace fs = std::filesystem;
using anim::Channel;
using anim::ChannelPath;
using anim::Interpolation;

/// The name of the .bin next to `gltf`: its stem with every character outside [A-Za-z0-9._-]
/// replaced by '_', so the URI needs no percent-encoding (which Assimp and tinygltf do not
/// decode).
std::string bin_file_name(const fs::path& gltf) {
  std::string name = gltf.stem().string();
  for (char& c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (!(u < 128 && (std::isalnum(u) || c == '-' || c == '.' || c == '_'))) c = '_';
  }
  return name + ".bin";
}

std::string mesh_label(const mesh::Mesh& m, std::size_t index) {
  return "mesh " + std::to_string(index) + (m.name.empty() ? std::string() : " ('" + m.name + "')");
}

bool finite(double x) { return std::isfinite(x); }

[[noreturn]] void invalid(const std::string& message) { throw InvalidInputError("write_gltf: " + message); }

/// Builds the tinygltf model: one buffer, little-endian data appended view by view.
class Builder {
 public:
  Builder(const anim::RiggedModel& model, std::vector<std::string>& warnings) : model_(model), warnings_(warnings) {
    gm_.buffers.resize(1);
    gm_.asset.version = "2.0";
    gm_.asset.generator = "cgamesh";
  }

  tinygltf::Model run() {
    if (model_.meshes.empty()) invalid("the model has no mesh");
    add_joint_nodes();
    gm_.scenes.resize(1);
    gm_.defaultScene = 0;
    add_meshes();  // may add the synthetic root, so scene roots come after
    if (synthetic_root_ >= 0) {
      gm_.scenes[0].nodes.push_back(synthetic_root_);
    } else {
      for (int j = 0; j < skeleton_size(); ++j)
        if (model_.skeleton.parents()[j] < 0) gm_.scenes[0].nodes.push_back(j);
    }
    for (int n : mesh_roots_) gm_.scenes[0].nodes.push_back(n);
    for (std::size_t c = 0; c < model_.clips.size(); ++c) add_clip(model_.clips[c], c);
    return std::move(gm_);
  }

 private:
  [[nodiscard]] int skeleton_size() const { return model_.skeleton.size(); }
  std::vector<unsigned char>& data() { return gm_.buffers[0].data; }

  // ---- buffer -------------------------------------------------------------------------------

  void put_u32(std::uint32_t v) {
    for (int b = 0; b < 4; ++b) data().push_back(static_cast<unsigned char>(v >> (8 * b)));
  }
  void put_u16(std::uint16_t v) {
    data().push_back(static_cast<unsigned char>(v & 0xff));
    data().push_back(static_cast<unsigned char>(v >> 8));
  }
  void put_f32(float v) { put_u32(std::bit_cast<std::uint32_t>(v)); }

  /// Starts a buffer view at a 4-byte boundary; returns its byte offset.
  std::size_t begin_view() {
    while (data().size() % 4 != 0) data().push_back(0);
    return data().size();
  }
  int end_view(std::size_t begin, int target, int stride) {
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = begin;
    v.byteLength = data().size() - begin;
    v.target = target;
    v.byteStride = static_cast<std::size_t>(stride);
    gm_.bufferViews.push_back(std::move(v));
    return static_cast<int>(gm_.bufferViews.size()) - 1;
  }
  int add_accessor(int view, int component_type, int type, std::size_t count, std::vector<double> min = {},
                   std::vector<double> max = {}) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = 0;
    a.componentType = component_type;
    a.type = type;
    a.count = count;
    a.minValues = std::move(min);
    a.maxValues = std::move(max);
    gm_.accessors.push_back(std::move(a));
    return static_cast<int>(gm_.accessors.size()) - 1;
  }
  /// Float vertex attribute or sampler data: `rows` x `cols` row-major floats.
  int add_float_accessor(const float* values, std::size_t rows, int cols, int type, int target, bool bounds) {
    const std::size_t begin = begin_view();
    std::vector<double> mn, mx;
    if (bounds) {
      mn.assign(cols, std::numeric_limits<double>::infinity());
      mx.assign(cols, -std::numeric_limits<double>::infinity());
    }
    for (std::size_t r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const float v = values[r * cols + c];
        put_f32(v);
        if (bounds) {
          mn[c] = std::min(mn[c], static_cast<double>(v));
          mx[c] = std::max(mx[c], static_cast<double>(v));
        }
      }
    const int stride = target == TINYGLTF_TARGET_ARRAY_BUFFER ? 4 * cols : 0;
    const int view = end_view(begin, target, stride);
    return add_accessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, type, rows, std::move(mn), std::move(mx));
  }

  // ---- skeleton -----------------------------------------------------------------------------

  void add_joint_nodes() {
    const auto& sk = model_.skeleton;
    gm_.nodes.resize(static_cast<std::size_t>(sk.size()));
    for (int j = 0; j < sk.size(); ++j) {
      tinygltf::Node& n = gm_.nodes[j];
      n.name = sk.names()[j];
      const anim::Transform& t = sk.rest()[j];
      const Eigen::Vector4d q = t.rotation.coeffs();  // x y z w
      if (!t.translation.allFinite() || !q.allFinite() || !t.scale.allFinite())
        invalid("joint '" + n.name + "' has a NaN or infinite rest transform");
      if (!(q.norm() > 0)) invalid("joint '" + n.name + "' has a zero rest rotation");
      if (!t.translation.isZero(0)) n.translation = {t.translation.x(), t.translation.y(), t.translation.z()};
      const Eigen::Vector4d qn = q / q.norm();
      if (qn != Eigen::Vector4d(0, 0, 0, 1)) n.rotation = {qn.x(), qn.y(), qn.z(), qn.w()};
      if (t.scale != Eigen::Vector3d::Ones()) n.scale = {t.scale.x(), t.scale.y(), t.scale.z()};
      const int p = sk.parents()[j];
      if (p >= 0) gm_.nodes[p].children.push_back(j);
    }
    depth_.resize(static_cast<std::size_t>(sk.size()));
    static_children_.assign(static_cast<std::size_t>(sk.size()), 0);
    for (int j = 0; j < sk.size(); ++j) depth_[j] = sk.parents()[j] < 0 ? 0 : depth_[sk.parents()[j]] + 1;
  }

  /// Lowest common ancestor of two joints, or -1 when they lie in different trees.
  [[nodiscard]] int common_ancestor(int a, int b) const {
    const auto parents = model_.skeleton.parents();
    while (a != b && a >= 0 && b >= 0) {
      if (depth_[a] >= depth_[b])
        a = parents[a];
      else
        b = parents[b];
    }
    return a == b ? a : -1;
  }

  /// The extra root above every skeleton root (made once, when a skin spans several trees).
  int synthetic_root() {
    if (synthetic_root_ < 0) {
      tinygltf::Node root;
      root.name = "cgamesh_root";
      for (int j = 0; j < skeleton_size(); ++j)
        if (model_.skeleton.parents()[j] < 0) root.children.push_back(j);
      gm_.nodes.push_back(std::move(root));
      synthetic_root_ = static_cast<int>(gm_.nodes.size()) - 1;
      warnings_.push_back("the joints of a skin lie in several trees: added the root node 'cgamesh_root' above them");
    }
    return synthetic_root_;
  }

  // ---- meshes -------------------------------------------------------------------------------

  void add_meshes() {
    for (std::size_t i = 0; i < model_.meshes.size(); ++i) add_mesh(model_.meshes[i], i);
  }

  void add_mesh(const mesh::Mesh& m, std::size_t index) {
    const std::string label = mesh_label(m, index);
    const Eigen::Index nv = m.vertex_count();
    if (nv == 0 || m.face_count() == 0) invalid(label + " has no vertices or no faces");
    if (!m.positions.allFinite()) invalid(label + " has NaN or infinite positions");
    if (m.normals.rows() != 0 && m.normals.rows() != nv)
      invalid(label + " has " + std::to_string(m.normals.rows()) + " normals for " + std::to_string(nv) + " vertices");
    if (m.uvs.rows() != 0 && m.uvs.rows() != nv)
      invalid(label + " has " + std::to_string(m.uvs.rows()) + " texture coordinates for " + std::to_string(nv) +
              " vertices");
    if (!m.uvs.allFinite()) invalid(label + " has NaN or infinite texture coordinates");
    if (m.faces.size() > 0 && (m.faces.minCoeff() < 0 || m.faces.maxCoeff() >= nv))
      invalid(label + " has a face index outside [0, " + std::to_string(nv) + ")");
    if (m.face_materials.rows() != 0 && m.face_materials.rows() != m.face_count())
      invalid(label + " has " + std::to_string(m.face_materials.rows()) + " face materials for " +
              std::to_string(m.face_count()) + " faces");

    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.attributes["POSITION"] = add_float_accessor(m.positions.data(), static_cast<std::size_t>(nv), 3,
                                                     TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    if (m.normals.rows() == nv) add_normals(m, prim, label);
    if (m.uvs.rows() == nv) {
      // glTF's v runs down the image; Mesh::uvs follow OpenGL (v up), as Assimp loads them.
      mesh::RowMatrixXf<2> uv = m.uvs;
      uv.col(1) = (1.0f - uv.col(1).array()).matrix();
      prim.attributes["TEXCOORD_0"] = add_float_accessor(uv.data(), static_cast<std::size_t>(nv), 2, TINYGLTF_TYPE_VEC2,
                                                         TINYGLTF_TARGET_ARRAY_BUFFER, false);
    }
    if (m.generated.rows() == nv && (m.generated.array() != 0).any()) {
      const std::vector<float> flags(m.generated.data(), m.generated.data() + nv);
      prim.attributes[detail::kGeneratedAttribute] = add_float_accessor(
          flags.data(), static_cast<std::size_t>(nv), 1, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    }
    int skin = -1;
    if (!m.skin.empty()) skin = add_skin(m, prim, label);
    if (!m.morph_targets.empty()) add_morph_targets(m, prim, label);

    // One primitive per material, in order of first use, all over the same vertex accessors.
    std::vector<int> materials;
    std::vector<std::vector<int>> faces_of;
    std::map<int, std::size_t> group;
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      const auto [it, added] = group.try_emplace(m.face_material(f), materials.size());
      if (added) {
        materials.push_back(it->first);
        faces_of.emplace_back();
      }
      faces_of[it->second].push_back(static_cast<int>(f));
    }
    tinygltf::Mesh gmesh;
    gmesh.name = m.name;
    gmesh.weights.assign(m.morph_weights.begin(), m.morph_weights.end());
    if (std::any_of(m.morph_targets.begin(), m.morph_targets.end(), [](const auto& t) { return !t.name.empty(); })) {
      // The de-facto convention (Blender, three.js, Babylon): names in mesh.extras.targetNames.
      tinygltf::Value::Array names;
      for (const mesh::MorphTarget& t : m.morph_targets) names.emplace_back(t.name);
      tinygltf::Value::Object extras;
      extras["targetNames"] = tinygltf::Value(std::move(names));
      gmesh.extras = tinygltf::Value(std::move(extras));
    }
    for (std::size_t g = 0; g < materials.size(); ++g) {
      tinygltf::Primitive p = prim;
      p.material = material_of(materials[g], prim.attributes.count("TEXCOORD_0") != 0, label);
      p.indices = add_indices(m, faces_of[g]);
      gmesh.primitives.push_back(std::move(p));
    }
    gm_.meshes.push_back(std::move(gmesh));

    // On its own node where that node holds no mesh yet, so that a read-write cycle adds no node.
    const int mesh_index = static_cast<int>(gm_.meshes.size()) - 1;
    if (m.node >= 0 && m.node < skeleton_size() && gm_.nodes[static_cast<std::size_t>(m.node)].mesh < 0) {
      gm_.nodes[static_cast<std::size_t>(m.node)].mesh = mesh_index;
      gm_.nodes[static_cast<std::size_t>(m.node)].skin = skin;
      if (!m.morph_targets.empty()) morph_nodes_[m.node].push_back({m.node, m.morph_targets.size()});
      return;
    }
    tinygltf::Node node;
    node.name = m.name;
    node.mesh = mesh_index;
    node.skin = skin;
    gm_.nodes.push_back(std::move(node));
    const int node_index = static_cast<int>(gm_.nodes.size()) - 1;
    if (!m.morph_targets.empty()) morph_nodes_[m.node].push_back({node_index, m.morph_targets.size()});
    if (skin >= 0 || m.node == -1) {
      mesh_roots_.push_back(node_index);
    } else {
      if (m.node < 0 || m.node >= skeleton_size())
        invalid(label + " hangs from node " + std::to_string(m.node) + " outside the skeleton of " +
                std::to_string(skeleton_size()) + " joints");
      // Before the joint's own children, in model order: a reader walking the hierarchy depth
      // first (Assimp, cgamesh's loader) then meets the static meshes in the model's order.
      auto& children = gm_.nodes[m.node].children;
      children.insert(children.begin() + static_children_[m.node]++, node_index);
    }
  }

  /// The morph targets of `m` on `prim`: displacements of POSITION (and NORMAL).
  void add_morph_targets(const mesh::Mesh& m, tinygltf::Primitive& prim, const std::string& label) {
    const Eigen::Index nv = m.vertex_count();
    if (m.morph_weights.size() != m.morph_targets.size())
      invalid(label + " has " + std::to_string(m.morph_weights.size()) + " morph weights for " +
              std::to_string(m.morph_targets.size()) + " morph targets");
    for (const float w : m.morph_weights)
      if (!finite(w)) invalid(label + " has a NaN or infinite morph weight");
    for (const mesh::MorphTarget& t : m.morph_targets) {
      const std::string what = label + ", morph target '" + t.name + "'";
      if (t.positions.rows() != nv || (t.normals.rows() != 0 && t.normals.rows() != nv))
        invalid(what + " does not have a row per vertex");
      if (!t.positions.allFinite() || !t.normals.allFinite()) invalid(what + " has NaN or infinite displacements");
      std::map<std::string, int> target;
      target["POSITION"] = add_displacements(t.positions, true);
      if (t.normals.rows() == nv && m.normals.rows() == nv) target["NORMAL"] = add_displacements(t.normals, false);
      prim.targets.push_back(std::move(target));
    }
  }

  /// A VEC3 accessor of #V displacements: sparse (the rows that move, by index) where that is
  /// smaller than every row (an index and a row against a row). Where none moves, one zero row
  /// is still written: an accessor without data is valid glTF, but Assimp refuses to read it.
  int add_displacements(const mesh::RowMatrixXf<3>& d, bool bounds) {
    const auto nv = static_cast<std::size_t>(d.rows());
    std::vector<std::uint32_t> moved;
    for (Eigen::Index v = 0; v < d.rows(); ++v)
      if ((d.row(v).array() != 0).any()) moved.push_back(static_cast<std::uint32_t>(v));
    if (moved.size() * 16 >= nv * 12)
      return add_float_accessor(d.data(), nv, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, bounds);
    std::vector<double> mn, mx;
    if (bounds) {
      // The rows that do not move are zeros, and there are some.
      mn.assign(3, 0.0);
      mx.assign(3, 0.0);
      for (const std::uint32_t v : moved)
        for (int c = 0; c < 3; ++c) {
          mn[static_cast<std::size_t>(c)] = std::min(mn[static_cast<std::size_t>(c)], static_cast<double>(d(v, c)));
          mx[static_cast<std::size_t>(c)] = std::max(mx[static_cast<std::size_t>(c)], static_cast<double>(d(v, c)));
        }
    }
    const int accessor = add_accessor(-1, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, nv, mn, mx);
    if (moved.empty()) moved.push_back(0);
    std::size_t begin = begin_view();
    for (const std::uint32_t v : moved) put_u32(v);
    const int indices = end_view(begin, 0, 0);
    begin = begin_view();
    for (const std::uint32_t v : moved)
      for (int c = 0; c < 3; ++c) put_f32(d(v, c));
    const int values = end_view(begin, 0, 0);
    tinygltf::Accessor& a = gm_.accessors[static_cast<std::size_t>(accessor)];
    a.sparse.isSparse = true;
    a.sparse.count = static_cast<int>(moved.size());
    a.sparse.indices.bufferView = indices;
    a.sparse.indices.byteOffset = 0;
    a.sparse.indices.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.sparse.values.bufferView = values;
    a.sparse.values.byteOffset = 0;
    return accessor;
  }

  // ---- materials ----------------------------------------------------------------------------

  /// The glTF material of model material `material`, written once; -1 for none. Only materials
  /// that faces use are written, so load → write cycles do not gather the loader's default
  /// material. A mesh without texture coordinates (`uv` false) gets the material without its
  /// textures, with a warning: glTF does not allow a texture there.
  int material_of(int material, bool uv, const std::string& mesh) {
    if (material < 0 || material >= static_cast<int>(model_.materials.size())) return -1;
    const mesh::Material& in = model_.materials[static_cast<std::size_t>(material)];
    const bool textured = in.base_color_texture >= 0 || in.metallic_roughness_texture >= 0 ||
                          in.normal_texture >= 0 || in.occlusion_texture >= 0 || in.emissive_texture >= 0;
    const bool bare = textured && !uv;
    if (bare)
      warnings_.push_back(mesh + " has no texture coordinates: material '" + in.name + "' written there without its textures");
    const auto [it, added] =
        material_index_.try_emplace({material, bare}, static_cast<int>(gm_.materials.size()));
    if (!added) return it->second;
    tinygltf::Material out;
    out.name = in.name;
    // glTF factors lie in [0, 1]; scale and strength are any finite number.
    const auto unit = [](float v) { return std::isfinite(v) ? std::clamp(static_cast<double>(v), 0.0, 1.0) : 1.0; };
    const auto finite_or_one = [](float v) { return std::isfinite(v) ? static_cast<double>(v) : 1.0; };
    auto& pbr = out.pbrMetallicRoughness;
    pbr.baseColorFactor = {unit(in.base_color.x()), unit(in.base_color.y()), unit(in.base_color.z()),
                           unit(in.base_color.w())};
    pbr.metallicFactor = unit(in.metallic);
    pbr.roughnessFactor = unit(in.roughness);
    const auto texture = [&](int t) { return bare ? -1 : texture_of(t, in.name); };
    pbr.baseColorTexture.index = texture(in.base_color_texture);
    pbr.metallicRoughnessTexture.index = texture(in.metallic_roughness_texture);
    out.normalTexture.index = texture(in.normal_texture);
    out.normalTexture.scale = finite_or_one(in.normal_scale);
    out.occlusionTexture.index = texture(in.occlusion_texture);
    out.occlusionTexture.strength = unit(in.occlusion_strength);
    out.emissiveTexture.index = texture(in.emissive_texture);
    out.emissiveFactor = {unit(in.emissive.x()), unit(in.emissive.y()), unit(in.emissive.z())};
    out.alphaMode = in.alpha_mode == mesh::AlphaMode::mask    ? "MASK"
                    : in.alpha_mode == mesh::AlphaMode::blend ? "BLEND"
                                                              : "OPAQUE";
    // The cutoff is only meaningful (and only allowed by the validator) in MASK mode.
    if (in.alpha_mode == mesh::AlphaMode::mask)
      out.alphaCutoff = std::isfinite(in.alpha_cutoff) ? std::max(0.0, static_cast<double>(in.alpha_cutoff)) : 0.5;
    out.doubleSided = in.double_sided;
    gm_.materials.push_back(std::move(out));
    return it->second;
  }

  /// The glTF texture of model texture `t`, its image embedded in the buffer; -1 (with a
  /// warning) for an image whose type glTF does not take.
  int texture_of(int t, const std::string& material) {
    if (t < 0 || t >= static_cast<int>(model_.textures.size())) return -1;
    const auto [it, added] = texture_index_.try_emplace(t, -1);
    if (!added) return it->second;
    const mesh::TextureImage& in = model_.textures[static_cast<std::size_t>(t)];
    if ((in.mime_type != "image/png" && in.mime_type != "image/jpeg") || in.data().empty()) {
      warnings_.push_back("material '" + material + "': texture '" + in.name +
                          "' is not PNG or JPEG; written without it");
      return -1;
    }
    const std::size_t begin = begin_view();
    data().insert(data().end(), in.data().begin(), in.data().end());
    tinygltf::Image image;
    image.name = in.name;
    image.mimeType = in.mime_type;
    image.bufferView = end_view(begin, 0, 0);
    gm_.images.push_back(std::move(image));
    tinygltf::Texture texture;
    texture.source = static_cast<int>(gm_.images.size()) - 1;
    gm_.textures.push_back(std::move(texture));
    return it->second = static_cast<int>(gm_.textures.size()) - 1;
  }

  void add_normals(const mesh::Mesh& m, tinygltf::Primitive& prim, const std::string& label) {
    mesh::RowMatrixXf<3> n(m.normals.rows(), 3);
    for (Eigen::Index v = 0; v < n.rows(); ++v) {
      const Eigen::Vector3f row = m.normals.row(v).transpose();
      const float len = row.norm();
      if (!std::isfinite(len) || !(len > 0)) {
        warnings_.push_back(label + ": normal " + std::to_string(v) + " is zero or not finite; NORMAL not written");
        return;
      }
      n.row(v) = (row / len).transpose();
    }
    prim.attributes["NORMAL"] = add_float_accessor(n.data(), static_cast<std::size_t>(n.rows()), 3, TINYGLTF_TYPE_VEC3,
                                                   TINYGLTF_TARGET_ARRAY_BUFFER, false);
  }

  /// The indices of faces `faces` of `m`.
  int add_indices(const mesh::Mesh& m, const std::vector<int>& faces) {
    const bool narrow = m.vertex_count() <= 65535;  // 65535 is the primitive restart value
    const std::size_t begin = begin_view();
    for (const int f : faces)
      for (int c = 0; c < 3; ++c) {
        if (narrow)
          put_u16(static_cast<std::uint16_t>(m.faces(f, c)));
        else
          put_u32(static_cast<std::uint32_t>(m.faces(f, c)));
      }
    const int view = end_view(begin, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, 0);
    return add_accessor(view, narrow ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT,
                        TINYGLTF_TYPE_SCALAR, 3 * faces.size());
  }

  int add_skin(const mesh::Mesh& m, tinygltf::Primitive& prim, const std::string& label) {
    const mesh::Skin& s = m.skin;
    const Eigen::Index nv = m.vertex_count();
    const std::size_t np = s.palette.size();
    if (s.joints.rows() != nv || s.weights.rows() != nv)
      invalid(label + ": skin has " + std::to_string(s.joints.rows()) + " joint rows and " +
              std::to_string(s.weights.rows()) + " weight rows for " + std::to_string(nv) + " vertices");
    if (s.inverse_bind.size() != np)
      invalid(label + ": skin palette has " + std::to_string(np) + " entries but " +
              std::to_string(s.inverse_bind.size()) + " inverse bind matrices");
    if (np > 65536) invalid(label + ": skin palette has more than 65536 entries");
    std::set<int> seen;
    for (int j : s.palette) {
      if (j < 0 || j >= skeleton_size())
        invalid(label + ": skin palette names joint " + std::to_string(j) + " outside the skeleton of " +
                std::to_string(skeleton_size()) + " joints");
      if (!seen.insert(j).second) invalid(label + ": skin palette names joint " + std::to_string(j) + " twice");
    }

    // JOINTS_0 and WEIGHTS_0: duplicates merged, by decreasing weight, rows renormalised, unused
    // slots (0, 0).
    std::vector<std::uint16_t> joints(static_cast<std::size_t>(4 * nv));
    std::vector<float> weights(static_cast<std::size_t>(4 * nv));
    Eigen::Index merged = 0;
    for (Eigen::Index v = 0; v < nv; ++v) {
      std::array<mesh::Influence, 4> in;
      for (int k = 0; k < 4; ++k) {
        in[k] = {s.weights(v, k), s.joints(v, k)};
        if (!finite(in[k].weight) || in[k].weight < 0)
          invalid(label + ": vertex " + std::to_string(v) + " has a negative or NaN skin weight");
        if (static_cast<std::size_t>(in[k].joint) >= np)
          invalid(label + ": vertex " + std::to_string(v) + " uses palette entry " + std::to_string(in[k].joint) +
                  " of " + std::to_string(np));
      }
      const mesh::TopInfluences top = mesh::top_influences(in);
      if (top.kept == 0) invalid(label + ": vertex " + std::to_string(v) + " has skin weights summing to 0");
      merged += top.merged ? 1 : 0;
      std::copy(top.joints.begin(), top.joints.end(), joints.begin() + 4 * v);
      std::copy(top.weights.begin(), top.weights.end(), weights.begin() + 4 * v);
    }
    if (merged > 0)
      warnings_.push_back(label + ": " + std::to_string(merged) +
                          " vertices listed a joint twice; their weights were merged");

    std::size_t begin = begin_view();
    for (std::uint16_t j : joints) put_u16(j);
    int view = end_view(begin, TINYGLTF_TARGET_ARRAY_BUFFER, 8);
    prim.attributes["JOINTS_0"] =
        add_accessor(view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, static_cast<std::size_t>(nv));
    prim.attributes["WEIGHTS_0"] = add_float_accessor(weights.data(), static_cast<std::size_t>(nv), 4,
                                                      TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER, false);

    // Inverse bind matrices, column-major, last row exactly (0 0 0 1).
    begin = begin_view();
    bool projective = false;
    for (const Eigen::Matrix4d& ibm : s.inverse_bind) {
      if (!ibm.allFinite()) invalid(label + ": an inverse bind matrix has NaN or infinite entries");
      projective = projective || (ibm.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) put_f32(r == 3 ? (c == 3 ? 1.0f : 0.0f) : static_cast<float>(ibm(r, c)));
    }
    if (projective)
      warnings_.push_back(label +
                          ": an inverse bind matrix had a last row other than (0 0 0 1); it was set to (0 0 0 1)");
    view = end_view(begin, 0, 0);
    tinygltf::Skin skin;
    skin.name = m.name;
    skin.inverseBindMatrices = add_accessor(view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, np);
    skin.joints = s.palette;
    int root = s.palette.front();
    for (int j : s.palette) root = root < 0 ? -1 : common_ancestor(root, j);
    skin.skeleton = root >= 0 ? root : synthetic_root();
    gm_.skins.push_back(std::move(skin));
    return static_cast<int>(gm_.skins.size()) - 1;
  }

  // ---- animations ---------------------------------------------------------------------------

  void add_clip(const anim::Clip& clip, std::size_t index) {
    const std::string label = "clip " + std::to_string(index) + " ('" + clip.name + "')";
    tinygltf::Animation a;
    a.name = clip.name;
    if (!finite(clip.duration)) invalid(label + " has a NaN or infinite duration");
    // glTF has no clip length: a clip declared longer than its keys (an OGRE or FBX file's) ends
    // at its last key unless its channels hold their last values up to the declared end.
    double last_key = 0;
    for (const Channel& ch : clip.channels)
      if (!ch.times.empty()) last_key = std::max(last_key, ch.times.back());
    const float end = static_cast<float>(clip.duration);
    const float hold_to = end > static_cast<float>(last_key) ? end : 0.0f;
    std::set<std::pair<int, ChannelPath>> targets;
    for (const Channel& ch : clip.channels) {
      if (ch.times.empty()) continue;
      if (ch.joint < 0 || ch.joint >= skeleton_size())
        invalid(label + " has a channel on joint " + std::to_string(ch.joint) + " outside the skeleton of " +
                std::to_string(skeleton_size()) + " joints");
      if (!targets.insert({ch.joint, ch.path}).second)
        invalid(label + " has two channels on the same path of joint '" +
                std::string(model_.skeleton.names()[ch.joint]) + "'");
      add_channel(a, ch, label, hold_to);
    }
    if (a.channels.empty()) {
      warnings_.push_back(label + " has no keys; not written");
      return;
    }
    gm_.animations.push_back(std::move(a));
  }

  /// Writes `ch`; when `hold_to` is later than its last key, with a key there that holds its
  /// last value (for a cubic spline: zero tangents there and at the old last key, whose out-tangent
  /// nothing used).
  void add_channel(tinygltf::Animation& a, const Channel& ch, const std::string& label, float hold_to) {
    const std::size_t keys = ch.times.size();
    const int comps = ch.components();
    const std::string what = label + ", channel on joint '" + std::string(model_.skeleton.names()[ch.joint]) + "'";
    // Weights drive the nodes that hold the joint's meshes with as many targets (one sampler for all).
    std::vector<int> nodes{ch.joint};
    if (ch.path == ChannelPath::weights) {
      nodes.clear();
      for (const auto& [node, targets] : morph_nodes_[ch.joint])
        if (targets == static_cast<std::size_t>(comps)) nodes.push_back(node);
      if (nodes.empty()) {
        warnings_.push_back(what + " animates " + std::to_string(comps) +
                            " morph weights, but no mesh there has that many targets; not written");
        return;
      }
    }
    Interpolation interp = ch.interpolation;
    const std::size_t per_key = static_cast<std::size_t>(comps) * (interp == Interpolation::cubic_spline ? 3 : 1);
    if (ch.values.size() != keys * per_key)
      invalid(what + " has " + std::to_string(ch.values.size()) + " values for " + std::to_string(keys) +
              " keys (expected " + std::to_string(keys * per_key) + ")");

    std::vector<float> times(keys);
    for (std::size_t k = 0; k < keys; ++k) {
      if (!finite(ch.times[k]) || ch.times[k] < 0) invalid(what + " has a negative, NaN or infinite key time");
      times[k] = static_cast<float>(ch.times[k]);
      if (k > 0 && !(times[k] > times[k - 1]))
        invalid(what + " has key times that are not strictly increasing (in float precision)");
    }
    for (double v : ch.values)
      if (!finite(v)) invalid(what + " has a NaN or infinite key value");

    // Values in the glTF layout; for a single cubic key keep only the value, as STEP.
    std::vector<float> out;
    std::size_t offset = 0, stride = per_key;
    if (interp == Interpolation::cubic_spline && keys == 1) {
      interp = Interpolation::step;
      offset = static_cast<std::size_t>(comps);
      warnings_.push_back(what + " is CUBICSPLINE with a single key; written as STEP");
    }
    const std::size_t out_per_key = interp == Interpolation::cubic_spline ? per_key : static_cast<std::size_t>(comps);
    out.reserve(keys * out_per_key);
    for (std::size_t k = 0; k < keys; ++k) {
      const std::size_t base = k * stride + offset;
      for (std::size_t e = 0; e < out_per_key; e += static_cast<std::size_t>(comps)) {
        const double* v = ch.values.data() + base + e;
        // The value of a cubic key is its middle element; tangents are not normalised.
        const bool is_value = interp != Interpolation::cubic_spline || e == static_cast<std::size_t>(comps);
        double scale = 1;
        if (ch.path == ChannelPath::rotation && is_value) {
          const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
          if (!(len > 0)) invalid(what + " has a zero rotation key");
          scale = 1 / len;
        }
        for (int c = 0; c < comps; ++c) {
          out.push_back(static_cast<float>(v[c] * scale));
          if (!std::isfinite(out.back())) invalid(what + " has a key value too large for a float");
        }
      }
    }

    if (hold_to > times.back()) {
      const std::size_t n = static_cast<std::size_t>(comps), last = out.size() - out_per_key;
      const bool cubic = interp == Interpolation::cubic_spline;
      if (cubic) {
        std::fill(out.begin() + static_cast<std::ptrdiff_t>(last + 2 * n), out.end(), 0.0f);
        out.resize(out.size() + n, 0.0f);
      }
      for (std::size_t c = 0; c < n; ++c) {
        const float v = out[last + (cubic ? n : 0) + c];
        out.push_back(v);
      }
      if (cubic) out.resize(out.size() + n, 0.0f);
      times.push_back(hold_to);
    }
    tinygltf::AnimationSampler sampler;
    sampler.input = add_float_accessor(times.data(), times.size(), 1, TINYGLTF_TYPE_SCALAR, 0, true);
    const bool weights = ch.path == ChannelPath::weights;
    sampler.output = weights ? add_float_accessor(out.data(), out.size(), 1, TINYGLTF_TYPE_SCALAR, 0, false)
                             : add_float_accessor(out.data(), out.size() / static_cast<std::size_t>(comps), comps,
                                                  comps == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, 0, false);
    sampler.interpolation = interp == Interpolation::step     ? "STEP"
                            : interp == Interpolation::linear ? "LINEAR"
                                                              : "CUBICSPLINE";
    a.samplers.push_back(std::move(sampler));
    for (const int node : nodes) {
      tinygltf::AnimationChannel channel;
      channel.sampler = static_cast<int>(a.samplers.size()) - 1;
      channel.target_node = node;
      channel.target_path = ch.path == ChannelPath::translation ? "translation"
                            : ch.path == ChannelPath::rotation  ? "rotation"
                            : weights                           ? "weights"
                                                                : "scale";
      a.channels.push_back(std::move(channel));
    }
  }

  std::map<std::pair<int, bool>, int> material_index_;  // (model index, without textures) -> glTF index
  std::map<int, int> texture_index_;                     // model index -> glTF index
  const anim::RiggedModel& model_;
  std::vector<std::string>& warnings_;
  tinygltf::Model gm_;
  std::vector<int> depth_;
  std::vector<int> mesh_roots_;
  std::vector<int> static_children_;  ///< per joint: static mesh nodes placed among its children
  /// Per joint: the glTF nodes holding its meshes with morph targets, and their target counts.
  std::map<int, std::vector<std::pair<int, std::size_t>>> morph_nodes_;
  int synthetic_root_ = -1;
};

/// Runs a JSON step, turning a JSON library error (a name that is not valid UTF-8) into
/// InvalidInputError.
template <class F>
auto json_step(F&& f) {
  try {
    return f();
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw InvalidInputError(std::string("write_gltf: cannot encode the model as JSON (names must be UTF-8): ") +
                            e.what());
  }
}

std::string serialize(const tinygltf::Model& gm, bool binary, bool pretty) {
  return json_step([&] {
    tinygltf::TinyGLTF writer;
    std::ostringstream stream(std::ios::out | std::ios::binary);
    if (!writer.WriteGltfSceneToStream(&gm, stream, pretty, binary) || !stream)
      throw WriteError("write_gltf: tinygltf could not serialise the model");
    return std::move(stream).str();
  });
}

}  // namespace

std::vector<EncodedFile> encode_gltf(const anim::RiggedModel& model, const std::filesystem::path& out,
                                     const GltfWriteOptions& options, std::vector<std::string>* warnings_out) {
  const std::string ext = lower_extension(out);
  if (ext != ".glb" && ext != ".gltf")
    throw InvalidInputError("write_gltf: unknown extension '" + out.extension().string() + "' of '" + out.string() +
                            "' (expected .glb or .gltf)");
  std::vector<std::string> warnings;
  tinygltf::Model gm = Builder(model, warnings).run();
  if (warnings_out != nullptr) *warnings_out = std::move(warnings);

  if (ext == ".glb") return {{out, serialize(gm, true, false)}};
  if (options.embed_buffer) return {{out, serialize(gm, false, options.pretty_json)}};
  // tinygltf's stream writer embeds buffers; write the JSON of a model with an empty buffer
  // and point the buffer at the .bin written next to it.
  const std::string bin_name = bin_file_name(out);
  std::vector<unsigned char> bin = std::move(gm.buffers[0].data);
  gm.buffers[0].data.clear();
  std::string text = json_step([&] {
    nlohmann::json json = nlohmann::json::parse(serialize(gm, false, false));
    json["buffers"][0] = {{"byteLength", bin.size()}, {"uri", bin_name}};
    return json.dump(options.pretty_json ? 2 : -1) + "\n";
  });
  std::vector<EncodedFile> files;
  files.push_back({out.parent_path() / bin_name, std::string(bin.begin(), bin.end())});
  files.push_back({out, std::move(text)});
  return files;
}

std::vector<std::string> write_gltf(const anim::RiggedModel& model, const std::filesystem::path& out,
                                    const GltfWriteOptions& options) {
  std::vector<std::string> warnings;
  write_files_atomically(encode_gltf(model, out, options, &warnings));
  return warnings;
}

}  // namespace cgamesh::io
