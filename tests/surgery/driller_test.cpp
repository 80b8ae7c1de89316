// The drill's steps one at a time (src/surgery/driller.hpp): the probe of a point, the cut of an
// edge by the cylinder and the end disks, the analysis of a grid into kept polygons and a rim,
// and one round of red-green refinement.
#include "surgery/driller.hpp"

#include <cmath>
#include <numbers>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;
using namespace cgamesh_test;
using surgery::detail::Driller;
using surgery::detail::EdgeCut;
using surgery::detail::Vertex;
using V3 = Eigen::Vector3d;

/// A point of the region at `p`, not from the mesh, with its own welded id.
int add_point(Driller& d, const Eigen::Vector3d& p, int weld) {
  Vertex v;
  v.placed = p;
  v.weld = weld;
  return d.add_vertex(v);
}

/// A Driller over a flat n×n grid, with everything it refers to.
struct GridDrill {
  anim::RiggedModel model;
  surgery::Placement placement;
  surgery::SurfaceIndex index;
  surgery::DrillOptions options;
  surgery::detail::Cylinder cylinder;
  Driller driller;

  GridDrill(int n, const V3& tip, const V3& base, double radius, const surgery::DrillOptions& drill_options = {})
      : model(static_model(grid(n))),
        placement(rest_placement(model)),
        index(surgery::SurfaceIndex::build(model, placement)),
        options(drill_options),
        cylinder(surgery::detail::make_cylinder(tip, base, radius, options)),
        driller(model.meshes[0], placement.positions[0], index.meshes[0], cylinder, options) {}
};

/// Distance of x from the z-parallel axis through (cx, cy).
double from_axis(const V3& x, double cx, double cy) { return std::hypot(x.x() - cx, x.y() - cy); }

TEST(Driller, ProbeGivesRhoSquaredMinusRSquaredAndTheHeight) {
  // A tilted axis far from the origin; u is perpendicular to it.
  const V3 base(10, -20, 5), axis = V3(1, 2, 2) / 3, tip = base + 3 * axis, u = V3(2, -1, 0) / std::sqrt(5.0);
  for (const surgery::Predicates predicates : {surgery::Predicates::cga, surgery::Predicates::euclidean}) {
    surgery::DrillOptions options;
    options.predicates = predicates;
    GridDrill g(2, tip, base, 0.5, options);
    const Vertex outside =
        g.driller.vertex(add_point(g.driller, base + 1.5 * axis + 0.9 * u, 100));
    EXPECT_NEAR(outside.s, 0.9 * 0.9 - 0.5 * 0.5, 1e-12);
    EXPECT_NEAR(outside.h, 1.5, 1e-12);
    const Vertex below =
        g.driller.vertex(add_point(g.driller, base - 0.7 * axis + 0.2 * u, 101));
    EXPECT_NEAR(below.s, 0.2 * 0.2 - 0.5 * 0.5, 1e-12);
    EXPECT_NEAR(below.h, -0.7, 1e-12);
    // On the cylinder and in the tip's plane: snapped to exactly 0 and |AB|.
    const Vertex on = g.driller.vertex(add_point(g.driller, base + 3 * axis + 0.5 * u, 102));
    EXPECT_EQ(on.s, 0.0);
    EXPECT_EQ(on.h, g.cylinder.length);
  }
}

TEST(Driller, EdgeCutFindsTheCylinderAndEndDiskCrossingsOnTheEdge) {
  // The unit cylinder about the z axis, from z = −1 (h = 0) to z = 1 (h = 2).
  GridDrill g(2, V3(0, 0, 1), V3(0, 0, -1), 1.0);
  int next_weld = 100;
  struct Cut {
    V3 a, b;
    EdgeCut e;
    [[nodiscard]] V3 at(int k) const {
      const double t = e.alpha[static_cast<std::size_t>(k)];
      return (1 - t) * a + t * b;
    }
  };
  // The ends get increasing welded ids, so that the cut runs from a to b.
  const auto cut = [&](const V3& a, const V3& b) {
    const int x = add_point(g.driller, a, next_weld++),
              y = add_point(g.driller, b, next_weld++);
    const int i = g.driller.edge_cut(x, y);
    EXPECT_EQ(g.driller.edge_cut(y, x), i) << "one cut per edge, whichever way round";
    return Cut{a, b, g.driller.cut(i)};
  };

  const Cut miss = cut(V3(-2, 1.5, 0), V3(2, 1.5, 0));
  EXPECT_EQ(miss.e.roots, 0);
  EXPECT_FALSE(miss.e.any_inside);

  const Cut enter = cut(V3(0.2, 0.1, 0), V3(3, 0.1, 0));
  ASSERT_EQ(enter.e.roots, 1);
  EXPECT_NEAR(enter.e.alpha[0], (std::sqrt(0.99) - 0.2) / 2.8, 1e-9);
  EXPECT_NEAR(from_axis(enter.at(0), 0, 0), 1.0, 1e-9);
  EXPECT_EQ(enter.e.level[0], -1.0);
  EXPECT_TRUE(enter.e.inside[0]);
  EXPECT_FALSE(enter.e.inside[1]);

  const Cut through = cut(V3(-2, 0.6, 0), V3(2, 0.6, 0));
  ASSERT_EQ(through.e.roots, 2);
  EXPECT_NEAR(through.e.alpha[0], 0.3, 1e-9);
  EXPECT_NEAR(through.e.alpha[1], 0.7, 1e-9);
  EXPECT_FALSE(through.e.inside[0]);
  EXPECT_TRUE(through.e.inside[1]);
  EXPECT_FALSE(through.e.inside[2]);

  const Cut slanted = cut(V3(-2, -0.3, -0.5), V3(2, 0.5, 0.5));
  ASSERT_EQ(slanted.e.roots, 2);
  for (int k = 0; k < 2; ++k) EXPECT_NEAR(from_axis(slanted.at(k), 0, 0), 1.0, 1e-9) << "point " << k;
  EXPECT_LT(slanted.e.alpha[0], slanted.e.alpha[1]);
  EXPECT_TRUE(slanted.e.inside[1]);

  // Across the tip's plane inside the radius: one point, on the tip's disk.
  const Cut tip = cut(V3(0.3, 0.2, 0.5), V3(0.3, 0.2, 1.5));
  ASSERT_EQ(tip.e.roots, 1);
  EXPECT_NEAR(tip.e.alpha[0], 0.5, 1e-9);
  EXPECT_EQ(tip.e.level[0], 2.0);
  EXPECT_NEAR(tip.at(0).z(), 1.0, 1e-9);
  EXPECT_TRUE(tip.e.inside[0]);
  EXPECT_FALSE(tip.e.inside[1]);

  // Across the base's plane: inside above it.
  const Cut bottom = cut(V3(0.1, 0.1, -1.5), V3(0.1, 0.1, -0.5));
  ASSERT_EQ(bottom.e.roots, 1);
  EXPECT_EQ(bottom.e.level[0], 0.0);
  EXPECT_NEAR(bottom.at(0).z(), -1.0, 1e-9);
  EXPECT_FALSE(bottom.e.inside[0]);
  EXPECT_TRUE(bottom.e.inside[1]);

  // Across the tip's plane beside the cylinder: the point bounds nothing and goes.
  const Cut beside = cut(V3(1.5, 0, 0.5), V3(1.5, 0, 1.5));
  EXPECT_EQ(beside.e.roots, 0);
  EXPECT_FALSE(beside.e.any_inside);
}

TEST(Driller, AnalysisOfAGridKeepsWhatIsOutsideAndFindsOneClosedRimOnTheCylinder) {
  const double cx = 5.3, cy = 4.6, r = 1.7;
  GridDrill g(10, V3(cx, cy, 1), V3(cx, cy, -1), r);
  std::vector<int> faces(200);
  std::iota(faces.begin(), faces.end(), 0);
  const surgery::detail::Pass pass = g.driller.analyse(g.driller.slots_of(faces));
  ASSERT_FALSE(pass.affected.empty());
  EXPECT_EQ(pass.disks_inside, 0);
  EXPECT_EQ(pass.coarse_arcs, 0);
  const auto point = [&](int x) { return g.driller.vertex(x).placed; };
  for (const int x : pass.corners) EXPECT_GE(g.driller.vertex(x).s, 0.0) << "a kept corner in the hole";

  const std::vector<surgery::detail::Rim> rims = g.driller.find_rims(pass);
  ASSERT_EQ(rims.size(), 1u);
  const surgery::detail::Rim& rim = rims[0];
  EXPECT_TRUE(rim.closed);
  EXPECT_GE(rim.chords.size(), 8u);
  double winding = 0, hole = 0;
  for (std::size_t i = 0; i < rim.chords.size(); ++i) {
    const surgery::detail::Chord& c = pass.chords[static_cast<std::size_t>(rim.chords[i])];
    const surgery::detail::Chord& next = pass.chords[static_cast<std::size_t>(rim.chords[(i + 1) % rim.chords.size()])];
    EXPECT_EQ(g.driller.vertex(c.e).weld, g.driller.vertex(next.p).weld)
        << "chord " << i << " does not lead to the next";
    EXPECT_NEAR(from_axis(point(c.p), cx, cy), r, 1e-9) << "chord " << i;
    const V3 p = point(c.p) - V3(cx, cy, 0), e = point(c.e) - V3(cx, cy, 0);
    winding += std::atan2(p.x() * e.y() - p.y() * e.x(), p.x() * e.x() + p.y() * e.y());
    hole += 0.5 * (p.x() * e.y() - p.y() * e.x());
  }
  EXPECT_NEAR(std::abs(winding), 2 * std::numbers::pi, 1e-9);
  // What is kept and the hole (the polygon inscribed in the circle) make up the affected faces.
  double kept = 0;
  for (const auto& [slot, first, count] : pass.polygons)
    for (int k = 0; k < count; ++k) {
      const V3 p = point(pass.corners[static_cast<std::size_t>(first + k)]),
               q = point(pass.corners[static_cast<std::size_t>(first + (k + 1) % count)]);
      kept += 0.5 * (p.x() * q.y() - p.y() * q.x());
    }
  EXPECT_NEAR(kept + std::abs(hole), 0.5 * static_cast<double>(pass.affected.size()), 1e-9);
  EXPECT_LT(std::abs(hole), std::numbers::pi * r * r);
}

TEST(Driller, RefineSplitsARedFaceIntoFourAndItsNeighbourIntoTwoAtTheSameMidpoint) {
  GridDrill g(1, V3(0.3, 0.3, 1), V3(0.3, 0.3, -1), 0.1);
  g.driller.refine(g.driller.slots_of({0}));
  // Four corners and three midpoints: the green face is split at the red one's midpoint.
  EXPECT_EQ(g.driller.vertex_count(), 7);
  int red = 0, green = 0;
  double area = 0;
  for (const surgery::detail::Face& f : g.driller.faces()) {
    if (!f.alive) continue;
    EXPECT_FALSE(f.original);
    const V3 a = g.driller.vertex(f.v[0]).placed, b = g.driller.vertex(f.v[1]).placed,
             c = g.driller.vertex(f.v[2]).placed;
    const double z = 0.5 * (b - a).cross(c - a).z();
    EXPECT_GT(z, 0.1) << "flipped or sliver";
    area += z;
    (f.origin == 0 ? red : green) += 1;
  }
  EXPECT_EQ(red, 4);
  EXPECT_EQ(green, 2);
  EXPECT_NEAR(area, 1.0, 1e-12);
}

}  // namespace
