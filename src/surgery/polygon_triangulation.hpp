#pragma once
// Private to surgery: triangulating planar regions bounded by closed loops (caps and walls).

#include <array>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace cgamesh::surgery::detail {

/// Triangulates the region enclosed by `edges` (closed loops, possibly nested: holes inside
/// outer loops, islands inside holes) with a constrained Delaunay triangulation (CGAL). A
/// point is inside when a ray from it crosses the loops an odd number of times.
/// @param[in] points  2-D coordinates of the loop vertices
/// @param[in] edges   boundary segments as pairs of indices into `points`
/// @return counter-clockwise triangles of indices into `points`
/// Points at the same place are merged (the triangles use the first index).
/// @throws TopologyError when loops cross each other.
[[nodiscard]] std::vector<std::array<int, 3>> triangulate_loops(std::span<const Eigen::Vector2d> points,
                                                                std::span<const std::array<int, 2>> edges);

/// The loops that can be triangulated together, triangulated as triangulate_loops() does: a
/// loop that crosses itself is left out, and so are two loops that cross each other (loops
/// are the connected components of `edges`).
/// @param[out] left_out  the number of loops left out
/// @throws TopologyError only where triangulate_loops() fails on loops that triangulate alone
///         and pairwise (not seen).
[[nodiscard]] std::vector<std::array<int, 3>> triangulate_loops_that_can_be(std::span<const Eigen::Vector2d> points,
                                                                            std::span<const std::array<int, 2>> edges,
                                                                            int& left_out);

/// Constrained Delaunay triangulation of `points` with `segments` as edges (CGAL): every
/// triangle of their convex hull, counter-clockwise. Points at the same place are merged (the
/// triangles use the first index).
/// @throws TopologyError when two segments cross.
[[nodiscard]] std::vector<std::array<int, 3>> triangulate_constrained(std::span<const Eigen::Vector2d> points,
                                                                      std::span<const std::array<int, 2>> segments);

}  // namespace cgamesh::surgery::detail
