#pragma once
// Private to surgery: triangulating the small convex polygons left when a face is cut (the
// kept part of a triangle minus a convex region), without sliver or zero-area triangles.

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::surgery::detail {

/// Triangulates a convex polygon whose boundary may hold collinear points (points on the same
/// edge of the face it was cut from) by the O(n³) dynamic programme that maximises the
/// smallest triangle quality (area over the sum of squared sides): a fan would put zero-area
/// triangles on collinear points; this finds a triangulation without any where one exists.
/// @param[in]  points  the n >= 3 corners in boundary order (coplanar, 3-D)
/// @param[out] out     n − 2 triangles of indices into `points`, with the polygon's winding,
///                     appended
void triangulate_convex(std::span<const Eigen::Vector3d> points, std::vector<std::array<int, 3>>& out);

}  // namespace cgamesh::surgery::detail
