#include "surgery_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/number_text.hpp"

namespace cgamesh::surgery {

namespace {

/// Per axis, the least and greatest coordinate of the rows of `points` (at least one row). The
/// coordinates are scanned 12 (4 rows) at a time, which vectorises, then reduced per axis.
std::pair<Eigen::Array3f, Eigen::Array3f> float_bounds(const mesh::RowMatrixXf<3>& points) {
  using Array12f = Eigen::Array<float, 12, 1>;
  const float* x = points.data();
  const Eigen::Index n = points.size();
  Array12f lo = Eigen::Map<const Eigen::Array3f>(x).replicate<4, 1>(), hi = lo;  // slot k: axis k % 3
  Eigen::Index i = 0;
  for (; i + 12 <= n; i += 12) {
    const Eigen::Map<const Array12f> block(x + i);
    lo = lo.min(block);
    hi = hi.max(block);
  }
  Eigen::Array3f l = lo.segment<3>(0).min(lo.segment<3>(3)).min(lo.segment<3>(6).min(lo.segment<3>(9)));
  Eigen::Array3f h = hi.segment<3>(0).max(hi.segment<3>(3)).max(hi.segment<3>(6).max(hi.segment<3>(9)));
  for (; i < n; i += 3) {
    const Eigen::Map<const Eigen::Array3f> row(x + i);
    l = l.min(row);
    h = h.max(row);
  }
  return {l, h};
}

}  // namespace

double bounding_diagonal(const mesh::RowMatrixXf<3>& points) {
  if (points.rows() == 0) return 0;
  const auto [lo, hi] = float_bounds(points);
  const Eigen::Array3f extent = hi - lo;
  return static_cast<double>(std::sqrt((extent[0] * extent[0] + extent[1] * extent[1]) + extent[2] * extent[2]));
}

Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d axis = std::abs(n.x()) < 0.6 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(axis).normalized();
}

int face_total(const anim::RiggedModel& model) {
  int n = 0;
  for (const mesh::Mesh& m : model.meshes) n += static_cast<int>(m.face_count());
  return n;
}

void copy_rig(const anim::RiggedModel& model, anim::RiggedModel& out) {
  out.skeleton = model.skeleton;
  out.clips = model.clips;
  out.materials = model.materials;
  out.textures = model.textures;
  out.warnings = model.warnings;
  out.source_max_influences = model.source_max_influences;
}

void require_index_fits(const anim::RiggedModel& model, const SurfaceIndex& index, const std::string& operation) {
  if (index.meshes.size() != model.meshes.size())
    throw InvalidInputError(operation + ": the surface index has " + std::to_string(index.meshes.size()) +
                            " meshes, the model " + std::to_string(model.meshes.size()));
  for (std::size_t i = 0; i < model.meshes.size(); ++i)
    if (static_cast<Eigen::Index>(index.meshes[i].weld.size()) != model.meshes[i].vertex_count() ||
        static_cast<Eigen::Index>(index.meshes[i].neighbor.size()) != model.meshes[i].face_count())
      throw InvalidInputError(operation + ": the surface index does not fit mesh '" + model.meshes[i].name + "'");
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

PlacedBox placed_box(const Placement& placement) {
  PlacedBox b;
  for (const auto& p : placement.positions)
    if (p.rows() > 0) {
      const auto [lo, hi] = float_bounds(p);
      b.lo = b.lo.cwiseMin(lo.cast<double>().matrix());
      b.hi = b.hi.cwiseMax(hi.cast<double>().matrix());
    }
  return b;
}

PlacedBox placed_box(const SurfaceIndex& index) {
  PlacedBox b;
  for (const MeshIndex& m : index.meshes)
    if (m.bvh.face_count() > 0) {
      b.lo = b.lo.cwiseMin(m.bvh.lower());
      b.hi = b.hi.cwiseMax(m.bvh.upper());
    }
  return b;
}

void require_in_reach(const PlacedBox& b, const Eigen::Vector3d& point, const std::string& what) {
  if (b.empty()) return;
  const double reach = kMaxToolReach * std::max(b.diagonal(), 1e-30);
  const Eigen::Vector3d outside = (b.lo - point).cwiseMax(point - b.hi).cwiseMax(0.0);
  if (!(outside.stableNorm() <= reach))
    throw InvalidInputError(what + " lies " + number_text(outside.stableNorm()) + " from the model, more than " +
                            number_text(kMaxToolReach) + " times the model's size (" + number_text(b.diagonal()) +
                            "): no geometric sense for this model");
}

void require_size_in_reach(const PlacedBox& b, double length, const std::string& what) {
  if (b.empty()) return;
  if (!(length <= kMaxToolReach * std::max(b.diagonal(), 1e-30)))
    throw InvalidInputError(what + " " + number_text(length) + " is more than " + number_text(kMaxToolReach) +
                            " times the model's size (" + number_text(b.diagonal()) +
                            "): no geometric sense for this model");
}

namespace {

/// The rows `kept` of `old` (all of them, as one block copy, when `all`), then the rows of
/// `fresh`.
template <class Matrix>
Matrix stack_rows(const Matrix& old, const std::vector<int>& kept, bool all, const Matrix& fresh) {
  if (old.rows() == 0) return Matrix(0, old.cols());
  Matrix out(static_cast<Eigen::Index>(kept.size()) + fresh.rows(), old.cols());
  if (all) {
    out.topRows(old.rows()) = old;
  } else {
    for (std::size_t i = 0; i < kept.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = old.row(kept[i]);
  }
  out.bottomRows(fresh.rows()) = fresh;
  return out;
}

}  // namespace

std::vector<int> checked_removed_faces(const mesh::Mesh& old, const LocalEdit& edit) {
  const auto nf = old.face_count();
  const int total = static_cast<int>(old.vertex_count() + static_cast<Eigen::Index>(edit.new_vertices().size()));
  std::vector<int> removed(edit.removed_faces().begin(), edit.removed_faces().end());
  std::sort(removed.begin(), removed.end());
  for (std::size_t i = 0; i < removed.size(); ++i)
    if (removed[i] < 0 || removed[i] >= nf || (i > 0 && removed[i] == removed[i - 1]))
      throw InvalidInputError("surgery: removed face " + std::to_string(removed[i]) + " out of range or repeated");
  for (const auto& t : edit.new_faces())
    for (int x : t)
      if (x < 0 || x >= total)
        throw InvalidInputError("surgery: new face vertex " + std::to_string(x) + " out of range");
  for (const int f : edit.new_face_origins())
    if (f != LocalEdit::kCutSurface && (f < 0 || f >= nf))
      throw InvalidInputError("surgery: a new face's material origin " + std::to_string(f) + " is not an old face");
  return removed;
}

bool has_cut_surface(const LocalEdit& edit) {
  const std::span<const int> origins = edit.new_face_origins();
  return std::find(origins.begin(), origins.end(), LocalEdit::kCutSurface) != origins.end();
}

int new_face_material(const mesh::Mesh& old, const LocalEdit& edit, std::size_t t, int cut_surface) {
  if (!edit.new_face_origins().empty()) {
    const int f = edit.new_face_origins()[t];
    return f == LocalEdit::kCutSurface ? cut_surface : old.face_material(f);
  }
  return edit.new_face_parents().empty() ? old.material : old.face_material(edit.new_face_parents()[t]);
}

void solve_rest_positions(mesh::Mesh& m, const anim::SkinningPalette& palette, const mesh::RowMatrixXf<3>& placed,
                          std::span<const mesh::VertexSource> origins, Eigen::Index first, RestPosition rest,
                          std::span<const char> off_surface) {
  for (std::size_t k = 0; k < origins.size(); ++k) {
    const bool forced = !off_surface.empty() && off_surface[k] != 0;
    if (!forced && (rest == RestPosition::parametric || origins[k].count() == 1)) continue;
    const Eigen::Index v = first + static_cast<Eigen::Index>(k);
    const Eigen::Matrix<double, 3, 4> a = anim::blended_affine(m, palette, v);
    // A blend of joints that collapse space has no inverse: keep the parametric point.
    // The placed point is the skinned morphed rest point: its rest position is that less the
    // vertex's own morph displacement (blended from its sources' as its UVs are).
    if (const auto x = unskin(a.leftCols<3>(), placed.row(v).cast<double>().transpose() - a.col(3)))
      m.positions.row(v) = x->cast<float>().transpose() - anim::morph_offset(m, palette.morph_weights, v).transpose();
  }
}

void bound_warnings(std::vector<std::string>& warnings, std::size_t keep) {
  if (warnings.size() <= keep) return;
  const std::size_t more = warnings.size() - keep;
  warnings.resize(keep);
  warnings.push_back("... and " + std::to_string(more) + " more warnings like these");
}

std::optional<Eigen::Vector3d> unskin(const Eigen::Matrix3d& l, const Eigen::Vector3d& y) {
  const double scale = l.cwiseAbs().maxCoeff();
  if (!(std::abs(l.determinant()) > 1e-12 * scale * scale * scale)) return std::nullopt;
  return l.inverse() * y;  // 3×3: cofactors
}

void set_placed_normal(mesh::Mesh& m, const anim::SkinningPalette& palette, Eigen::Index v,
                       const Eigen::Vector3d& placed_normal) {
  if (m.normals.rows() == 0 || !(placed_normal.squaredNorm() > 0)) return;
  const Eigen::Vector3d n = anim::blended_affine(m, palette, v).leftCols<3>().transpose() * placed_normal;
  if (n.squaredNorm() > 0) m.normals.row(v) = n.normalized().cast<float>().transpose();
}

EditedMesh apply_edit(const mesh::Mesh& old, const mesh::RowMatrixXf<3>& placed, const anim::SkinningPalette& palette,
                      const LocalEdit& edit, RestPosition rest, int cut_surface) {
  const auto nv = static_cast<int>(old.vertex_count());
  const auto nf = old.face_count();
  const int total = nv + static_cast<int>(edit.new_vertices().size());
  const std::vector<int> removed = checked_removed_faces(old, edit);
  // Kept faces in runs between removed ones (block copies), then the new faces.
  mesh::Faces faces(nf - static_cast<Eigen::Index>(removed.size()) + static_cast<Eigen::Index>(edit.new_faces().size()),
                    3);
  Eigen::Index row = 0, from = 0;
  const auto copy_run = [&](Eigen::Index to) {
    faces.middleRows(row, to - from) = old.faces.middleRows(from, to - from);
    row += to - from;
  };
  for (const int f : removed) {
    copy_run(f);
    from = f + 1;
  }
  copy_run(nf);
  for (const auto& t : edit.new_faces()) faces.row(row++) << t[0], t[1], t[2];
  // Materials along the same runs, where the faces' differ.
  std::vector<int> fresh_materials(edit.new_faces().size());
  for (std::size_t t = 0; t < fresh_materials.size(); ++t)
    fresh_materials[t] = new_face_material(old, edit, t, cut_surface);
  mesh::RowArray<int, 1> face_materials;
  if (old.face_materials.rows() > 0 ||
      std::any_of(fresh_materials.begin(), fresh_materials.end(), [&](int x) { return x != old.material; })) {
    face_materials.resize(faces.rows());
    Eigen::Index at = 0, start = 0;
    const auto copy_materials = [&](Eigen::Index to) {
      for (Eigen::Index f = start; f < to; ++f) face_materials[at++] = old.face_material(f);
    };
    for (const int f : removed) {
      copy_materials(f);
      start = f + 1;
    }
    copy_materials(nf);
    for (const int x : fresh_materials) face_materials[at++] = x;
  }
  // Used vertices; old ones keep their order, then the new ones.
  std::vector<int> remap(static_cast<std::size_t>(total), -1);
  const int* ids = faces.data();
  for (Eigen::Index i = 0; i < faces.size(); ++i) remap[static_cast<std::size_t>(ids[i])] = 0;
  std::vector<int> kept;
  kept.reserve(static_cast<std::size_t>(nv));
  for (int v = 0; v < nv; ++v)
    if (remap[static_cast<std::size_t>(v)] == 0) {
      remap[static_cast<std::size_t>(v)] = static_cast<int>(kept.size());
      kept.push_back(v);
    }
  const bool all = static_cast<int>(kept.size()) == nv;
  EditedMesh out;
  out.origins.reserve(static_cast<std::size_t>(total));
  for (const int v : kept) out.origins.push_back(mesh::VertexSource::copy(v));
  std::vector<mesh::VertexSource> fresh_sources;
  std::vector<int> fresh;  // used new vertices, as extended ids
  for (int x = nv; x < total; ++x)
    if (remap[static_cast<std::size_t>(x)] == 0) {
      remap[static_cast<std::size_t>(x)] = static_cast<int>(kept.size() + fresh.size());
      fresh.push_back(x);
      fresh_sources.push_back(edit.new_vertices()[static_cast<std::size_t>(x - nv)].source);
      out.origins.push_back(fresh_sources.back());
    }
  int* out_ids = faces.data();
  for (Eigen::Index i = 0; i < faces.size(); ++i) out_ids[i] = remap[static_cast<std::size_t>(out_ids[i])];
  // Old vertices are copied as they are; only the new ones are blended (resample).
  mesh::Mesh blended = mesh::resample(old, fresh_sources, mesh::Faces(0, 3));
  mesh::Mesh& m = out.mesh;
  m.name = old.name;
  m.node = old.node;
  m.material = old.material;
  m.faces = std::move(faces);
  m.face_materials = std::move(face_materials);
  m.positions = stack_rows(old.positions, kept, all, blended.positions);
  m.normals = stack_rows(old.normals, kept, all, blended.normals);
  m.uvs = stack_rows(old.uvs, kept, all, blended.uvs);
  m.generated = stack_rows(old.generated.rows() > 0 ? old.generated : decltype(old.generated)::Zero(nv), kept, all,
                           blended.generated);
  m.file_index = stack_rows(old.file_index, kept, all, blended.file_index);
  m.morph_weights = old.morph_weights;
  m.morph_targets = std::move(blended.morph_targets);
  for (std::size_t t = 0; t < m.morph_targets.size(); ++t) {
    m.morph_targets[t].positions = stack_rows(old.morph_targets[t].positions, kept, all, m.morph_targets[t].positions);
    m.morph_targets[t].normals = stack_rows(old.morph_targets[t].normals, kept, all, m.morph_targets[t].normals);
  }
  if (!old.skin.empty()) {
    m.skin = std::move(blended.skin);
    m.skin.joints = stack_rows(old.skin.joints, kept, all, m.skin.joints);
    m.skin.weights = stack_rows(old.skin.weights, kept, all, m.skin.weights);
  }
  mesh::RowMatrixXf<3> fresh_placed(static_cast<Eigen::Index>(fresh.size()), 3);
  for (std::size_t i = 0; i < fresh.size(); ++i)
    fresh_placed.row(static_cast<Eigen::Index>(i)) =
        edit.new_vertices()[static_cast<std::size_t>(fresh[i] - nv)].placed.cast<float>().transpose();
  out.placed = stack_rows(placed, kept, all, fresh_placed);
  std::vector<char> off_surface(fresh.size());
  for (std::size_t i = 0; i < fresh.size(); ++i)
    off_surface[i] = edit.new_vertices()[static_cast<std::size_t>(fresh[i] - nv)].off_surface;
  solve_rest_positions(m, palette, out.placed, std::span(out.origins).subspan(kept.size()),
                       static_cast<Eigen::Index>(kept.size()), rest, off_surface);
  for (std::size_t i = 0; i < fresh.size(); ++i)
    set_placed_normal(m, palette, static_cast<Eigen::Index>(kept.size() + i),
                      edit.new_vertices()[static_cast<std::size_t>(fresh[i] - nv)].normal);
  out.vertex_of = std::move(remap);
  return out;
}

}  // namespace cgamesh::surgery
