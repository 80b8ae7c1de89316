#include "cgamesh/surgery/tear.hpp"

#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cgamesh/errors.hpp"

#include "surgery_common.hpp"
#include "tearer.hpp"

namespace cgamesh::surgery {
namespace {

using detail::PathPoint;
using detail::Tearer;

/// Checks the input, finds the torn mesh (the one the blade enters first at t₀; later steps
/// must enter it too) and traces the path; then returns finish(tearer, torn mesh, path).
template <class Finish>
auto trace_tear(const anim::RiggedModel& model, const Placement& placement, const SurfaceIndex& index,
                std::span<const Scalpel> scalpel, const TearOptions& options, const Finish& finish) {
  if (scalpel.size() < 2)
    throw InvalidInputError("tear: the scalpel needs at least 2 time steps, got " + std::to_string(scalpel.size()));
  if (!(options.open >= 0) || !std::isfinite(options.open))
    throw InvalidInputError("tear: the opening width must be a finite number >= 0");
  const PlacedBox box = placed_box(index);
  for (std::size_t i = 0; i < scalpel.size(); ++i) {
    if (!scalpel[i].handle.allFinite() || !scalpel[i].tip.allFinite())
      throw InvalidInputError("tear: scalpel step " + std::to_string(i) + " holds NaN or infinity");
    if (scalpel[i].handle == scalpel[i].tip)
      throw InvalidInputError("tear: scalpel step " + std::to_string(i) +
                              " has handle == tip (a blade of zero length)");
    require_in_reach(box, scalpel[i].handle, "tear: the handle of scalpel step " + std::to_string(i));
    require_in_reach(box, scalpel[i].tip, "tear: the tip of scalpel step " + std::to_string(i));
  }
  const auto first_hit = [&](std::size_t m, const Scalpel& s) {
    const auto hits = index.meshes[m].bvh.segment_hits(s.handle, s.tip);
    return hits.empty() ? mesh::SegmentHit{} : hits.front();
  };
  int torn = -1;
  mesh::SegmentHit start;
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const mesh::SegmentHit h = first_hit(m, scalpel[0]);
    if (h.face >= 0 && (torn < 0 || h.t < start.t)) {
      start = h;
      torn = static_cast<int>(m);
    }
  }
  if (torn < 0) throw TopologyError("tear: the scalpel at step 0 does not meet the surface");
  const auto tm = static_cast<std::size_t>(torn);
  Tearer tearer(model.meshes[tm], placement.positions[tm], placement.palettes[tm], index.meshes[tm], options);
  std::vector<PathPoint> entries{tearer.entry(start)};
  for (std::size_t i = 1; i < scalpel.size(); ++i) {
    const mesh::SegmentHit h = first_hit(tm, scalpel[i]);
    if (h.face < 0)
      throw TopologyError("tear: the scalpel at step " + std::to_string(i) + " does not meet the surface of mesh '" +
                          model.meshes[tm].name + "'");
    entries.push_back(tearer.entry(h));
  }
  const std::vector<PathPoint> path = tearer.trace(entries, scalpel);
  if (path.size() < 2) throw TopologyError("tear: the scalpel does not move over the surface: nothing to tear");
  return finish(tearer, tm, path);
}

/// The statistics both forms report, but faces_out and new_vertices.
void record(TearStats& out, const anim::RiggedModel& model, const std::vector<PathPoint>& path, int faces_split) {
  for (const PathPoint& p : path) out.path.push_back(p.x);
  out.intersection_points = static_cast<int>(path.size());
  out.faces_in = face_total(model);
  out.faces_split = faces_split;
}

}  // namespace

ModelTear tear(const anim::RiggedModel& model, const Placement& placement, const SurfaceIndex& index,
               std::span<const Scalpel> scalpel, const TearOptions& options) {
  require_placement_fits(model, placement);
  require_index_fits(model, index, "tear");
  return trace_tear(
      model, placement, index, scalpel, options,
      [&](Tearer& tearer, std::size_t tm, const std::vector<PathPoint>& path) {
        ModelTear out;
        out.mesh = static_cast<int>(tm);
        record(out, model, path, tearer.prepare(path));
        EditedMesh edited =
            apply_edit(model.meshes[tm], placement.positions[tm], placement.palettes[tm], tearer.edit(), options.rest);
        const auto vertex_of = [&](int x) { return edited.vertex_of[static_cast<std::size_t>(x)]; };
        tearer.move_apart(path, edited.mesh, edited.placed, vertex_of);
        out.side.assign(static_cast<std::size_t>(edited.mesh.vertex_count()), 0);
        tearer.for_each_copy(vertex_of, [&](int v, signed char side) { out.side[static_cast<std::size_t>(v)] = side; });
        out.new_vertices = static_cast<int>(edited.mesh.vertex_count() - model.meshes[tm].vertex_count());
        // Everything but the torn mesh is copied as it is.
        copy_rig(model, out.model);
        for (std::size_t m = 0; m < model.meshes.size(); ++m)
          out.model.meshes.push_back(m == tm ? std::move(edited.mesh) : model.meshes[m]);
        out.origins = std::move(edited.origins);
        out.placed = std::move(edited.placed);
        out.faces_out = face_total(out.model);
        return out;
      });
}

LiveTear tear(LiveModel& live, std::span<const Scalpel> scalpel, const TearOptions& options) {
  return trace_tear(live.model(), live.placement(), live.index(), scalpel, options,
                    [&](Tearer& tearer, std::size_t tm, const std::vector<PathPoint>& path) {
                      LiveTear out;
                      record(out, live.model(), path, tearer.prepare(path));
                      AppliedEdit applied =
                          live.apply(tm, tearer.edit(), options.rest,
                                     [&](const AppliedEdit& a, mesh::Mesh& m, mesh::RowMatrixXf<3>& placed) {
                                       tearer.move_apart(path, m, placed, [&](int x) { return a.vertex_of(x); });
                                     });
                      tearer.for_each_copy([&](int x) { return applied.vertex_of(x); },
                                           [&](int v, signed char side) { out.sides.emplace_back(v, side); });
                      out.new_vertices = static_cast<int>(applied.change.origins.size());
                      out.faces_out = face_total(live.model());
                      out.change = std::move(applied.change);
                      return out;
                    });
}

ModelTear tear(const anim::RiggedModel& model, const Placement& placement, std::span<const Scalpel> scalpel,
               const TearOptions& options) {
  return tear(model, placement, SurfaceIndex::build(model, placement), scalpel, options);
}

}  // namespace cgamesh::surgery
