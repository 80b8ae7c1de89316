#include "surgery_common.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

namespace cgamesh::surgery {

std::uint64_t edge_key(int a, int b) noexcept {
  const auto [lo, hi] = std::minmax(a, b);
  return directed_key(lo, hi);
}

std::uint64_t directed_key(int a, int b) noexcept {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

std::vector<double> signed_distances(const mesh::RowMatrixXf<3>& placed, const Eigen::Vector3d& n, double d,
                                     const cga::Vector<double>& plane, Predicates predicates) {
  std::vector<double> out(static_cast<std::size_t>(placed.rows()));
  if (predicates == Predicates::cga) {
    for (Eigen::Index i = 0; i < placed.rows(); ++i)
      out[static_cast<std::size_t>(i)] = cga::scalar_product(cga::up<double>(placed.row(i).cast<double>().transpose()), plane);
  } else {
    for (Eigen::Index i = 0; i < placed.rows(); ++i)
      out[static_cast<std::size_t>(i)] = n.dot(placed.row(i).cast<double>().transpose()) - d;
  }
  return out;
}

double bounding_diagonal(const mesh::RowMatrixXf<3>& points) {
  if (points.rows() == 0) return 0;
  return static_cast<double>((points.colwise().maxCoeff() - points.colwise().minCoeff()).norm());
}

std::size_t PositionWelder::Hash::operator()(const std::array<float, 3>& p) const noexcept {
  std::array<std::uint32_t, 3> bits;
  std::memcpy(bits.data(), p.data(), sizeof bits);
  return (static_cast<std::size_t>(bits[0]) * 73856093u) ^ (static_cast<std::size_t>(bits[1]) * 19349663u) ^
         (static_cast<std::size_t>(bits[2]) * 83492791u);
}

int PositionWelder::operator()(int v) {
  // +0.0f folds -0.0f into 0.0f, whose bits differ.
  const std::array<float, 3> p{positions_(v, 0) + 0.0f, positions_(v, 1) + 0.0f, positions_(v, 2) + 0.0f};
  return first_.try_emplace(p, v).first->second;
}

std::vector<int> weld_by_position(const mesh::RowMatrixXf<3>& positions) {
  PositionWelder weld(positions);
  std::vector<int> out(static_cast<std::size_t>(positions.rows()));
  for (Eigen::Index i = 0; i < positions.rows(); ++i) out[static_cast<std::size_t>(i)] = weld(static_cast<int>(i));
  return out;
}

Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d axis = std::abs(n.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(axis).normalized();
}

void require_placement_fits(const anim::RiggedModel& model, const Placement& placement) {
  if (placement.positions.size() != model.meshes.size())
    throw InvalidInputError("surgery: the placement has " + std::to_string(placement.positions.size()) +
                            " meshes, the model " + std::to_string(model.meshes.size()));
  for (std::size_t i = 0; i < model.meshes.size(); ++i)
    if (placement.positions[i].rows() != model.meshes[i].vertex_count())
      throw InvalidInputError("surgery: mesh '" + model.meshes[i].name + "' has " +
                              std::to_string(model.meshes[i].vertex_count()) + " vertices but " +
                              std::to_string(placement.positions[i].rows()) + " placed positions");
}

EditedMesh apply_edit(const mesh::Mesh& old, const mesh::RowMatrixXf<3>& placed, const LocalEdit& edit) {
  const auto nv = static_cast<int>(old.vertex_count());
  const int total = nv + static_cast<int>(edit.new_vertices.size());
  std::vector<char> removed(static_cast<std::size_t>(old.face_count()), 0);
  for (int f : edit.removed_faces) {
    if (f < 0 || f >= old.face_count()) throw InvalidInputError("surgery: removed face " + std::to_string(f) + " out of range");
    removed[static_cast<std::size_t>(f)] = 1;
  }
  const auto kept = static_cast<Eigen::Index>(std::count(removed.begin(), removed.end(), 0));
  MeshFaces faces(kept + static_cast<Eigen::Index>(edit.new_faces.size()), 3);
  Eigen::Index row = 0;
  for (Eigen::Index f = 0; f < old.face_count(); ++f)
    if (removed[static_cast<std::size_t>(f)] == 0) faces.row(row++) = old.faces.row(f);
  for (const auto& t : edit.new_faces) {
    for (int x : t)
      if (x < 0 || x >= total) throw InvalidInputError("surgery: new face vertex " + std::to_string(x) + " out of range");
    faces.row(row++) << t[0], t[1], t[2];
  }
  // Compact: extended id -> output vertex, old vertices first in their order.
  std::vector<int> remap(static_cast<std::size_t>(total), -1);
  for (Eigen::Index i = 0; i < faces.size(); ++i) remap[static_cast<std::size_t>(faces.data()[i])] = 0;
  EditedMesh out;
  int next = 0;
  for (std::size_t x = 0; x < remap.size(); ++x) {
    if (remap[x] < 0) continue;
    remap[x] = next++;
    out.origins.push_back(static_cast<int>(x) < nv ? mesh::VertexSource::copy(static_cast<int>(x))
                                                   : edit.new_vertices[x - static_cast<std::size_t>(nv)]);
  }
  for (Eigen::Index i = 0; i < faces.size(); ++i) faces.data()[i] = remap[static_cast<std::size_t>(faces.data()[i])];
  out.mesh = mesh::resample(old, out.origins, faces);
  out.placed.resize(next, 3);
  for (std::size_t x = 0; x < remap.size(); ++x) {
    if (remap[x] < 0) continue;
    if (static_cast<int>(x) < nv) out.placed.row(remap[x]) = placed.row(static_cast<Eigen::Index>(x));
    else out.placed.row(remap[x]) = edit.new_placed[x - static_cast<std::size_t>(nv)].cast<float>().transpose();
  }
  out.vertex_of = std::move(remap);
  return out;
}

}  // namespace cgamesh::surgery
