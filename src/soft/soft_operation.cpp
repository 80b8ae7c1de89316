#include "cgamesh/soft/soft_operation.hpp"

#include <algorithm>
#include <chrono>

namespace cgamesh::soft {

SoftOperation operate_soft(surgery::LiveModel& live, const anim::Pose& pose, const TissueOptions& options,
                           const std::function<std::vector<surgery::MeshChange>(surgery::LiveModel&)>& operation,
                           double max_seconds) {
  Tissue tissue(live, options);
  const std::vector<surgery::MeshChange> changes = operation(live);
  const auto start = std::chrono::steady_clock::now();
  tissue.follow(live, changes);
  SoftOperation out;
  out.report.settle = tissue.settle(live, pose, max_seconds);
  out.positions = tissue.positions(live, pose);
  out.model = tissue.bake(live, pose);
  out.report.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  double sum = 0;
  for (const surgery::MeshChange& c : changes) {
    const auto i = static_cast<std::size_t>(c.mesh);
    for (Eigen::Index v = c.first_new_vertex; v < live.model().meshes[i].vertex_count(); ++v) {
      const double d = (out.positions[i].row(v) - live.placement().positions[i].row(v)).norm();
      sum += d;
      out.report.max_opening = std::max(out.report.max_opening, d);
      ++out.report.wound_vertices;
    }
  }
  out.report.mean_opening = out.report.wound_vertices > 0 ? sum / out.report.wound_vertices : 0;
  return out;
}

}  // namespace cgamesh::soft
