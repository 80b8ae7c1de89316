#include "cgamesh/surgery/drill.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/errors.hpp"
#include "cgamesh/number_text.hpp"

#include "driller.hpp"
#include "surgery_common.hpp"

namespace cgamesh::surgery {
namespace {

using detail::Cylinder;
using detail::Driller;
using detail::make_cylinder;

/// Per mesh, the faces near enough to the finite cylinder to meet it (a superset of those the
/// drill meets, found around its axis, not in the box of a slanted drill, which can hold much of
/// the model): the drill's candidates, in every mesh, whether its axis pierces them or not.
std::vector<std::vector<int>> candidate_faces(const SurfaceIndex& index, const Cylinder& c) {
  const Eigen::Vector3d tip = c.base + c.length * c.axis;
  // The finite cylinder lies within its radius of the axis segment; the tree's boxes are floats.
  const double radius = c.radius + 1e-6 * (c.length + 2 * c.radius);
  std::vector<std::vector<int>> out(index.meshes.size());
  for (std::size_t i = 0; i < index.meshes.size(); ++i)
    index.meshes[i].bvh.faces_near_segment(c.base, tip, radius, out[i]);
  return out;
}

/// The nearest distance along the drill's axis, beyond the tip (`ahead`) or behind the base,
/// at which the axis line meets a face of some mesh; infinity when it meets none.
double axis_hit(const Placement& placement, const SurfaceIndex& index, const Cylinder& c, bool ahead) {
  double radius = 0;  // of a ball about the origin holding every placed vertex
  for (const auto& p : placement.positions)
    if (p.rows() > 0) radius = std::max(radius, static_cast<double>(p.rowwise().norm().maxCoeff()));
  const Eigen::Vector3d from = ahead ? Eigen::Vector3d(c.base + c.length * c.axis) : c.base;
  const Eigen::Vector3d dir = ahead ? c.axis : Eigen::Vector3d(-c.axis);
  const double far = 2 * (from.norm() + radius) + 1;  // beyond every vertex
  double best = std::numeric_limits<double>::infinity();
  for (const auto& m : index.meshes) {
    const auto hits = m.bvh.segment_hits(from, from + far * dir);
    if (!hits.empty()) best = std::min(best, hits.front().t * far);
  }
  return best;
}

/// @throws TopologyError when the drill meets no face of any mesh; the message says when it
///         stops short of the surface (its axis meets it beyond the tip) or points away from it.
void require_hit(const DrillStats& stats, const Placement& placement, const SurfaceIndex& index, const Cylinder& c) {
  if (stats.faces_affected != 0) return;
  const double ahead = axis_hit(placement, index, c, true);
  if (std::isfinite(ahead))
    throw TopologyError("drill: the drill stops short of the surface: its axis meets the model " + number_text(ahead) +
                        " beyond the tip (move the tip further along the axis)");
  const double behind = axis_hit(placement, index, c, false);
  if (std::isfinite(behind))
    throw TopologyError("drill: the drill points away from the model: its axis meets the surface " +
                        number_text(behind) + " behind the base (swap --tip and --base, or move them)");
  throw TopologyError("drill: the drill misses the model (no face meets the cylinder between its base and tip)");
}

/// @throws InvalidInputError for a tip, base or radius far beyond the model (kMaxToolReach).
void require_in_reach(const SurfaceIndex& index, const Eigen::Vector3d& tip, const Eigen::Vector3d& base,
                      double radius) {
  const PlacedBox box = placed_box(index);
  surgery::require_in_reach(box, tip, "drill: the tip");
  surgery::require_in_reach(box, base, "drill: the base");
  require_size_in_reach(box, radius, "drill: the radius");
}

/// Whether an edit changes its mesh: a face that a disk inside it left as it was is re-emitted
/// unchanged, with no new vertex.
bool changes(const LocalEdit& edit) {
  return !edit.new_vertices().empty() || edit.new_faces().size() != edit.removed_faces().size();
}

/// @throws TopologyError when none of the edits changes its mesh.
void require_change(const std::vector<bool>& changed, const DrillStats& stats) {
  if (std::find(changed.begin(), changed.end(), true) != changed.end()) return;
  throw TopologyError("drill: the drill changes nothing" +
                      (stats.warnings.empty() ? std::string() : " (" + stats.warnings.front() + ")"));
}

int blended_count(const std::vector<mesh::VertexSource>& origins) {
  return static_cast<int>(
      std::count_if(origins.begin(), origins.end(), [](const mesh::VertexSource& o) { return o.count() > 1; }));
}

}  // namespace

ModelDrill drill(const anim::RiggedModel& model, const Placement& placement, const SurfaceIndex& index,
                 const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius, const DrillOptions& options) {
  require_placement_fits(model, placement);
  const Cylinder c = make_cylinder(tip, base, radius, options);
  require_index_fits(model, index, "drill");
  require_in_reach(index, tip, base, radius);
  const auto candidates = candidate_faces(index, c);
  ModelDrill out;
  std::vector<LocalEdit> edits(model.meshes.size());
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    out.faces_in += static_cast<int>(model.meshes[i].face_count());
    if (!candidates[i].empty())
      Driller(model.meshes[i], placement.positions[i], index.meshes[i], c, options).run(candidates[i], edits[i], out);
  }
  require_hit(out, placement, index, c);
  std::vector<bool> changed(edits.size());
  std::transform(edits.begin(), edits.end(), changed.begin(), changes);
  require_change(changed, out);
  copy_rig(model, out.model);
  const int cut_surface = std::any_of(edits.begin(), edits.end(), has_cut_surface)
                              ? mesh::cut_surface_material_index(out.model.materials)
                              : -1;
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    if (edits[i].removed_faces().empty()) {  // not reached: copied as it is
      out.model.meshes.push_back(m);
      out.source_mesh.push_back(static_cast<int>(i));
      std::vector<mesh::VertexSource> identity(static_cast<std::size_t>(m.vertex_count()));
      for (std::size_t v = 0; v < identity.size(); ++v) identity[v] = mesh::VertexSource::copy(static_cast<int>(v));
      out.origins.push_back(std::move(identity));
      out.placed.push_back(placement.positions[i]);
      out.faces_out += static_cast<int>(m.face_count());
      continue;
    }
    out.faces_removed += static_cast<int>(edits[i].removed_faces().size());
    EditedMesh e = apply_edit(m, placement.positions[i], placement.palettes[i], edits[i], options.rest, cut_surface);
    out.new_vertices += blended_count(e.origins);
    if (e.mesh.face_count() == 0) {
      out.warnings.push_back("mesh '" + m.name + "' is drilled away entirely");
      continue;
    }
    out.faces_out += static_cast<int>(e.mesh.face_count());
    out.model.meshes.push_back(std::move(e.mesh));
    out.source_mesh.push_back(static_cast<int>(i));
    out.origins.push_back(std::move(e.origins));
    out.placed.push_back(std::move(e.placed));
  }
  bound_warnings(out.warnings);
  return out;
}

LiveDrill drill(LiveModel& live, const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius,
                const DrillOptions& options) {
  const Cylinder c = make_cylinder(tip, base, radius, options);
  require_in_reach(live.index(), tip, base, radius);
  const auto candidates = candidate_faces(live.index(), c);
  const anim::RiggedModel& model = live.model();
  LiveDrill out;
  // Every edit is made before any is applied, so that a throw leaves `live` as it was.
  std::vector<LocalEdit> edits(model.meshes.size());
  out.faces_in = face_total(model);
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    if (candidates[i].empty()) continue;
    Driller(model.meshes[i], live.placement().positions[i], live.index().meshes[i], c, options)
        .run(candidates[i], edits[i], out);
    out.faces_removed += static_cast<int>(edits[i].removed_faces().size());
  }
  require_hit(out, live.placement(), live.index(), c);
  std::vector<bool> changed(edits.size());
  std::transform(edits.begin(), edits.end(), changed.begin(), changes);
  require_change(changed, out);
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    if (edits[i].removed_faces().empty()) continue;
    AppliedEdit applied = live.apply(i, edits[i], options.rest);
    out.new_vertices += blended_count(applied.change.origins);
    if (model.meshes[i].face_count() == 0)
      out.warnings.push_back("mesh '" + model.meshes[i].name + "' is drilled away entirely");
    out.changes.push_back(std::move(applied.change));
  }
  out.faces_out = face_total(model);
  bound_warnings(out.warnings);
  return out;
}

ModelDrill drill(const anim::RiggedModel& model, const Placement& placement, const Eigen::Vector3d& tip,
                 const Eigen::Vector3d& base, double radius, const DrillOptions& options) {
  return drill(model, placement, SurfaceIndex::build(model, placement), tip, base, radius, options);
}

}  // namespace cgamesh::surgery
