// Cap triangulation of cross-section loops (src/surgery/polygon_triangulation.hpp).
#include "surgery/polygon_triangulation.hpp"

#include <array>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

namespace {

using cgamesh::surgery::detail::triangulate_loops;

double area(const std::vector<Eigen::Vector2d>& p, const std::vector<std::array<int, 3>>& triangles) {
  double a = 0;
  for (const auto& t : triangles) {
    const Eigen::Vector2d u = p[static_cast<std::size_t>(t[1])] - p[static_cast<std::size_t>(t[0])];
    const Eigen::Vector2d v = p[static_cast<std::size_t>(t[2])] - p[static_cast<std::size_t>(t[0])];
    a += 0.5 * (u.x() * v.y() - u.y() * v.x());
  }
  return a;
}

TEST(PolygonTriangulation, ASquareWithAHoleCoversItsArea) {
  const std::vector<Eigen::Vector2d> p{{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {2, 1}, {2, 2}, {1, 2}};
  const std::vector<std::array<int, 2>> e{{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
  EXPECT_NEAR(area(p, triangulate_loops(p, e)), 15.0, 1e-12);
}

// A section of Debian's LWO2/box_2vc_1unused.lwo has two points at one place joined by an edge;
// CGAL crashed on the constraint from a vertex to itself.
TEST(PolygonTriangulation, AZeroLengthEdgeBetweenTwoPointsAtOnePlaceIsNoConstraint) {
  const std::vector<Eigen::Vector2d> p{{0, 0}, {1, 0}, {1, 0}, {1, 1}, {0, 1}};
  const std::vector<std::array<int, 2>> e{{0, 1}, {1, 2}, {2, 3}, {3, 4}, {4, 0}};
  const auto triangles = triangulate_loops(p, e);
  EXPECT_EQ(triangles.size(), 2u);
  EXPECT_NEAR(area(p, triangles), 1.0, 1e-12);
}

TEST(PolygonTriangulation, CrossingLoopsAreATopologyError) {
  const std::vector<Eigen::Vector2d> p{{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}, {3, 1}, {3, 3}, {1, 3}};
  const std::vector<std::array<int, 2>> e{{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
  EXPECT_THROW((void)triangulate_loops(p, e), cgamesh::TopologyError);
}

}  // namespace
