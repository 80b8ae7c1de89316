// A Tearer's steps on small grids, through its interface: the surface path along the blade (its
// crossings of the faces with the step's plane) and the copies a path vertex is split into.
#include "surgery/tearer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/surgery/surface_index.hpp"
#include "cgamesh/surgery/tear.hpp"

#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;
using namespace cgamesh_test;
using surgery::Scalpel;
using surgery::TearOptions;
using surgery::detail::PathPoint;
using surgery::detail::Tearer;

/// One static mesh at rest with its index: what a Tearer refers to, kept alive for it.
struct OneMesh {
  anim::RiggedModel model;
  surgery::Placement placement;
  surgery::SurfaceIndex index;
  TearOptions options;

  explicit OneMesh(mesh::Mesh m, TearOptions o = {})
      : model(static_model(std::move(m))),
        placement(rest_placement(model)),
        index(surgery::SurfaceIndex::build(model, placement)),
        options(o) {}

  [[nodiscard]] Tearer tearer() const {
    return Tearer(model.meshes[0], placement.positions[0], placement.palettes[0], index.meshes[0], options);
  }

  /// Where the blade first meets the surface.
  [[nodiscard]] PathPoint entry(const Tearer& t, const Scalpel& s) const {
    const auto hits = index.meshes[0].bvh.segment_hits(s.handle, s.tip);
    if (hits.empty()) throw std::logic_error("the blade misses the mesh");
    return t.entry(hits.front());
  }

  [[nodiscard]] Eigen::Vector3d vertex(int v) const { return placement.positions[0].row(v).cast<double>().transpose(); }

  /// The point of face f at barycentric coordinates b.
  [[nodiscard]] Eigen::Vector3d at(int f, const std::array<double, 3>& b) const {
    const mesh::Faces& faces = model.meshes[0].faces;
    return b[0] * vertex(faces(f, 0)) + b[1] * vertex(faces(f, 1)) + b[2] * vertex(faces(f, 2));
  }

  /// The distance of x from the plane of face f, and how far outside the face its projection
  /// falls (0: inside), by its barycentric coordinates there.
  [[nodiscard]] std::pair<double, double> off_face(int f, const Eigen::Vector3d& x) const {
    const mesh::Faces& faces = model.meshes[0].faces;
    const Eigen::Vector3d a = vertex(faces(f, 0)), u = vertex(faces(f, 1)) - a, v = vertex(faces(f, 2)) - a;
    const Eigen::Vector3d n = u.cross(v).normalized();
    const Eigen::Vector2d uv = (Eigen::Matrix<double, 3, 2>() << u, v).finished().colPivHouseholderQr().solve(x - a);
    const double outside = std::max({0.0, -uv[0], -uv[1], uv[0] + uv[1] - 1});
    return {std::abs(n.dot(x - a)), outside};
  }
};

/// A vertical blade over (x, y) of a grid in z = 0.
Scalpel blade_at(double x, double y) { return {{x, y, 1.0}, {x, y, -1.0}}; }

/// Π of a step: the plane through its entry point and the next blade, as (unit n, d).
struct StepPlane {
  Eigen::Vector3d n;
  double d = 0;
};

StepPlane step_plane(const Eigen::Vector3d& entry, const Scalpel& next) {
  const Eigen::Vector3d n = (next.handle - entry).cross(next.tip - entry).normalized();
  return {n, n.dot(entry)};
}

double offset(const StepPlane& p, const Eigen::Vector3d& x) { return p.n.dot(x) - p.d; }

/// The path of a stroke over a grid through the given blade positions.
std::vector<PathPoint> trace(const OneMesh& g, Tearer& t, const std::vector<Scalpel>& steps) {
  std::vector<PathPoint> entries;
  for (const Scalpel& s : steps) entries.push_back(g.entry(t, s));
  return t.trace(entries, steps);
}

// A curved surface and a slanted blade, so that Π is no plane of symmetry of the grid: the
// path's points between the two entry points are crossings of face borders with Π.
TEST(TearerSteps, CrossingsOfTheFacesWithAStepPlaneLieOnThePlaneAndOnTheFaceBorders) {
  mesh::Mesh m = grid(4);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    m.positions(v, 2) = 0.1f * m.positions(v, 0) + 0.05f * m.positions(v, 1) * m.positions(v, 1);
  for (const surgery::Predicates predicates : {surgery::Predicates::cga, surgery::Predicates::euclidean}) {
    const OneMesh g(m, {.predicates = predicates});
    Tearer t = g.tearer();
    const std::vector<Scalpel> steps{{{1.7, 2.2, 5.0}, {1.7, 2.2, -5.0}}, {{3.3, 0.9, 3.0}, {3.1, 1.4, -3.0}}};
    const std::vector<PathPoint> path = trace(g, t, steps);
    ASSERT_GE(path.size(), 4u) << "Π crosses the grid";
    const StepPlane plane = step_plane(path.front().x, steps[1]);
    for (std::size_t i = 0; i < path.size(); ++i) {
      const PathPoint& p = path[i];
      const int f = p.face;
      ASSERT_GE(f, 0);
      EXPECT_NEAR(offset(plane, p.x), 0.0, 1e-9) << "point " << i;
      EXPECT_NEAR(p.bary[0] + p.bary[1] + p.bary[2], 1.0, 1e-12);
      for (const double b : p.bary) EXPECT_TRUE(b >= 0 && b <= 1);
      EXPECT_LE((g.at(f, p.bary) - p.x).norm(), 1e-12) << "point " << i;
      if (i == 0 || i + 1 == path.size()) continue;  // the entry points
      EXPECT_NE(p.kind, PathPoint::Kind::face) << "point " << i << " is no crossing of a face border";
      if (p.kind == PathPoint::Kind::edge) {  // the edge's two ends lie on opposite sides of Π
        const auto corner_offset = [&](int k) { return offset(plane, g.vertex(m.faces(f, k % 3))); };
        EXPECT_LT(corner_offset(p.corner) * corner_offset(p.corner + 1), 0.0) << "point " << i;
      }
    }
  }
}

// On a flat grid the surface path along Π from one entry point to the next is the straight
// segment between them: its points come in order along it, each in the faces it names. The
// second stroke passes through grid vertices.
TEST(TearerSteps, TracedPathRunsInOrderAlongTheBladeThroughTheFacesItNames) {
  const OneMesh g(grid(6));
  for (const std::vector<Scalpel>& steps :
       {std::vector<Scalpel>{blade_at(0.6, 0.7), blade_at(2.3, 2.1), blade_at(3.8, 2.4), blade_at(5.2, 4.6)},
        std::vector<Scalpel>{blade_at(0.8, 0.6), blade_at(2.3, 3.6), blade_at(5.3, 5.1)}}) {
    Tearer t = g.tearer();
    const std::vector<PathPoint> path = trace(g, t, steps);
    ASSERT_GT(path.size(), steps.size() + 4);
    const auto entry = [&](int i) {
      const Scalpel& s = steps[static_cast<std::size_t>(i)];
      return Eigen::Vector3d(s.tip.x(), s.tip.y(), 0.0);
    };
    EXPECT_LE((path.front().x - entry(0)).norm(), 1e-9);
    EXPECT_LE((path.back().x - entry(static_cast<int>(steps.size()) - 1)).norm(), 1e-9);
    double length = 0, straight = 0;
    for (int s = 1; s < static_cast<int>(steps.size()); ++s) straight += (entry(s) - entry(s - 1)).norm();
    for (std::size_t i = 0; i < path.size(); ++i) {
      const PathPoint& p = path[i];
      ASSERT_GE(p.face, 0);
      EXPECT_NEAR(p.bary[0] + p.bary[1] + p.bary[2], 1.0, 1e-12);
      for (const double b : p.bary) EXPECT_TRUE(b >= 0 && b <= 1);
      EXPECT_LE((g.at(p.face, p.bary) - p.x).norm(), 1e-12) << "point " << i;
      const StepPlane plane = step_plane(entry(p.step), steps[static_cast<std::size_t>(p.step) + 1]);
      EXPECT_NEAR(offset(plane, p.x), 0.0, 1e-9) << "point " << i;
      if (i == 0) continue;
      const PathPoint& q = path[i - 1];
      // The segment from q to p lies in p's segment face: both ends are points of it.
      for (const PathPoint* end : {&q, &p}) {
        const auto [distance, outside] = g.off_face(p.segment_face, end->x);
        EXPECT_LE(distance, 1e-12) << "segment " << i;
        EXPECT_LE(outside, 1e-12) << "segment " << i;
      }
      // A point's step is that of the segment leaving it (an entry point's, the next step's).
      const Eigen::Vector3d dir = (entry(q.step + 1) - entry(q.step)).normalized();
      EXPECT_GT((p.x - q.x).dot(dir), 1e-6) << "point " << i << " is not beyond point " << i - 1;
      EXPECT_LE((p.x - q.x).cross(dir).norm(), 1e-9) << "segment " << i << " leaves the blade's line";
      length += (p.x - q.x).norm();
    }
    EXPECT_NEAR(length, straight, 1e-9);
  }
}

// Every face around an inner path vertex lies on one side of the (straight) path: prepare()
// gives the faces on each side one copy of the vertex, and the two sides different copies. One
// stroke crosses edges only, the other passes through grid vertices, whose whole fans are split.
TEST(TearerSteps, PrepareGivesTheFacesOnEachSideOfThePathTheirOwnCopyOfAPathVertex) {
  const OneMesh g(grid(4));
  const mesh::Mesh& m = g.model.meshes[0];
  const int nv = static_cast<int>(m.vertex_count());
  struct Stroke {
    Scalpel from, to;
    bool through_vertices;
  };
  for (const Stroke& stroke :
       {Stroke{blade_at(0.7, 1.3), blade_at(3.4, 2.2), false}, Stroke{blade_at(0.8, 0.6), blade_at(2.3, 3.6), true}}) {
    Tearer t = g.tearer();
    const std::vector<PathPoint> path = trace(g, t, {stroke.from, stroke.to});
    ASSERT_GE(path.size(), 4u);
    EXPECT_EQ(std::any_of(path.begin() + 1, path.end() - 1,
                          [](const PathPoint& p) { return p.kind == PathPoint::Kind::vertex; }),
              stroke.through_vertices);
    t.prepare(path);
    const surgery::LocalEdit& edit = t.edit();
    const auto position = [&](int x) {
      return x < nv ? g.vertex(x) : edit.new_vertices()[static_cast<std::size_t>(x - nv)].placed;
    };
    const StepPlane plane = step_plane(path.front().x, stroke.to);
    for (int i = 1; i + 1 < static_cast<int>(path.size()); ++i) {
      const Eigen::Vector3d& point = path[static_cast<std::size_t>(i)].x;
      std::map<int, std::set<int>> copies_on_side;  // side of Π (±1) -> the ids of the point there
      for (const std::array<int, 3>& face : edit.new_faces())
        for (const int x : face) {
          if ((position(x) - point).norm() > 1e-12) continue;
          const Eigen::Vector3d centroid = (position(face[0]) + position(face[1]) + position(face[2])) / 3;
          const double side = offset(plane, centroid);
          ASSERT_GT(std::abs(side), 1e-3) << "a face around point " << i << " lies on the path";
          copies_on_side[side > 0 ? 1 : -1].insert(x);
        }
      ASSERT_EQ(copies_on_side.size(), 2u) << "faces on both sides of point " << i;
      ASSERT_EQ(copies_on_side[1].size(), 1u) << "faces on one side of point " << i << " with two copies";
      ASSERT_EQ(copies_on_side[-1].size(), 1u) << "faces on one side of point " << i << " with two copies";
      EXPECT_NE(*copies_on_side[1].begin(), *copies_on_side[-1].begin())
          << "the two sides of point " << i << " share a copy";
    }
  }
}

}  // namespace
