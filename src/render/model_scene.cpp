#include "cgamesh/render/model_scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/normals.hpp"
#include "cgamesh/surgery/pieces.hpp"

namespace cgamesh::render {
namespace {

// Moves each piece away from the centre of the placed vertices by `amount` times the
// offset of the piece's centre.
void explode_pieces(const surgery::Pieces& p, double amount, mesh::RowMatrixXf<3>& positions) {
  if (p.count < 2) return;
  std::vector<Eigen::Vector3d> sum(static_cast<std::size_t>(p.count), Eigen::Vector3d::Zero());
  std::vector<int> count(static_cast<std::size_t>(p.count), 0);
  Eigen::Vector3d all = Eigen::Vector3d::Zero();
  int used = 0;
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    const int id = p.of_vertex[static_cast<std::size_t>(v)];
    if (id < 0) continue;
    sum[static_cast<std::size_t>(id)] += positions.row(v).transpose().cast<double>();
    ++count[static_cast<std::size_t>(id)];
    all += positions.row(v).transpose().cast<double>();
    ++used;
  }
  const Eigen::Vector3d centre = all / std::max(used, 1);
  for (Eigen::Index v = 0; v < positions.rows(); ++v) {
    const int piece = p.of_vertex[static_cast<std::size_t>(v)];
    if (piece < 0) continue;
    const auto id = static_cast<std::size_t>(piece);
    const Eigen::Vector3d move = amount * (sum[id] / count[id] - centre);
    positions.row(v) += move.cast<float>().transpose();
  }
}

using mesh::RowMatrixXf;

/// A distinct colour for item i (hues a golden angle apart).
Eigen::Vector3f distinct_color(int i) {
  const float h = std::fmod(0.08f + 0.618034f * static_cast<float>(i), 1.0f) * 6.0f, s = 0.62f, v = 0.93f;
  const float f = h - std::floor(h), p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  switch (static_cast<int>(h) % 6) {
    case 0:
      return {v, t, p};
    case 1:
      return {q, v, p};
    case 2:
      return {p, v, t};
    case 3:
      return {p, q, v};
    case 4:
      return {t, p, v};
    default:
      return {v, p, q};
  }
}

/// Skeleton joint of each palette entry of a mesh (its node for a static mesh), and the weight
/// each vertex gives it.
template <class F>
void for_each_influence(const mesh::Mesh& m, Eigen::Index v, F&& f) {
  if (m.skin.empty()) {
    f(m.node, 1.0f);
    return;
  }
  for (int k = 0; k < 4; ++k)
    if (m.skin.weights(v, k) > 0) f(m.skin.palette[m.skin.joints(v, k)], m.skin.weights(v, k));
}

void add_skeleton(Scene& scene, const anim::RiggedModel& model, const std::vector<Eigen::Matrix4d>& globals) {
  // Bones are the joints that skins use and their ancestors below the first used one.
  const auto parents = model.skeleton.parents();
  std::vector<char> used(static_cast<std::size_t>(model.skeleton.size()), 0);
  for (const mesh::Mesh& m : model.meshes)
    for (const int j : m.skin.palette) used[static_cast<std::size_t>(j)] = 1;
  LineSet bones;
  PointSet joints;
  const auto at = [&](int j) {
    return Eigen::Vector3f(globals[static_cast<std::size_t>(j)].topRightCorner<3, 1>().cast<float>());
  };
  for (int j = 0; j < model.skeleton.size(); ++j) {
    if (!used[static_cast<std::size_t>(j)]) continue;
    joints.points.push_back(at(j));
    const int p = parents[static_cast<std::size_t>(j)];
    if (p >= 0 && used[static_cast<std::size_t>(p)]) {
      bones.points.push_back(at(p));
      bones.points.push_back(at(j));
    }
  }
  // Dark outlines under light cores: visible on any mesh colour and background.
  LineSet bone_core = bones;
  bones.color = {0.05f, 0.05f, 0.1f};
  bones.width_pixels = 5;
  bone_core.color = {1.0f, 1.0f, 1.0f};
  bone_core.width_pixels = 2.5f;
  PointSet joint_core = joints;
  joints.color = {0.05f, 0.05f, 0.1f};
  joints.size_pixels = 10;
  joint_core.color = {1.0f, 0.6f, 0.1f};
  joint_core.size_pixels = 7;
  scene.lines.push_back(std::move(bones));
  scene.lines.push_back(std::move(bone_core));
  scene.points.push_back(std::move(joints));
  scene.points.push_back(std::move(joint_core));
}

}  // namespace

ColorMode parse_color_mode(const std::string& name, std::string& joint_name) {
  if (name.rfind("joint:", 0) == 0) {
    joint_name = name.substr(6);
    if (joint_name.empty()) throw InvalidInputError("--color joint:NAME needs a joint name");
    return ColorMode::joint;
  }
  for (const auto& [text, mode] : kColorModes)
    if (name == text && mode != ColorMode::joint) return mode;
  throw InvalidInputError("colour '" + name +
                          "': expected material, height, normal, joint:NAME, weights, piece or new");
}

Eigen::Vector3f heat_color(float t) noexcept {
  static constexpr std::array<std::array<float, 3>, 5> kStops{{{0.15f, 0.25f, 0.85f},
                                                               {0.10f, 0.75f, 0.90f},
                                                               {0.25f, 0.80f, 0.30f},
                                                               {0.98f, 0.85f, 0.15f},
                                                               {0.90f, 0.12f, 0.10f}}};
  t = std::isfinite(t) ? std::clamp(t, 0.0f, 1.0f) * 4.0f : 0.0f;
  const int i = std::min(static_cast<int>(t), 3);
  const float f = t - static_cast<float>(i);
  const auto& a = kStops[static_cast<std::size_t>(i)];
  const auto& b = kStops[static_cast<std::size_t>(i) + 1];
  return {a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])};
}

Scene model_scene(std::span<const ModelInstance> instances, const ModelSceneOptions& o,
                  std::vector<std::string>* warnings) {
  Scene scene;
  int piece_count = 0;
  for (const ModelInstance& in : instances) {
    if (!in.model) throw InvalidInputError("model_scene: a null model");
    const anim::RiggedModel& model = *in.model;
    int joint = -1;
    if (o.color == ColorMode::joint) {
      joint = model.skeleton.find(o.joint);
      if (joint < 0)
        throw InvalidInputError("unknown joint '" + o.joint + "' (joints: " + anim::name_list(model.skeleton.names()) +
                                ")");
    }
    if (static_cast<int>(in.pose.local.size()) != model.skeleton.size())
      throw InvalidInputError("model_scene: the pose has " + std::to_string(in.pose.local.size()) +
                              " joints, the skeleton " + std::to_string(model.skeleton.size()));
    std::map<int, std::shared_ptr<const Image>> decoded;  // per texture index
    const auto texture = [&](int t) -> std::shared_ptr<const Image> {
      if (t < 0 || t >= static_cast<int>(model.textures.size())) return nullptr;
      if (const auto it = decoded.find(t); it != decoded.end()) return it->second;
      std::shared_ptr<const Image> image;
      try {
        const mesh::TextureImage& ti = model.textures[static_cast<std::size_t>(t)];
        image = std::make_shared<const Image>(decode_image(ti.data(), "texture '" + ti.name + "'", warnings));
      } catch (const FileError& e) {
        if (warnings) warnings->push_back(std::string(e.what()) + "; drawn without it");
      }
      return decoded[t] = image;
    };
    const auto gv = anim::global_versors(model.skeleton, in.pose);
    const auto gm = anim::global_matrices(model.skeleton, in.pose);
    for (const mesh::Mesh& m : model.meshes) {
      const anim::SkinningPalette palette = anim::make_palette(m, gv, gm, o.skinning, anim::morph_weights(in.pose, m));
      DrawMesh d;
      anim::skin_into(m, palette, d.positions, &d.normals);
      d.faces = m.faces;
      const std::size_t mi = static_cast<std::size_t>(&m - model.meshes.data());
      if (in.positions != nullptr) {
        if (mi >= in.positions->size() || (*in.positions)[mi].rows() != m.vertex_count())
          throw InvalidInputError("model_scene: the positions given do not fit mesh " + std::to_string(mi));
        d.positions = (*in.positions)[mi];
      }
      const auto mesh_pieces = [&] {
        return in.index != nullptr && mi < in.index->meshes.size() ? surgery::pieces(m, in.index->meshes[mi].weld)
                                                                   : surgery::pieces(m);
      };
      if (o.explode != 0) explode_pieces(mesh_pieces(), o.explode, d.positions);
      const auto paint = [&](DrawMesh& draw, int material) {
        if (material < 0 || material >= static_cast<int>(model.materials.size())) return;
        const mesh::Material& mat = model.materials[static_cast<std::size_t>(material)];
        draw.base_color = mat.base_color;
        if (m.uvs.rows() > 0) draw.texture = texture(mat.base_color_texture);
        if (draw.texture) draw.uvs = m.uvs;
      };
      if (o.color != ColorMode::material) {
        d.base_color = {1, 1, 1, 1};
      } else if (m.face_materials.rows() > 0 && m.face_materials.rows() == m.face_count()) {
        // Faces of several materials (a cut's caps, a hole's walls): one draw per material.
        std::map<int, std::vector<Eigen::Index>> groups;
        for (Eigen::Index f = 0; f < m.face_count(); ++f) groups[m.face_materials[f]].push_back(f);
        for (const auto& [material, faces] : groups) {
          DrawMesh part = d;
          part.faces.resize(static_cast<Eigen::Index>(faces.size()), 3);
          for (std::size_t i = 0; i < faces.size(); ++i)
            part.faces.row(static_cast<Eigen::Index>(i)) = m.faces.row(faces[i]);
          paint(part, material);
          scene.meshes.push_back(std::move(part));
        }
        continue;
      } else {
        paint(d, m.material);
      }
      const Eigen::Index nv = m.vertex_count();
      switch (o.color) {
        case ColorMode::material:
        case ColorMode::height:  // after every mesh is placed
          break;
        case ColorMode::normal: {
          const RowMatrixXf<3> n = d.normals.rows() > 0 ? d.normals : mesh::area_weighted_normals(d.positions, d.faces);
          d.colors = (n.array() + 1.0f) / 2.0f;
          break;
        }
        case ColorMode::joint:
        case ColorMode::weights:
          d.colors = RowMatrixXf<3>::Zero(nv, 3);
          for (Eigen::Index v = 0; v < nv; ++v) {
            if (o.color == ColorMode::weights) {
              for_each_influence(
                  m, v, [&](int j, float w) { d.colors.row(v) += w * distinct_color(std::max(j, 0)).transpose(); });
            } else {
              float w_joint = 0;
              for_each_influence(m, v, [&](int j, float w) { w_joint += j == joint ? w : 0.0f; });
              d.colors.row(v) = heat_color(w_joint).transpose();
            }
          }
          break;
        case ColorMode::piece: {
          const surgery::Pieces p = mesh_pieces();
          d.colors.resize(nv, 3);
          for (Eigen::Index v = 0; v < nv; ++v) {
            const int id = p.of_vertex[static_cast<std::size_t>(v)];
            d.colors.row(v) =
                (id < 0 ? Eigen::Vector3f(0.6f, 0.6f, 0.6f) : distinct_color(piece_count + id)).transpose();
          }
          piece_count += p.count;
          break;
        }
        case ColorMode::generated:
          d.colors.resize(nv, 3);
          for (Eigen::Index v = 0; v < nv; ++v)
            d.colors.row(v) = (m.generated.size() == nv && m.generated[v] ? Eigen::Vector3f(0.95f, 0.15f, 0.1f)
                                                                          : Eigen::Vector3f(0.7f, 0.7f, 0.7f))
                                  .transpose();
          break;
      }
      scene.meshes.push_back(std::move(d));
    }
    if (o.skeleton) add_skeleton(scene, model, gm);
  }
  if (o.color == ColorMode::height) {
    float lo = INFINITY, hi = -INFINITY;
    for (const DrawMesh& d : scene.meshes)
      if (d.positions.rows() > 0) {
        lo = std::min(lo, d.positions.col(1).minCoeff());
        hi = std::max(hi, d.positions.col(1).maxCoeff());
      }
    const float span = hi > lo ? hi - lo : 1.0f;
    for (DrawMesh& d : scene.meshes) {
      d.colors.resize(d.positions.rows(), 3);
      for (Eigen::Index v = 0; v < d.positions.rows(); ++v)
        d.colors.row(v) = heat_color((d.positions(v, 1) - lo) / span).transpose();
    }
  }
  return scene;
}

}  // namespace cgamesh::render
