#pragma once
// What a cut, tear or drill reports, as the CLI's --json, Python's `stats` and the C ABI's
// cgamesh_change_json give it: one set of keys for every front end.

#include <string>

#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/tear.hpp"

namespace cgamesh::io {

/// The counts of a cut as a JSON object's text: new_vertices, intersection_points, faces_in,
/// faces_split, cap_triangles. Faces out and warnings are the caller's to add (a cut in two
/// has two face counts, one in place one; warnings go with the caller's own).
[[nodiscard]] std::string stats_json(const surgery::CutStats& stats);
/// The same for a tear: new_vertices, intersection_points, faces_in, faces_out, faces_split and
/// the path (#P × [x, y, z], placed coordinates).
[[nodiscard]] std::string stats_json(const surgery::TearStats& stats);
/// The same for a drill: new_vertices, intersection_points, faces_in, faces_out, faces_removed,
/// faces_affected, refinements, rims, walls, open_rims, wall_triangles.
[[nodiscard]] std::string stats_json(const surgery::DrillStats& stats);

}  // namespace cgamesh::io
