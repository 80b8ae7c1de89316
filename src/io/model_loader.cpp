#include "cgamesh/io/model_loader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <nlohmann/json.hpp>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/transform.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/mesh/influences.hpp"
#include "cgamesh/mesh/normals.hpp"
#include "cgamesh/mesh/weld.hpp"

#include "excerpt.hpp"
#include "file_vertices.hpp"
#include "gltf_extras_reader.hpp"
#include "cgamesh/io/file_extension.hpp"
#include "lower_case.hpp"
#include "preflight.hpp"

namespace cgamesh::io {
namespace {

using anim::Channel;
using anim::ChannelPath;
using anim::Transform;

/// How the warnings on non-uniform scale end: what each skinning mode does with it.
constexpr const char* kApproximated =
    ": cga and matrix skinning keep it exactly, versor and dqs approximate it (a posed frame says by how much)";

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  e << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return e;
}

// Mirrors. Versors are even: they cannot hold a reflection. A node whose matrix mirrors
// (negative determinant) is made proper by the reflection F = diag(1, 1, -1) pushed down the
// tree: with m_i the parity of mirrors on the path to node i (itself included) and c_i that of
// its parent, the local L_i becomes L'_i = F^c_i L_i F^m_i, so that G'_i = G_i F^m_i, proper
// everywhere. A mesh then gets its data reflected where that keeps its maps proper: a static
// mesh on a mirrored node, and a skinned mesh whose inverse binds B_j (made F^m_j B_j F^s) need
// it; reflected data gets its triangles' winding reversed so that faces keep their outside,
// unless the file wound them for the mirror already (see reflect_mirrored).
const Eigen::DiagonalMatrix<double, 4> kMirror(1, 1, -1, 1);

bool mirrors(const Eigen::Matrix4d& m) { return m.topLeftCorner<3, 3>().determinant() < 0; }

/// Reflects a mesh's data by F: positions and normals, and the winding of its triangles.
void reflect(mesh::Mesh& m) {
  m.positions.col(2) *= -1;
  if (m.normals.rows() > 0) m.normals.col(2) *= -1;
  for (mesh::MorphTarget& t : m.morph_targets) {
    t.positions.col(2) *= -1;
    if (t.normals.rows() > 0) t.normals.col(2) *= -1;
  }
  m.faces.col(1).swap(m.faces.col(2));
}

/// Whether a mesh's faces are wound against its own normals: the sum over faces of their area
/// vectors against their corners' normals is negative.
bool wound_against_normals(const mesh::Mesh& m) {
  if (m.normals.rows() != m.positions.rows()) return false;
  double agreement = 0;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const auto corner = [&](int k) { return m.positions.row(m.faces(f, k)).cast<double>(); };
    const Eigen::RowVector3d area = (corner(1) - corner(0)).cross(corner(2) - corner(0));
    for (int k = 0; k < 3; ++k) agreement += area.dot(m.normals.row(m.faces(f, k)).cast<double>());
  }
  return agreement < 0;
}

/// A mesh whose world transform mirrors shows its faces' other side unless their winding is
/// reversed: glTF says so, and three.js and the engines draw such a mesh that way. Some
/// exporters (Blender's DirectX exporter, as Assimp reads its files) wind the data for the mirror
/// already; their normals say so, and then the winding the file has is the one it means.
void reflect_mirrored(mesh::Mesh& m) {
  const bool wound_for_the_mirror = wound_against_normals(m);
  reflect(m);
  if (wound_for_the_mirror) m.faces.col(1).swap(m.faces.col(2));
}

std::string describe(const Eigen::Vector3d& s) {
  return std::to_string(s.x()) + ", " + std::to_string(s.y()) + ", " + std::to_string(s.z());
}

/// A scale key that flattens (a zero factor) or mirrors (negative product) has no versor: the
/// file is broken for every command, not only for those that pose it.
/// @throws FileError naming the clip, joint and time.
void check_scale_keys(const anim::RiggedModel& model) {
  for (const anim::Clip& clip : model.clips)
    for (const Channel& ch : clip.channels) {
      if (ch.path != ChannelPath::scale) continue;
      const std::size_t stride = ch.interpolation == anim::Interpolation::cubic_spline ? 9 : 3;
      const std::size_t offset = ch.interpolation == anim::Interpolation::cubic_spline ? 3 : 0;
      for (std::size_t k = 0; k < ch.times.size() && (k + 1) * stride <= ch.values.size(); ++k) {
        const Eigen::Vector3d v(ch.values.data() + k * stride + offset);
        if (!(std::abs(v.prod()) > 1e-300) || v.prod() < 0)
          throw FileError("clip '" + clip.name + "' scales joint '" + model.skeleton.names()[ch.joint] + "' by (" +
                          describe(v) + ") at t = " + std::to_string(ch.times[k]) +
                          ": a zero or mirroring scale has no versor");
      }
    }
}

/// `bytes` as UTF-8: itself when it is valid UTF-8 (glTF's names always are), else read as
/// Latin-1, the encoding of the older formats' names (an OBJ's "Terraind\xe6k"), which any bytes
/// are. Sets `converted` then. Writers and JSON need UTF-8, and a user cannot type the rest.
std::string utf8_name(const char* bytes, bool& converted) {
  std::string s(bytes);
  try {
    (void)nlohmann::json(s).dump();  // the JSON library's UTF-8 check
    return s;
  } catch (const nlohmann::json::type_error&) {
    converted = true;
  }
  std::string out;
  for (const unsigned char c : s) {
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

/// Keys before t = 0 (LightWave's, for one; or an invalid glTF file's) are replaced by a key at
/// 0 with the value the channel has there: a clip plays from 0 (anim::sample clamps), and glTF
/// allows no negative time, so what plays is unchanged and the clip can be written.
/// @throws FileError for such keys in a cubic-spline channel.
void start_clips_at_zero(anim::RiggedModel& model) {
  for (anim::Clip& clip : model.clips) {
    double earliest = 0;
    for (Channel& ch : clip.channels) {
      if (ch.times.empty() || ch.times.front() >= 0) continue;
      if (ch.interpolation == anim::Interpolation::cubic_spline)
        throw FileError("clip '" + clip.name + "' has cubic-spline keys before t = 0 (from t = " +
                        std::to_string(ch.times.front()) + "); cgamesh cannot start it at 0");
      earliest = std::min(earliest, ch.times.front());
      const anim::Clip one{.name = clip.name, .duration = std::max(0.0, ch.times.back()), .channels = {ch}};
      const anim::Pose zero = anim::sample(model.skeleton, one, 0.0, anim::BlendMode::format);
      const Transform& at_zero = zero.local[static_cast<std::size_t>(ch.joint)];
      std::vector<double> value(at_zero.rotation.coeffs().data(), at_zero.rotation.coeffs().data() + 4);  // x y z w
      if (ch.path == ChannelPath::weights)
        value.assign(zero.morph_weights[static_cast<std::size_t>(ch.joint)].begin(),
                     zero.morph_weights[static_cast<std::size_t>(ch.joint)].end());
      else if (ch.path == ChannelPath::translation)
        value.assign(at_zero.translation.data(), at_zero.translation.data() + 3);
      else if (ch.path == ChannelPath::scale)
        value.assign(at_zero.scale.data(), at_zero.scale.data() + 3);
      const auto before = std::lower_bound(ch.times.begin(), ch.times.end(), 0.0) - ch.times.begin();
      ch.times.erase(ch.times.begin(), ch.times.begin() + before);
      ch.values.erase(ch.values.begin(), ch.values.begin() + before * ch.components());
      if (!ch.times.empty() && ch.times.front() == 0) continue;
      ch.times.insert(ch.times.begin(), 0.0);
      ch.values.insert(ch.values.begin(), value.begin(), value.end());
    }
    if (earliest < 0)
      model.warnings.push_back("clip '" + clip.name + "' has keys before t = 0 (from t = " + std::to_string(earliest) +
                               "); they are replaced by the pose they give at t = 0, where the clip starts");
  }
}

/// Why a scene gives no model when it has no triangle mesh: an animation file (.bvh, an .md5anim)
/// is named so, since its reader loads without error.
/// `relative` under `directory` as the file system has it, each part matched ignoring ASCII case
/// (textures named by Windows exporters: "DWARF.JPG" for dwarf.jpg), else the file of its
/// name alone in `directory` (an absolute path from the exporter's machine); empty when none.
std::filesystem::path find_ignoring_case(const std::filesystem::path& directory, const std::filesystem::path& relative) {
  const auto match = [](const std::filesystem::path& dir, const std::string& name) -> std::filesystem::path {
    std::error_code ec;
    for (std::filesystem::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
      if (detail::lower(it->path().filename().string()) == detail::lower(name)) return it->path();
    return {};
  };
  std::filesystem::path at = directory;
  for (const std::filesystem::path& part : relative.relative_path()) {
    if (part == "." || part.empty()) continue;
    at = part == ".." ? at / part : match(at, part.string());
    if (at.empty()) break;
  }
  if (!at.empty() && std::filesystem::is_regular_file(at)) return at;
  return match(directory, relative.filename().string());
}

std::string no_mesh(const aiScene& scene) {
  if (scene.mNumAnimations == 0) return "the file holds no triangle mesh";
  return "the file holds animation (" + std::to_string(scene.mNumAnimations) +
         (scene.mNumAnimations == 1 ? " clip" : " clips") +
         ") but no mesh: cgamesh needs a model with a mesh (an animation file alone cannot be posed)";
}

class Loader {
 public:
  Loader(const aiScene& scene, const LoadOptions& options, std::filesystem::path directory)
      : scene_(scene), options_(options), directory_(std::move(directory)) {}

  anim::RiggedModel run() {
    collect_nodes(scene_.mRootNode, -1);
    model_.skeleton = anim::Skeleton::build(editable_, &remap_);
    // The primitives of one glTF mesh over the same vertices (cgamesh writes a mesh whose faces
    // have several materials so) become one Mesh again, with per-face materials.
    for (std::size_t r = 0; r < mesh_refs_.size();) {
      std::vector<const aiMesh*> parts{scene_.mMeshes[mesh_refs_[r].second]};
      std::size_t end = r + 1;
      for (; end < mesh_refs_.size() && mesh_refs_[end].first == mesh_refs_[r].first; ++end) {
        const aiMesh* next = scene_.mMeshes[mesh_refs_[end].second];
        if (!same_vertices(*parts.front(), *next)) break;
        parts.push_back(next);
      }
      add_mesh(parts, mesh_refs_[r].first);
      r = end;
    }
    if (model_.meshes.empty()) throw FileError(no_mesh(scene_));
    for (unsigned i = 0; i < scene_.mNumMaterials; ++i) add_material(*scene_.mMaterials[i]);
    for (unsigned a = 0; a < scene_.mNumAnimations; ++a) add_clip(*scene_.mAnimations[a], a);
    if (unrated_clips_ > 0)
      warn("the file gives no ticks per second for " + std::to_string(unrated_clips_) + " of " +
           std::to_string(scene_.mNumAnimations) + " clips (the first: '" + first_unrated_ + "'); " +
           number(options_.default_ticks_per_second) + " ticks per second assumed");
    return std::move(model_);
  }

  /// Conjugates by F the keys of the joints below a mirror, as their rests are (see kMirror);
  /// run once the clips are final (a glTF file's are read again by read_gltf_extras).
  /// @throws FileError for a mirrored joint that a clip rotates or scales.
  void conjugate_keys(anim::RiggedModel& model) const {
    std::vector<bool> below(model.skeleton.size(), false), own(model.skeleton.size(), false);
    for (std::size_t e = 0; e < editable_.joints.size(); ++e) {
      const auto j = static_cast<std::size_t>(remap_[e]);
      const int parent = editable_.joints[e].parent;
      below[j] = parent >= 0 && mirrored_[static_cast<std::size_t>(parent)];
      own[j] = own_mirror_[e];
    }
    for (anim::Clip& clip : model.clips)
      for (Channel& ch : clip.channels) {
        const auto j = static_cast<std::size_t>(ch.joint);
        if (ch.path == ChannelPath::weights) continue;  // numbers, not geometry
        if (own[j] && ch.path != ChannelPath::translation)
          throw FileError("node '" + model.skeleton.names()[j] + "' mirrors (negative determinant) and clip '" +
                          clip.name + "' rotates or scales it; cgamesh cannot represent that");
        if (!below[j] || ch.path == ChannelPath::scale) continue;  // F S F = S for a diagonal S
        // F T F translates by F t; F R F turns about the reflected axis by the opposite angle.
        const std::size_t n = static_cast<std::size_t>(ch.components());
        for (std::size_t k = 0; k < ch.values.size(); k += n) {
          if (ch.path == ChannelPath::translation) {
            ch.values[k + 2] = -ch.values[k + 2];
          } else {
            ch.values[k] = -ch.values[k];
            ch.values[k + 1] = -ch.values[k + 1];
          }
        }
      }
  }

 private:
  void collect_nodes(const aiNode* node, int parent) {
    const int index = static_cast<int>(editable_.joints.size());
    anim::JointDesc j;
    j.name = name(node->mName);
    if (j.name.empty()) j.name = "node" + std::to_string(index);
    j.parent = parent;
    const bool under_mirror = parent >= 0 && mirrored_[static_cast<std::size_t>(parent)];
    Eigen::Matrix4d local = to_eigen(node->mTransformation);
    const bool own_mirror = mirrors(local);
    if (under_mirror) local = kMirror * local;
    if (mirrors(local)) local = local * kMirror;
    mirrored_.push_back(under_mirror != own_mirror);
    own_mirror_.push_back(own_mirror);
    j.rest = Transform::from_matrix(local);
    if (!j.rest.is_uniform())
      warn("node '" + j.name + "' has non-uniform scale (" + describe(j.rest.scale) + ")" + kApproximated);
    editable_.joints.push_back(std::move(j));
    by_name_.emplace(editable_.joints.back().name, index);
    for (unsigned m = 0; m < node->mNumMeshes; ++m) mesh_refs_.emplace_back(index, node->mMeshes[m]);
    // Some readers (Assimp's RAW) leave a child slot empty: the rest of the tree still loads.
    for (unsigned c = 0; c < node->mNumChildren; ++c)
      if (node->mChildren[c] != nullptr)
        collect_nodes(node->mChildren[c], index);
      else
        warn("node '" + editable_.joints[static_cast<std::size_t>(index)].name + "': the reader left child " +
             std::to_string(c) + " of " + std::to_string(node->mNumChildren) + " empty; skipped");
  }

  /// Whether two meshes are triangle meshes with the same vertices (every attribute cgamesh
  /// reads, and the same bones).
  static bool same_vertices(const aiMesh& a, const aiMesh& b) {
    const unsigned n = a.mNumVertices;
    const auto same = [n](const aiVector3D* x, const aiVector3D* y) {
      return (x == nullptr) == (y == nullptr) && (x == nullptr || std::equal(x, x + n, y));
    };
    if ((a.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0 || (b.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0 ||
        b.mNumVertices != n || b.mNumBones != a.mNumBones || !same(a.mVertices, b.mVertices) ||
        !same(a.mNormals, b.mNormals) || !same(a.mTextureCoords[0], b.mTextureCoords[0]))
      return false;
    for (unsigned k = 0; k < a.mNumBones; ++k)
      if (a.mBones[k]->mName != b.mBones[k]->mName || a.mBones[k]->mNumWeights != b.mBones[k]->mNumWeights)
        return false;
    return true;
  }

  /// One Mesh from `parts` (meshes with the same vertices; their faces in turn) on the node of
  /// editable index `node`.
  void add_mesh(const std::vector<const aiMesh*>& parts, int node) {
    const aiMesh& in = *parts.front();
    if ((in.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) return;
    mesh::Mesh m;
    m.name = in.mName.length > 0 ? name(in.mName) : "mesh" + std::to_string(model_.meshes.size());
    // Assimp names the primitives of glTF mesh NAME "NAME-0", "NAME-1", ...
    if (parts.size() > 1 && m.name.size() > 2 && m.name.ends_with("-0")) m.name.resize(m.name.size() - 2);
    const Eigen::Index nv = in.mNumVertices;
    m.positions.resize(nv, 3);
    for (Eigen::Index i = 0; i < nv; ++i) m.positions.row(i) << in.mVertices[i].x, in.mVertices[i].y, in.mVertices[i].z;
    if (!m.positions.allFinite()) throw FileError("mesh '" + m.name + "' has NaN or infinite vertex positions");
    if (in.HasNormals()) {
      m.normals.resize(nv, 3);
      for (Eigen::Index i = 0; i < nv; ++i) m.normals.row(i) << in.mNormals[i].x, in.mNormals[i].y, in.mNormals[i].z;
    }
    if (in.HasTextureCoords(0)) {
      m.uvs.resize(nv, 2);
      for (Eigen::Index i = 0; i < nv; ++i) m.uvs.row(i) << in.mTextureCoords[0][i].x, in.mTextureCoords[0][i].y;
    }
    std::vector<Eigen::Vector3i> faces;
    std::vector<int> materials;
    for (const aiMesh* part : parts) {
      const int material = part->mMaterialIndex < scene_.mNumMaterials ? static_cast<int>(part->mMaterialIndex) : -1;
      for (unsigned f = 0; f < part->mNumFaces; ++f) {
        const aiFace& face = part->mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines of a mixed mesh
        for (unsigned k = 0; k < 3; ++k)
          if (face.mIndices[k] >= in.mNumVertices)
            throw FileError("mesh '" + m.name + "' has a face with vertex " + std::to_string(face.mIndices[k]) +
                            " of " + std::to_string(in.mNumVertices));
        faces.emplace_back(face.mIndices[0], face.mIndices[1], face.mIndices[2]);
        materials.push_back(material);
      }
    }
    if (faces.empty()) return;
    // Corrupt files (OFF/invalid.off) give triangles whose corners are one point: no surface.
    const auto distinct = [&](int a, int b) { return m.positions.row(a) != m.positions.row(b); };
    if (std::none_of(faces.begin(), faces.end(), [&](const Eigen::Vector3i& f) {
          return distinct(f[0], f[1]) && distinct(f[1], f[2]) && distinct(f[0], f[2]);
        })) {
      warn("mesh '" + m.name + "' has no triangle with three distinct corners (" + std::to_string(faces.size()) +
           " degenerate); it is left out");
      return;
    }
    m.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (std::size_t f = 0; f < faces.size(); ++f) m.faces.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
    repair_normals(m);
    add_morph_targets(in, m);
    m.material = materials.front();
    if (std::any_of(materials.begin(), materials.end(), [&](int x) { return x != m.material; }))
      m.face_materials =
          Eigen::Map<const Eigen::VectorXi>(materials.data(), static_cast<Eigen::Index>(materials.size()));
    if (in.HasBones() ? add_skin(in, m) : mirrored_[static_cast<std::size_t>(node)]) reflect_mirrored(m);
    m.node = remap_[static_cast<std::size_t>(node)];
    model_.meshes.push_back(std::move(m));
  }

  /// The mesh's morph targets: Assimp's anim meshes hold each target's absolute positions and
  /// normals (rest + displacement), and its default weight.
  void add_morph_targets(const aiMesh& in, mesh::Mesh& m) {
    const Eigen::Index nv = m.vertex_count();
    for (unsigned k = 0; k < in.mNumAnimMeshes; ++k) {
      const aiAnimMesh& a = *in.mAnimMeshes[k];
      mesh::MorphTarget t;
      t.name = name(a.mName);
      // A target must be addressable by name (--morph, sliders, Python): an unnamed one gets its number.
      if (t.name.empty()) t.name = "target_" + std::to_string(k);
      if (a.mNumVertices != in.mNumVertices) {
        warn("morph target " + std::to_string(k) + " ('" + t.name + "') of mesh '" + m.name + "' has " +
             std::to_string(a.mNumVertices) + " vertices for the mesh's " + std::to_string(in.mNumVertices) +
             "; the mesh loads without its morph targets");
        m.morph_targets.clear();
        m.morph_weights.clear();
        return;
      }
      t.positions.setZero(nv, 3);
      if (a.mVertices != nullptr)
        for (Eigen::Index i = 0; i < nv; ++i) {
          const aiVector3D d = a.mVertices[i] - in.mVertices[i];
          t.positions.row(i) << d.x, d.y, d.z;
        }
      if (a.mNormals != nullptr && m.normals.rows() == nv) {
        t.normals.resize(nv, 3);
        for (Eigen::Index i = 0; i < nv; ++i) {
          const aiVector3D d = a.mNormals[i] - in.mNormals[i];
          t.normals.row(i) << d.x, d.y, d.z;
        }
        // A mesh whose normals were repaired (NaN in the file) keeps its targets' positions only.
        if (!t.normals.allFinite()) t.normals.resize(0, 3);
      }
      if (!t.positions.allFinite())
        throw FileError("morph target '" + t.name + "' of mesh '" + m.name + "' has NaN or infinite positions");
      m.morph_targets.push_back(std::move(t));
      m.morph_weights.push_back(std::isfinite(a.mWeight) ? a.mWeight : 0.0f);
    }
  }

  /// A reader's NaN or infinite normals (Q3D's earth has a few) would make every posed normal, and
  /// so every output, invalid: they become the area-weighted normals of their faces.
  void repair_normals(mesh::Mesh& m) {
    if (m.normals.rows() == 0) return;
    const Eigen::Array<bool, Eigen::Dynamic, 1> broken = (!m.normals.array().isFinite()).rowwise().any();
    if (const auto count = broken.count(); count > 0) {
      const mesh::RowMatrixXf<3> faces = mesh::area_weighted_normals(m.positions, m.faces);
      for (Eigen::Index v = 0; v < m.normals.rows(); ++v)
        if (broken(v)) m.normals.row(v) = faces.row(v);
      warn("mesh '" + m.name + "': " + std::to_string(count) + " of " + std::to_string(m.normals.rows()) +
           " normals were NaN or infinite; replaced by the area-weighted normals of their faces");
    }
    // Normals against a winding that encloses positive volume (pab_skeleton.fbx: 2798 of 2811
    // faces) point into the body, and the model renders dark: they are turned outward.
    double volume = 0;
    long against = 0;
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      const Eigen::Vector3d a = m.positions.row(m.faces(f, 0)).cast<double>(),
                            b = m.positions.row(m.faces(f, 1)).cast<double>(),
                            c = m.positions.row(m.faces(f, 2)).cast<double>();
      volume += a.dot(b.cross(c)) / 6;
      const Eigen::Vector3d n = (m.normals.row(m.faces(f, 0)) + m.normals.row(m.faces(f, 1)) +
                                 m.normals.row(m.faces(f, 2)))
                                    .cast<double>();
      if ((b - a).cross(c - a).dot(n) < 0) ++against;
    }
    if (volume > 0 && m.face_count() >= 4 && against * 10 >= m.face_count() * 9) {
      m.normals = -m.normals;
      warn("mesh '" + m.name + "': its normals point against its faces' winding (into the body) on " +
           std::to_string(against) + " of " + std::to_string(m.face_count()) + " faces; turned outward");
    }
  }

  /// Returns whether the mesh's data must be reflected (see kMirror).
  bool add_skin(const aiMesh& in, mesh::Mesh& m) {
    const Eigen::Index nv = in.mNumVertices;
    if (in.mNumBones > 65536)
      throw FileError("mesh '" + m.name + "' is bound to " + std::to_string(in.mNumBones) +
                      " bones; at most 65536 are supported");
    std::vector<std::vector<mesh::Influence>> influences(nv);
    int reflected = -1;  // unknown until the first bone
    for (unsigned b = 0; b < in.mNumBones; ++b) {
      const aiBone& bone = *in.mBones[b];
      const std::string bone_name = name(bone.mName);
      const auto it = by_name_.find(bone_name);
      if (it == by_name_.end())
        throw FileError("mesh '" + m.name + "' is bound to bone '" + bone_name + "', which is not a node");
      m.skin.palette.push_back(remap_[static_cast<std::size_t>(it->second)]);
      Eigen::Matrix4d ibm = to_eigen(bone.mOffsetMatrix);
      const bool joint_mirrored = mirrored_[static_cast<std::size_t>(it->second)];
      if (joint_mirrored) ibm = kMirror * ibm;
      const int reflect_data = mirrors(ibm) ? 1 : 0;
      if (reflected >= 0 && reflect_data != reflected)
        throw FileError("mesh '" + m.name + "' is bound to bones on both sides of a mirror (bone '" + bone_name +
                        "'); cgamesh cannot represent that");
      reflected = reflect_data;
      if (reflect_data != 0) ibm = ibm * kMirror;
      const Transform t = Transform::from_matrix(ibm);
      if (!anim::is_similarity(ibm))
        warn("inverse bind matrix of bone '" + bone_name + "' has non-uniform scale or shear (" + describe(t.scale) +
             ")" + kApproximated);
      m.skin.inverse_bind.push_back(ibm);
      m.skin.inverse_bind_versors.push_back(t.versor());
      for (unsigned w = 0; w < bone.mNumWeights; ++w) {
        const aiVertexWeight& vw = bone.mWeights[w];
        if (vw.mVertexId < nv) influences[vw.mVertexId].push_back({vw.mWeight, static_cast<std::uint16_t>(b)});
      }
    }
    m.skin.joints.setZero(nv, 4);
    m.skin.weights.setZero(nv, 4);
    Eigen::Index truncated = 0, unweighted = 0;
    for (Eigen::Index i = 0; i < nv; ++i) {
      mesh::TopInfluences top = mesh::top_influences(influences[static_cast<std::size_t>(i)]);
      model_.source_max_influences = std::max(model_.source_max_influences, top.distinct);
      truncated += top.distinct > 4 ? 1 : 0;
      if (top.kept == 0) {
        top.weights[0] = 1;  // joint 0
        ++unweighted;
      }
      for (Eigen::Index k = 0; k < 4; ++k) {
        m.skin.weights(i, k) = top.weights[static_cast<std::size_t>(k)];
        m.skin.joints(i, k) = top.joints[static_cast<std::size_t>(k)];
      }
    }
    if (truncated > 0)
      warn("mesh '" + m.name + "': " + std::to_string(truncated) +
           " vertices had more than 4 influences; kept the 4 largest and renormalised");
    if (unweighted > 0)
      warn("mesh '" + m.name + "': " + std::to_string(unweighted) + " vertices had no weights; bound to bone '" +
           name(in.mBones[0]->mName) + "'");
    return reflected == 1;
  }

  void add_material(const aiMaterial& in) {
    mesh::Material m;
    aiString material;
    if (in.Get(AI_MATKEY_NAME, material) == AI_SUCCESS) m.name = name(material);
    aiColor4D c;
    if (in.Get(AI_MATKEY_BASE_COLOR, c) == AI_SUCCESS || in.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) {
      m.base_color = Eigen::Vector4f(c.r, c.g, c.b, c.a);
      if (!m.base_color.allFinite()) {
        warn("material '" + m.name + "' has a NaN or infinite colour; white used");
        m.base_color.setOnes();
      }
    }
    const auto scalar = [&](const char* key, unsigned type, unsigned index, float& out) {
      ai_real v = 0;
      if (in.Get(key, type, index, v) == AI_SUCCESS && std::isfinite(v)) out = static_cast<float>(v);
    };
    scalar(AI_MATKEY_METALLIC_FACTOR, m.metallic);
    scalar(AI_MATKEY_ROUGHNESS_FACTOR, m.roughness);
    int two_sided = 0;
    if (in.Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS) m.double_sided = two_sided != 0;
    aiColor3D e;
    if (in.Get(AI_MATKEY_COLOR_EMISSIVE, e) == AI_SUCCESS) {
      m.emissive = Eigen::Vector3f(e.r, e.g, e.b);
      if (!m.emissive.allFinite()) m.emissive.setZero();
    }
    // Only Assimp's glTF importer sets the alpha mode; its metallic-roughness texture is the
    // "unknown" type and its occlusion texture the lightmap, which mean other things elsewhere.
    aiString alpha;
    const bool gltf = in.Get(AI_MATKEY_GLTF_ALPHAMODE, alpha) == AI_SUCCESS;
    if (gltf) {
      const std::string mode = alpha.C_Str();
      m.alpha_mode = mode == "MASK"    ? mesh::AlphaMode::mask
                     : mode == "BLEND" ? mesh::AlphaMode::blend
                                       : mesh::AlphaMode::opaque;
      scalar(AI_MATKEY_GLTF_ALPHACUTOFF, m.alpha_cutoff);
    }
    const auto texture_of = [&](std::initializer_list<aiTextureType> types) {
      aiString path;
      for (const aiTextureType type : types)
        if (in.GetTexture(type, 0, &path) == AI_SUCCESS) return texture(path.C_Str(), m.name);
      return -1;
    };
    m.base_color_texture = texture_of({aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE});
    m.normal_texture = texture_of({aiTextureType_NORMALS});
    if (m.normal_texture >= 0) scalar(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0), m.normal_scale);
    m.emissive_texture = texture_of({aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR});
    if (gltf) {
      m.metallic_roughness_texture = texture_of({aiTextureType_UNKNOWN});
      m.occlusion_texture = texture_of({aiTextureType_LIGHTMAP});
      if (m.occlusion_texture >= 0)
        scalar(AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0), m.occlusion_strength);
    } else {
      m.occlusion_texture = texture_of({aiTextureType_AMBIENT_OCCLUSION});
    }
    model_.materials.push_back(std::move(m));
  }

  /// Index of the texture at `path` (embedded "*N" or a name, or a file next to the model), read
  /// once; -1 with a warning when it cannot be read.
  int texture(const std::string& path, const std::string& material) {
    if (const auto it = texture_of_path_.find(path); it != texture_of_path_.end()) return it->second;
    mesh::TextureImage image;
    image.name = path;
    if (const aiTexture* t = scene_.GetEmbeddedTexture(path.c_str())) {
      if (t->mHeight != 0) {
        warn("material '" + material + "': texture '" + path + "' is stored uncompressed; not kept");
        return texture_of_path_[path] = -1;
      }
      const auto* bytes = reinterpret_cast<const std::uint8_t*>(t->pcData);
      image.bytes = std::make_shared<const std::vector<std::uint8_t>>(bytes, bytes + t->mWidth);
      const std::string hint = t->achFormatHint;
      image.mime_type = hint == "png" ? "image/png" : hint == "jpg" || hint == "jpeg" ? "image/jpeg" : "";
    } else {
      std::string relative = path;
      std::replace(relative.begin(), relative.end(), '\\', '/');
      std::filesystem::path file = directory_ / relative;
      if (!std::filesystem::exists(file))
        if (std::filesystem::path found = find_ignoring_case(directory_, relative); !found.empty()) {
          warn("material '" + material + "': texture '" + path + "' is read from '" + found.filename().string() +
               "' (the file's name differs in case or folder)");
          file = std::move(found);
        }
      std::error_code ec;
      const auto size = std::filesystem::file_size(file, ec);
      if (ec || size == 0 || size > kMaxTextureBytes) {
        warn("material '" + material + "': texture '" + path + "' " +
             (ec          ? "not found"
              : size == 0 ? "is empty"
                          : "is larger than 256 MiB") +
             "; not kept");
        return texture_of_path_[path] = -1;
      }
      std::ifstream stream(file, std::ios::binary);
      auto bytes = std::make_shared<std::vector<std::uint8_t>>(static_cast<std::size_t>(size));
      if (!stream.read(reinterpret_cast<char*>(bytes->data()), static_cast<std::streamsize>(size))) {
        warn("material '" + material + "': texture '" + path + "' cannot be read; not kept");
        return texture_of_path_[path] = -1;
      }
      image.bytes = std::move(bytes);
      const std::string ext = lower_extension(file);
      image.mime_type = ext == ".png" ? "image/png" : ext == ".jpg" || ext == ".jpeg" ? "image/jpeg" : "";
    }
    model_.textures.push_back(std::move(image));
    return texture_of_path_[path] = static_cast<int>(model_.textures.size()) - 1;
  }

  void add_clip(const aiAnimation& in, unsigned index) {
    anim::Clip clip;
    clip.name = in.mName.length > 0 ? name(in.mName) : "clip" + std::to_string(index);
    // Assimp reports 0 when the file gives no rate (a .x file without AnimTicksPerSecond).
    const bool rate_given = in.mTicksPerSecond > 0;
    const double tps = rate_given ? in.mTicksPerSecond : options_.default_ticks_per_second;
    if (!rate_given && unrated_clips_++ == 0) first_unrated_ = clip.name;
    // The clip lasts as long as the file declares, which may be past its last key (OGRE, FBX).
    clip.duration = in.mDuration / tps;
    for (unsigned c = 0; c < in.mNumChannels; ++c) {
      const aiNodeAnim& na = *in.mChannels[c];
      const std::string node = name(na.mNodeName);
      const auto it = by_name_.find(node);
      if (it == by_name_.end()) {
        warn("clip '" + clip.name + "' animates unknown node '" + node + "'; ignored");
        continue;
      }
      const int joint = remap_[static_cast<std::size_t>(it->second)];
      add_channel(clip, joint, ChannelPath::translation, na.mPositionKeys, na.mNumPositionKeys, tps);
      add_channel(clip, joint, ChannelPath::rotation, na.mRotationKeys, na.mNumRotationKeys, tps);
      add_channel(clip, joint, ChannelPath::scale, na.mScalingKeys, na.mNumScalingKeys, tps);
    }
    for (unsigned c = 0; c < in.mNumMorphMeshChannels; ++c) add_weights_channel(clip, *in.mMorphMeshChannels[c], tps);
    for (const Channel& ch : clip.channels)
      if (!ch.times.empty()) clip.duration = std::max(clip.duration, ch.times.back());
    model_.clips.push_back(std::move(clip));
  }

  /// A channel of morph weights: Assimp names the node whose meshes it drives and gives, per key,
  /// (target, weight) pairs; the channel keeps every target's weight, 0 for those a key omits.
  void add_weights_channel(anim::Clip& clip, const aiMeshMorphAnim& in, double tps) {
    const std::string node = name(in.mName);
    const auto it = by_name_.find(node);
    const int joint = it == by_name_.end() ? -1 : remap_[static_cast<std::size_t>(it->second)];
    std::size_t targets = 0;
    for (const mesh::Mesh& m : model_.meshes)
      if (m.node == joint) targets = std::max(targets, m.morph_targets.size());
    if (targets == 0) {
      warn("clip '" + clip.name + "' animates the morph weights of node '" + node +
           "', which has no mesh with morph targets; ignored");
      return;
    }
    Channel ch;
    ch.joint = joint;
    ch.path = ChannelPath::weights;
    ch.weight_count = static_cast<int>(targets);
    for (unsigned k = 0; k < in.mNumKeys; ++k) {
      const aiMeshMorphKey& key = in.mKeys[k];
      const double t = key.mTime / tps;
      if (!std::isfinite(t)) throw FileError("clip '" + clip.name + "' has a NaN key time");
      if (!ch.times.empty() && t <= ch.times.back()) continue;
      ch.times.push_back(t);
      ch.values.resize(ch.values.size() + targets, 0.0);
      for (unsigned i = 0; i < key.mNumValuesAndWeights; ++i) {
        if (key.mValues[i] >= targets) continue;
        if (!std::isfinite(key.mWeights[i]))
          throw FileError("clip '" + clip.name + "' has NaN or infinite morph weights");
        ch.values[ch.values.size() - targets + key.mValues[i]] = key.mWeights[i];
      }
    }
    if (!ch.times.empty()) clip.channels.push_back(std::move(ch));
  }

  template <class Key>
  void add_channel(anim::Clip& clip, int joint, ChannelPath path, const Key* keys, unsigned n, double tps) {
    Channel ch;
    ch.joint = joint;
    ch.path = path;
    ch.interpolation = anim::Interpolation::linear;  // Assimp keeps no per-key interpolation
    bool non_uniform = false;
    for (unsigned k = 0; k < n; ++k) {
      const double t = keys[k].mTime / tps;
      if (!std::isfinite(t)) throw FileError("clip '" + clip.name + "' has a NaN key time");
      if (!ch.times.empty() && t <= ch.times.back()) continue;  // keep times strictly increasing
      ch.times.push_back(t);
      if constexpr (std::is_same_v<Key, aiQuatKey>) {
        const aiQuaternion& q = keys[k].mValue;
        ch.values.insert(ch.values.end(), {q.x, q.y, q.z, q.w});
      } else {
        const aiVector3D& v = keys[k].mValue;
        ch.values.insert(ch.values.end(), {v.x, v.y, v.z});
        if (path == ChannelPath::scale && !Transform{.scale = Eigen::Vector3d(v.x, v.y, v.z)}.is_uniform())
          non_uniform = true;
      }
    }
    for (double v : ch.values)
      if (!std::isfinite(v)) throw FileError("clip '" + clip.name + "' has NaN or infinite key values");
    if (non_uniform)
      warn("clip '" + clip.name + "' scales joint '" + model_.skeleton.names()[joint] + "' non-uniformly" +
           kApproximated);
    if (!ch.times.empty()) clip.channels.push_back(std::move(ch));
  }

  void warn(std::string message) { model_.warnings.push_back(std::move(message)); }

  /// A name of the file as UTF-8 (utf8_name); the first one converted is said.
  std::string name(const aiString& s) {
    bool converted = false;
    std::string out = utf8_name(s.C_Str(), converted);
    if (converted && !said_latin1_) {
      said_latin1_ = true;
      warn("names that are not UTF-8 (the first: '" + out + "') are read as Latin-1");
    }
    return out;
  }

  static constexpr std::uintmax_t kMaxTextureBytes = 256u << 20;

  const aiScene& scene_;
  const LoadOptions& options_;
  std::filesystem::path directory_;
  std::map<std::string, int> texture_of_path_;
  anim::EditableSkeleton editable_;
  std::map<std::string, int> by_name_;
  std::vector<std::pair<int, unsigned>> mesh_refs_;
  std::vector<int> remap_;        ///< editable node -> skeleton joint
  std::vector<bool> mirrored_;    ///< per editable node: m_i, parity of mirrors down to it (see kMirror)
  std::vector<bool> own_mirror_;  ///< per editable node: its own matrix mirrors
  anim::RiggedModel model_;
  bool said_latin1_ = false;
  unsigned unrated_clips_ = 0;  ///< clips whose rate the file does not give
  std::string first_unrated_;
};

}  // namespace

anim::RiggedModel load_model(const std::filesystem::path& path, const LoadOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw FileError("cannot read '" + path.string() + "': is a directory");
  if (!std::filesystem::is_regular_file(path, ec)) throw FileError("cannot read '" + path.string() + "': no such file");
  detail::preflight(path);
  Assimp::Importer importer;
  // Readers of animation formats (.bvh) otherwise make up a mesh of sticks for the skeleton:
  // that is not the user's model, and the file is refused as holding no mesh.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
  // Vertices that agree in every attribute are joined once the model is read
  // (mesh::join_identical_vertices), not by Assimp's JoinIdenticalVertices: glTF's indexed
  // vertices are kept as the file has them, so that vertex ids are the file's.
  // Spherical, cylindrical and planar texture mappings (LWO, NFF) become UV coordinates, so a
  // texture is drawn and written as the file means it.
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_GenUVCoords);
  // Readers of animation formats flag their scene incomplete, as it has no mesh.
  if (scene != nullptr && scene->mRootNode != nullptr && scene->mNumMeshes == 0 && scene->mNumAnimations > 0)
    throw FileError("cannot load '" + path.string() + "': " + no_mesh(*scene));
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 || scene->mRootNode == nullptr) {
    // For a corrupt or truncated file of a format it reads, Assimp may only say that no reader
    // suits it: say what the file is not. Its message can quote the rest of the file: bounded.
    const std::string error = detail::excerpt(importer.GetErrorString()), ext = path.extension().string();
    const bool no_reader = error.find("No suitable reader") != std::string::npos;
    const std::string what = no_reader && !ext.empty() && importer.IsExtensionSupported(ext)
                                 ? "not a valid " + ext + " file (corrupt, truncated or of another format): "
                                 : std::string();
    throw FileError(
        "cannot load '" + path.string() + "': " + what +
        (error.empty() ? "the importer gave no reason (corrupt, truncated or unsupported content)" : error));
  }
  try {
    Loader loader(*scene, options, path.parent_path());
    anim::RiggedModel model = loader.run();
    detail::number_file_vertices(path, model.meshes);
    if (detail::is_gltf(path))
      detail::read_gltf_extras(path, model);
    else
      for (mesh::Mesh& m : model.meshes) mesh::join_identical_vertices(m);
    check_scale_keys(model);
    start_clips_at_zero(model);
    loader.conjugate_keys(model);
    return model;
  } catch (const FileError&) {
    throw;
  } catch (const InvalidInputError& e) {
    throw FileError("'" + path.string() + "' is not a valid model: " + e.what());
  }
}

}  // namespace cgamesh::io
