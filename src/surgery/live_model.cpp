#include "cgamesh/surgery/live_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>

#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/adjacency.hpp"

#include "surgery_common.hpp"

namespace cgamesh::surgery {

LiveModel::LiveModel(anim::RiggedModel model, Placement placement)
    : model_(std::move(model)), placement_(std::move(placement)), index_(SurfaceIndex::build(model_, placement_)) {
  reserve_headroom();
}

LiveModel::LiveModel(const LiveModel& other)
    : model_(other.model_), placement_(other.placement_), index_(other.index_) {
  reserve_headroom();  // a copied vector has no spare capacity
}

LiveModel& LiveModel::operator=(const LiveModel& other) {
  if (this != &other) {
    model_ = other.model_;
    placement_ = other.placement_;
    index_ = other.index_;
    reserve_headroom();
  }
  return *this;
}

void LiveModel::reserve_headroom() {
  // So that the first operations on a large mesh copy none of its arrays, its placed positions
  // or its index (the arrays then grow by half when full).
  const auto room = [](auto n) { return n + n / 4 + 1024; };
  for (std::size_t i = 0; i < model_.meshes.size(); ++i) {
    mesh::Mesh& m = model_.meshes[i];
    m.reserve(room(m.vertex_count()), room(m.face_count()));
    placement_.positions[i].reserve(room(m.vertex_count()));
    MeshIndex& index = index_.meshes[i];
    index.neighbor.reserve(room(index.neighbor.size()));
    index.bvh.reserve(static_cast<int>(room(index.neighbor.size())));
    index.weld.reserve(room(index.weld.size()));
  }
}

namespace {

using mesh::RowMatrixXf;

/// Welded ids of the new vertices, as SurfaceIndex::build gives them (the first vertex at the same
/// rest position), but copies for different sides of a separation apart: a copy of an old vertex
/// at its place for no side welds to it, other new vertices to the first new vertex at the same
/// rest position for the same side (edge and face points never fall on an old vertex: the
/// operations snap them onto it).
void weld_new_vertices(const mesh::Mesh& m, std::span<const mesh::VertexSource> origins,
                       std::span<const signed char> side, int first, std::vector<int>& weld) {
  struct SidedPosition {
    std::array<float, 3> at;
    signed char side;
    bool operator==(const SidedPosition&) const = default;
  };
  struct Hash {
    std::size_t operator()(const SidedPosition& k) const noexcept {
      return PositionHash{}(k.at) ^ static_cast<std::size_t>(k.side + 1);
    }
  };
  FlatMap<int, SidedPosition, Hash> first_at;
  first_at.reserve(origins.size());
  for (Eigen::Index v = first; v < m.vertex_count(); ++v) {
    const auto i = static_cast<std::size_t>(v - first);
    const mesh::VertexSource& o = origins[i];
    if (side[i] == 0 && o.count() == 1 && m.positions.row(v) == m.positions.row(o.vertex[0])) {
      weld.push_back(weld[static_cast<std::size_t>(o.vertex[0])]);
      continue;
    }
    weld.push_back(*first_at.try_emplace({position_key(m.positions, v), side[i]}, static_cast<int>(v)).first);
  }
}

std::array<Eigen::Vector3f, 3> placed_corners(const mesh::Mesh& m, const RowMatrixXf<3>& placed, int f) {
  return {placed.row(m.faces(f, 0)).transpose(), placed.row(m.faces(f, 1)).transpose(),
          placed.row(m.faces(f, 2)).transpose()};
}

/// Faces are stored in three parallel places (rows of the mesh and of its face materials when
/// it has them, the BVH, the adjacency); this moves them together and remembers where faces
/// went.
class FaceSlots {
 public:
  FaceSlots(mesh::Mesh& m, const RowMatrixXf<3>& placed, MeshIndex& index)
      : m_(m),
        placed_(placed),
        index_(index),
        count_(static_cast<int>(m.face_count())),
        materials_(m.face_materials.rows() > 0) {}

  void put(int f, const std::array<int, 3>& t, int material) {
    m_.faces.row(f) << t[0], t[1], t[2];
    if (materials_) m_.face_materials[f] = material;
    index_.bvh.replace(f, placed_corners(m_, placed_, f));
  }

  /// Makes room for n faces at the end (within the arrays' spare capacity as a rule).
  void reserve_more(int n) {
    if (n <= 0) return;
    m_.faces.conservativeResize(count_ + n, Eigen::NoChange);
    if (materials_) m_.face_materials.conservativeResize(count_ + n);
    index_.neighbor.resize(static_cast<std::size_t>(count_ + n), {-1, -1, -1});
  }

  /// Adds face t after the others (room made by reserve_more), in the BVH leaf of face `near`.
  int append(const std::array<int, 3>& t, int near, int material) {
    const int f = count_++;
    m_.faces.row(f) << t[0], t[1], t[2];
    if (materials_) m_.face_materials[f] = material;
    index_.bvh.append(placed_corners(m_, placed_, f), near);
    return f;
  }

  /// Removes faces `left_over` (sorted), largest first, so that a face moved into a freed
  /// slot is never one still to be removed.
  void erase_all(const std::vector<int>& left_over) {
    origin_.reserve(left_over.size());
    for (auto it = left_over.rbegin(); it != left_over.rend(); ++it) erase(*it);
  }

  /// Removes face f; the last face takes its id.
  void erase(int f) {
    const int last = --count_;
    int* moved = origin_.find(static_cast<std::uint64_t>(last));
    const int origin = moved != nullptr && *moved >= 0 ? std::exchange(*moved, -1) : last;
    if (f != last) {
      m_.faces.row(f) = m_.faces.row(last);
      if (materials_) m_.face_materials[f] = m_.face_materials[last];
      auto& nb = index_.neighbor;
      nb[static_cast<std::size_t>(f)] = nb[static_cast<std::size_t>(last)];
      for (const int g : nb[static_cast<std::size_t>(f)])
        if (g >= 0)
          for (int& back : nb[static_cast<std::size_t>(g)])
            if (back == last) back = f;
      const auto [at, added] = origin_.try_emplace(static_cast<std::uint64_t>(f), origin);
      *at = origin;
      if (added) filled_.push_back(f);
    }
    index_.bvh.erase(f);
  }

  void shrink() {
    m_.faces.conservativeResize(count_, Eigen::NoChange);
    if (materials_) m_.face_materials.conservativeResize(count_);
    index_.neighbor.resize(static_cast<std::size_t>(count_));
  }

  /// The faces the edit moved, as (id before the edit, current id).
  [[nodiscard]] std::vector<std::pair<int, int>> moves() const {
    std::vector<std::pair<int, int>> out;
    out.reserve(filled_.size());
    for (const int now : filled_)
      if (const int* before = origin_.find(static_cast<std::uint64_t>(now)); *before >= 0)
        out.emplace_back(*before, now);
    return out;
  }

 private:
  mesh::Mesh& m_;
  const RowMatrixXf<3>& placed_;
  MeshIndex& index_;
  int count_;
  bool materials_;           ///< the mesh has face_materials
  FlatMap<int> origin_;      ///< current id -> id before the edit of a moved face, or −1 once moved on
  std::vector<int> filled_;  ///< the keys of origin_
};

/// 3-D Morton code of p in the box [lo, lo + 1/scale]: 10 bits per axis.
std::uint32_t morton(const Eigen::Vector3f& p, const Eigen::Vector3f& lo, const Eigen::Vector3f& scale) {
  const auto spread = [](std::uint32_t x) {  // bit i of x to bit 3i
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x30000ffu;
    x = (x | (x << 8)) & 0x300f00fu;
    x = (x | (x << 4)) & 0x30c30c3u;
    return (x | (x << 2)) & 0x9249249u;
  };
  const Eigen::Vector3f q = ((p - lo).cwiseProduct(scale) * 1023.0f).cwiseMax(0.0f).cwiseMin(1023.0f);
  return spread(static_cast<std::uint32_t>(q.x())) | (spread(static_cast<std::uint32_t>(q.y())) << 1) |
         (spread(static_cast<std::uint32_t>(q.z())) << 2);
}

/// Where the new faces go when they have no parents (a drill's): each into the slot of the
/// removed face next to it in Morton order of the centroids when that slot is still free, else
/// appended in that face's BVH leaf; so the BVH boxes barely grow.
struct SlotPlan {
  std::vector<int> slot;       ///< per new face: the removed face whose slot it takes, or −1
  std::vector<int> near;       ///< per appended new face: the removed face it goes next to
  std::vector<int> left_over;  ///< removed faces whose slots no new face takes, sorted
};

SlotPlan plan_slots(const mesh::Mesh& m, const RowMatrixXf<3>& placed, const std::vector<int>& removed,
                    const std::vector<std::array<int, 3>>& faces) {
  const auto centroid = [&](const std::array<int, 3>& t) {
    return Eigen::Vector3f((placed.row(t[0]) + placed.row(t[1]) + placed.row(t[2])).transpose() / 3.0f);
  };
  std::vector<Eigen::Vector3f> old_at(removed.size()), new_at(faces.size());
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (std::size_t r = 0; r < removed.size(); ++r) {
    old_at[r] = centroid({m.faces(removed[r], 0), m.faces(removed[r], 1), m.faces(removed[r], 2)});
    lo = lo.cwiseMin(old_at[r]);
    hi = hi.cwiseMax(old_at[r]);
  }
  for (std::size_t t = 0; t < faces.size(); ++t) {
    new_at[t] = centroid(faces[t]);
    lo = lo.cwiseMin(new_at[t]);
    hi = hi.cwiseMax(new_at[t]);
  }
  const Eigen::Vector3f scale = (hi - lo).cwiseMax(1e-30f).cwiseInverse();
  const auto by_code = [&](const std::vector<Eigen::Vector3f>& at) {
    std::vector<std::pair<std::uint32_t, int>> order(at.size());
    for (std::size_t i = 0; i < at.size(); ++i) order[i] = {morton(at[i], lo, scale), static_cast<int>(i)};
    std::sort(order.begin(), order.end());
    return order;
  };
  const auto old_order = by_code(old_at), new_order = by_code(new_at);
  SlotPlan plan;
  plan.slot.assign(faces.size(), -1);
  plan.near.assign(faces.size(), removed.empty() ? 0 : removed.front());
  std::vector<char> taken(removed.size(), 0);
  for (std::size_t j = 0; j < new_order.size() && !removed.empty(); ++j) {
    const std::size_t rank = j * removed.size() / new_order.size();
    const auto r = static_cast<std::size_t>(old_order[rank].second);
    const auto t = static_cast<std::size_t>(new_order[j].second);
    if (taken[r] == 0) {
      taken[r] = 1;
      plan.slot[t] = removed[r];
    } else {
      plan.near[t] = removed[r];
    }
  }
  for (std::size_t r = 0; r < removed.size(); ++r)
    if (taken[r] == 0) plan.left_over.push_back(removed[r]);
  return plan;
}

/// Where the new faces go when each lies in a removed face (its parent): the first into its
/// parent's slot, the others appended in the parent's BVH leaf; the BVH boxes barely grow.
/// `rank` maps each removed face to its index in `removed`.
SlotPlan plan_slots_by_parent(const std::vector<int>& removed, std::span<const int> parent, const FlatMap<int>& rank) {
  SlotPlan plan;
  plan.slot.assign(parent.size(), -1);
  plan.near.assign(parent.begin(), parent.end());
  std::vector<char> taken(removed.size(), 0);
  for (std::size_t t = 0; t < parent.size(); ++t) {
    const auto r = static_cast<std::size_t>(*rank.find(static_cast<std::uint64_t>(parent[t])));
    if (taken[r] == 0) {
      taken[r] = 1;
      plan.slot[t] = removed[r];
    }
  }
  for (std::size_t r = 0; r < removed.size(); ++r)
    if (taken[r] == 0) plan.left_over.push_back(removed[r]);
  return plan;
}

}  // namespace

AppliedEdit LiveModel::apply(std::size_t i, const LocalEdit& edit, RestPosition rest, const Adjust& adjust) {
  if (i >= model_.meshes.size())
    throw InvalidInputError("surgery: mesh " + std::to_string(i) + " of a model with " +
                            std::to_string(model_.meshes.size()) + " meshes");
  mesh::Mesh& m = model_.meshes[i];
  RowMatrixXf<3>& placed = placement_.positions[i];
  MeshIndex& index = index_.meshes[i];
  const std::vector<int> removed = checked_removed_faces(m, edit);
  // Removed faces by id (a hash, not a binary search: its branches mispredict).
  FlatMap<int> rank;
  rank.reserve(removed.size());
  for (std::size_t r = 0; r < removed.size(); ++r)
    rank.try_emplace(static_cast<std::uint64_t>(removed[r]), static_cast<int>(r));
  const auto is_removed = [&](int f) { return rank.find(static_cast<std::uint64_t>(f)) != nullptr; };
  const std::span<const int> parents = edit.new_face_parents();
  if (!std::all_of(parents.begin(), parents.end(), is_removed))
    throw InvalidInputError("surgery: a new face's parent is not a removed face");
  // The new faces' materials; the mesh gets a face material column (once) when they differ.
  const int cut_surface = has_cut_surface(edit) ? mesh::cut_surface_material_index(model_.materials) : -1;
  std::vector<int> materials(edit.new_faces().size());
  for (std::size_t t = 0; t < materials.size(); ++t) materials[t] = new_face_material(m, edit, t, cut_surface);
  if (m.face_materials.rows() == 0 &&
      std::any_of(materials.begin(), materials.end(), [&](int x) { return x != m.material; }))
    m.face_materials.setConstant(m.face_count(), m.material);
  const int nv = static_cast<int>(m.vertex_count());
  AppliedEdit out;
  out.old_vertex_count = nv;
  out.change.mesh = static_cast<int>(i);
  out.change.first_new_vertex = nv;
  out.change.removed_faces = static_cast<int>(removed.size());

  // Vertices: the used new ones appended, blended from their sources (section 4.3).
  out.fresh.assign(edit.new_vertices().size(), -1);
  for (const auto& t : edit.new_faces())
    for (const int x : t)
      if (x >= nv) out.fresh[static_cast<std::size_t>(x - nv)] = 0;
  std::vector<signed char> fresh_side;
  for (std::size_t k = 0; k < out.fresh.size(); ++k) {
    if (out.fresh[k] < 0) continue;
    out.fresh[k] = nv + static_cast<int>(out.change.origins.size());
    out.change.origins.push_back(edit.new_vertices()[k].source);
    fresh_side.push_back(edit.new_vertices()[k].side);
  }
  mesh::append_resampled(m, out.change.origins);
  placed.conservativeResize(m.vertex_count(), Eigen::NoChange);
  for (std::size_t k = 0; k < out.fresh.size(); ++k)
    if (out.fresh[k] >= 0) placed.row(out.fresh[k]) = edit.new_vertices()[k].placed.cast<float>().transpose();
  std::vector<char> off_surface;
  off_surface.reserve(out.change.origins.size());
  for (std::size_t k = 0; k < out.fresh.size(); ++k)
    if (out.fresh[k] >= 0) off_surface.push_back(edit.new_vertices()[k].off_surface);
  solve_rest_positions(m, placement_.palettes[i], placed, out.change.origins, nv, rest, off_surface);
  for (std::size_t k = 0; k < out.fresh.size(); ++k)
    if (out.fresh[k] >= 0) set_placed_normal(m, placement_.palettes[i], out.fresh[k], edit.new_vertices()[k].normal);

  // Adjacency entries of untouched faces that point into the removed ones: found again below.
  std::vector<std::pair<int, int>> open_entries;
  for (const int r : removed)
    for (const int g : index.neighbor[static_cast<std::size_t>(r)])
      if (g >= 0 && !is_removed(g))
        for (int j = 0; j < 3; ++j)
          if (index.neighbor[static_cast<std::size_t>(g)][static_cast<std::size_t>(j)] == r)
            open_entries.emplace_back(g, j);
  std::sort(open_entries.begin(), open_entries.end());  // a face next to a removed one twice
  open_entries.erase(std::unique(open_entries.begin(), open_entries.end()), open_entries.end());

  // Faces: each new one into the slot of a removed face near it, or appended next to it; the
  // slots left over are filled by the last faces (largest slot first, so a face moved is never
  // one still to be removed).
  std::vector<std::array<int, 3>> faces(edit.new_faces().begin(), edit.new_faces().end());
  for (auto& t : faces)
    for (int& x : t) x = out.vertex_of(x);
  const SlotPlan plan =
      parents.empty() ? plan_slots(m, placed, removed, faces) : plan_slots_by_parent(removed, parents, rank);
  FaceSlots slots(m, placed, index);
  std::vector<int>& ids = out.change.new_faces;
  ids.assign(faces.size(), -1);
  slots.reserve_more(static_cast<int>(faces.size()) - static_cast<int>(removed.size() - plan.left_over.size()));
  for (std::size_t t = 0; t < faces.size(); ++t) {
    if (plan.slot[t] >= 0) {
      slots.put(plan.slot[t], faces[t], materials[t]);
      ids[t] = plan.slot[t];
    } else {
      ids[t] = slots.append(faces[t], plan.near[t], materials[t]);
    }
  }
  slots.erase_all(plan.left_over);
  slots.shrink();
  const std::vector<std::pair<int, int>> moves = slots.moves();
  FlatMap<int> current;
  current.reserve(moves.size());
  for (const auto& [before, after] : moves) current.try_emplace(static_cast<std::uint64_t>(before), after);
  const auto now = [&](int f) {
    const int* moved = current.find(static_cast<std::uint64_t>(f));
    return moved == nullptr ? f : *moved;
  };
  for (int& f : ids) f = now(f);
  for (const auto& [before, after] : moves)
    if (!is_removed(before)) out.change.moved_faces.push_back({before, after});
  std::sort(out.change.moved_faces.begin(), out.change.moved_faces.end());

  // The vertices are final once adjusted: then the welds, the BVH boxes, the adjacency.
  if (adjust) {
    adjust(out, m, placed);
    for (const int f : ids) index.bvh.replace(f, placed_corners(m, placed, f));
  }
  weld_new_vertices(m, out.change.origins, fresh_side, nv, index.weld);

  // Adjacency of the new faces and of the open entries: twins by welded edge.
  std::vector<std::array<int, 2>> edges;
  edges.reserve(3 * ids.size() + open_entries.size());
  for (const int f : ids)
    for (int k = 0; k < 3; ++k) edges.push_back({f, k});
  for (const auto& [g, j] : open_entries) edges.push_back({now(g), j});
  mesh::link_twins(m.faces, index.weld, edges, index.neighbor);
  return out;
}

}  // namespace cgamesh::surgery
