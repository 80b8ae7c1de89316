#include "cgamesh/deform/bound_deformer.hpp"

#include <algorithm>
#include <string>

#include <Eigen/LU>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/deform/morph_transport.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/mesh/normals.hpp"
#include "deform_method.hpp"

namespace cgamesh::deform {

using detail::bad;

namespace {

/// Checks the points and lengths every method's spec may give (handles' spheres and boxes, keys)
/// against `reach`; a method checks its own (an IK chain, a lattice box) when it binds.
void check_reach(const DeformSpec& spec, const detail::Reach& reach) {
  for (std::size_t h = 0; h < spec.handles.size(); ++h) {
    const HandleSelection& s = spec.handles[h];
    const std::string field = "handles[" + std::to_string(h) + "]";
    const auto& v = s.shape;
    if (s.kind == HandleSelection::Kind::sphere) {
      reach.point({v[0], v[1], v[2]}, field + ".sphere");
      reach.length(v[3], field + ".sphere");
    } else if (s.kind == HandleSelection::Kind::box) {
      reach.point({v[0], v[1], v[2]}, field + ".box");
      reach.point({v[3], v[4], v[5]}, field + ".box");
    }
  }
  for (std::size_t k = 0; k < spec.keys.size(); ++k) {
    const std::string field = "keys[" + std::to_string(k) + "]";
    reach.point(spec.keys[k].center, field + ".center");
    reach.vector(spec.keys[k].translate, field + ".translate");
  }
}

}  // namespace

std::vector<Eigen::Vector3d> BoundMethod::control_points(std::span<const cga::Versor<double>>) const { return {}; }

DeformSpace default_space(const anim::RiggedModel& model) noexcept {
  const bool rigged =
      std::any_of(model.meshes.begin(), model.meshes.end(), [](const mesh::Mesh& m) { return !m.skin.empty(); });
  return rigged ? DeformSpace::world : DeformSpace::mesh;
}

mesh::WorldSurface rest_surfaces(const anim::RiggedModel& model, DeformSpace space) {
  mesh::WorldSurface out;
  if (space == DeformSpace::mesh) {
    for (const mesh::Mesh& m : model.meshes) {
      out.positions.push_back(m.positions);
      out.normals.push_back(m.normals);
    }
    return out;
  }
  const anim::Pose bind = anim::rest_pose(model.skeleton);
  const auto gv = anim::global_versors(model.skeleton, bind);
  const auto gm = anim::global_matrices(model.skeleton, bind);
  for (const mesh::Mesh& m : model.meshes) {
    mesh::RowMatrixXf<3>& x = out.positions.emplace_back();
    mesh::RowMatrixXf<3>& n = out.normals.emplace_back();
    anim::skin_into(m, anim::make_palette(m, gv, gm, anim::SkinningMode::matrix), x, &n);
  }
  return out;
}

std::vector<mesh::RowMatrixXf<3>> rest_positions(const anim::RiggedModel& model, DeformSpace space) {
  return rest_surfaces(model, space).positions;
}

BoundDeformer::BoundDeformer(const DeformSpec& spec, const anim::RiggedModel& model, const SpecBindOptions& options)
    : mesh_(spec.mesh), space_(spec.space.value_or(default_space(model))) {
  if (mesh_ < 0 || mesh_ >= static_cast<int>(model.meshes.size()))
    bad("mesh", "no mesh " + std::to_string(mesh_) + " (the model has " + std::to_string(model.meshes.size()) + ")");
  const mesh::Mesh& target = model.meshes[static_cast<std::size_t>(mesh_)];
  if (space_ == DeformSpace::mesh) {
    rest_ = target.positions;
  } else {
    // The bind pose of this mesh alone, and each vertex's inverse bind map for to_mesh_space().
    const anim::Pose bind = anim::rest_pose(model.skeleton);
    const anim::SkinningPalette palette =
        anim::make_palette(target, anim::global_versors(model.skeleton, bind),
                           anim::global_matrices(model.skeleton, bind), anim::SkinningMode::matrix);
    rest_ = anim::skin(target, palette);
    to_mesh_.resize(static_cast<std::size_t>(target.vertex_count()));
    for (Eigen::Index i = 0; i < target.vertex_count(); ++i) {
      const Eigen::Matrix<double, 3, 4> m = anim::blended_affine(target, palette, i);
      Eigen::Matrix3d inverse;
      bool invertible = false;
      m.leftCols<3>().computeInverseWithCheck(inverse, invertible);
      if (!invertible)
        bad("space", "world: the bind skinning of vertex " + std::to_string(target.vertex_label(i)) +
                         " is singular, so an edit cannot be mapped back to the mesh (use \"space\": \"mesh\")");
      to_mesh_[static_cast<std::size_t>(i)] << inverse, -inverse * m.col(3);
    }
  }
  const detail::Reach reach(rest_);
  check_reach(spec, reach);
  method_ = detail::deform_methods()[static_cast<std::size_t>(spec.method())].bind({spec, target, rest_, reach, options},
                                                                                   bound_);
}

namespace {

/// @throws InvalidInputError unless `keys` has the bound count.
void check_key_count(std::span<const cga::Versor<double>> keys, std::size_t bound) {
  if (keys.size() != bound)
    throw InvalidInputError(std::to_string(keys.size()) + " keys given, bound to " + std::to_string(bound));
}

}  // namespace

std::vector<Eigen::Vector3d> BoundDeformer::control_points(std::span<const cga::Versor<double>> keys) const {
  check_key_count(keys, bound_.keys.size());
  return method_->control_points(keys);
}

void BoundDeformer::apply(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out,
                          ArapReport* report) const {
  check_key_count(keys, bound_.keys.size());
  method_->apply(keys, out, report);
}

mesh::RowMatrixXf<3> BoundDeformer::apply(std::span<const cga::Versor<double>> keys) const {
  mesh::RowMatrixXf<3> out;
  apply(keys, out);
  return out;
}

mesh::RowMatrixXf<3> BoundDeformer::to_mesh_space(const mesh::RowMatrixXf<3>& positions) const {
  if (positions.rows() != rest_.rows())
    throw InvalidInputError("to_mesh_space: " + std::to_string(positions.rows()) + " positions for " +
                            std::to_string(rest_.rows()) + " vertices");
  if (space_ == DeformSpace::mesh) return positions;
  mesh::RowMatrixXf<3> out(positions.rows(), 3);
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    const Eigen::Matrix<double, 3, 4>& m = to_mesh_[static_cast<std::size_t>(i)];
    out.row(i) = (m.leftCols<3>() * positions.row(i).transpose().cast<double>() + m.col(3)).transpose().cast<float>();
  }
  return out;
}

anim::RiggedModel BoundDeformer::deformed_model(const anim::RiggedModel& model,
                                                const mesh::RowMatrixXf<3>& positions) const {
  anim::RiggedModel out = model;
  if (mesh_ >= static_cast<int>(out.meshes.size()) ||
      out.meshes[static_cast<std::size_t>(mesh_)].vertex_count() != rest_.rows())
    throw InvalidInputError("deformed_model: the model is not the one bound (mesh " + std::to_string(mesh_) +
                            " has another vertex count)");
  mesh::Mesh& m = out.meshes[static_cast<std::size_t>(mesh_)];
  const mesh::RowMatrixXf<3> rest = to_mesh_space(positions);
  m.normals = mesh::reshaped_normals(m, rest);
  transport_morph_targets(m, rest);
  m.positions = rest;
  return out;
}

mesh::WorldSurface BoundDeformer::deformed_surfaces(const anim::RiggedModel& model, const mesh::RowMatrixXf<3>& positions) const {
  mesh::WorldSurface out = rest_surfaces(deformed_model(model, positions), space_);
  out.positions[static_cast<std::size_t>(mesh_)] = positions;  // not through to_mesh_space and back
  return out;
}

std::vector<std::string> BoundDeformer::write(const anim::RiggedModel& model, const mesh::RowMatrixXf<3>& positions,
                                              const std::filesystem::path& out) const {
  return io::write_model(io::is_rigged_format(out) ? deformed_model(model, positions) : model, out,
                         [&] { return deformed_surfaces(model, positions); });
}

}  // namespace cgamesh::deform
