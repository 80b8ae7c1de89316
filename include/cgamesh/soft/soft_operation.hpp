#pragma once
// One operation with living tissue, as the CLI's --soft runs it: bind the tissue, operate in
// place, let the wound open (settle) and bake the result into a model that animates with it.

#include <functional>
#include <vector>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/row_array.hpp"
#include "cgamesh/soft/tissue.hpp"
#include "cgamesh/surgery/live_model.hpp"

namespace cgamesh::soft {

/// How far the wound opened.
struct WoundReport {
  int wound_vertices = 0;   ///< the operation's new vertices
  double mean_opening = 0;  ///< mean distance they moved from where the tool left them (model units)
  double max_opening = 0;
  SettleReport settle;
  double milliseconds = 0;  ///< binding, following, settling and baking
};

struct SoftOperation {
  anim::RiggedModel model;                      ///< Tissue::bake(): animates with the wound open
  std::vector<mesh::RowMatrixXf<3>> positions;  ///< per mesh, #V×3: the settled surface in the pose
  WoundReport report;
};

/// Binds a Tissue with `options` to `live`, runs `operation` on it (an in-place cut, tear or
/// drill returning its MeshChanges), follows the changes, settles in `pose` (at most
/// `max_seconds` of simulated time) and bakes.
/// @param[in,out] live  placed in `pose`; edited by the operation
/// @throws what the operation throws; InvalidInputError as TissueOptions::validate(); SolverError
///         when the tissue diverges.
[[nodiscard]] SoftOperation operate_soft(surgery::LiveModel& live, const anim::Pose& pose,
                                         const TissueOptions& options,
                                         const std::function<std::vector<surgery::MeshChange>(surgery::LiveModel&)>& operation,
                                         double max_seconds = 5.0);

}  // namespace cgamesh::soft
