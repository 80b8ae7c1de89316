// The steps of a tear run one at a time on small grids: the crossings of a face with a step's
// plane, the surface path along the blade, and the side groups a path vertex is split into.
#include "surgery/tearer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/surgery/surface_index.hpp"
#include "cgamesh/surgery/tear.hpp"

#include "surgery/surgery_fixtures.hpp"

namespace cgamesh::surgery::detail {

/// Runs the private steps of a Tearer alone.
struct TearerProbe {
  static StepPlane step_plane(const PathPoint& s, const Scalpel& blade) { return Tearer::step_plane(s, blade, 0); }
  static std::vector<PathPoint> crossings(const Tearer& t, int f, const StepPlane& p) { return t.crossings(f, p); }
  static const StepPlane& plane(const Tearer& t, int step) { return t.planes_[static_cast<std::size_t>(step)]; }
  static Eigen::Vector3d at(const Tearer& t, int f, const std::array<double, 3>& b) { return t.at(f, b); }
  static std::array<double, 3> bary_in(const Tearer& t, const PathPoint& p, int g) { return t.bary_in(p, g); }

  /// What duplicate() starts from: the faces the path crosses split, the fans of its vertices
  /// freed.
  static void split_faces(Tearer& t, const std::vector<PathPoint>& path) {
    t.retriangulate(path);
    t.free_fans(path);
  }

  /// The new faces around inner path point i (sorted, each once) and their side groups.
  static std::pair<std::vector<int>, std::vector<int>> groups_at(const Tearer& t, const std::vector<PathPoint>& path,
                                                                 int i) {
    const long long k = t.point_key(path, i);
    std::vector<int> faces = t.faces_by_key().at(k);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    std::vector<int> group = t.side_groups(k, faces, t.path_edges(path));
    return {std::move(faces), std::move(group)};
  }
};

}  // namespace cgamesh::surgery::detail

namespace {

using namespace cgamesh;
using namespace cgamesh_test;
using surgery::Scalpel;
using surgery::TearOptions;
using surgery::detail::PathPoint;
using surgery::detail::StepPlane;
using surgery::detail::Tearer;
using surgery::detail::TearerProbe;

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
};

/// A vertical blade over (x, y) of a grid in z = 0.
Scalpel blade_at(double x, double y) { return {{x, y, 1.0}, {x, y, -1.0}}; }

double offset(const StepPlane& p, const Eigen::Vector3d& x) { return p.n.dot(x) - p.d; }

/// The path of a stroke over a grid through the given blade positions.
std::vector<PathPoint> trace(const OneMesh& g, Tearer& t, const std::vector<Scalpel>& steps) {
  std::vector<PathPoint> entries;
  for (const Scalpel& s : steps) entries.push_back(g.entry(t, s));
  return t.trace(entries, steps);
}

// A curved surface and a slanted blade, so that Π is no plane of symmetry of the grid.
TEST(TearerSteps, CrossingsOfAFaceWithAStepPlaneLieOnThePlaneAndOnTheFaceBorder) {
  mesh::Mesh m = grid(4);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    m.positions(v, 2) = 0.1f * m.positions(v, 0) + 0.05f * m.positions(v, 1) * m.positions(v, 1);
  for (const surgery::Predicates predicates : {surgery::Predicates::cga, surgery::Predicates::euclidean}) {
    const OneMesh g(m, {.predicates = predicates});
    const Tearer t = g.tearer();
    const Scalpel next{{3.3, 0.9, 3.0}, {3.1, 1.4, -3.0}};
    const PathPoint s = g.entry(t, {{1.7, 2.2, 5.0}, {1.7, 2.2, -5.0}});
    const StepPlane plane = TearerProbe::step_plane(s, next);
    EXPECT_NEAR(plane.n.norm(), 1.0, 1e-12);
    for (const Eigen::Vector3d& x : {s.x, next.handle, next.tip}) EXPECT_NEAR(offset(plane, x), 0.0, 1e-9);
    int cut = 0;
    for (int f = 0; f < static_cast<int>(m.face_count()); ++f) {
      std::array<double, 3> corner_offset{};
      for (int k = 0; k < 3; ++k) corner_offset[static_cast<std::size_t>(k)] = offset(plane, g.vertex(m.faces(f, k)));
      const auto [lo, hi] = std::minmax_element(corner_offset.begin(), corner_offset.end());
      const std::vector<PathPoint> crossings = TearerProbe::crossings(t, f, plane);
      if (*lo > 1e-4 || *hi < -1e-4) {
        EXPECT_TRUE(crossings.empty()) << "face " << f << " lies on one side";
      }
      if (*lo < -1e-4 && *hi > 1e-4) {
        EXPECT_EQ(crossings.size(), 2u) << "Π enters and leaves face " << f;
        ++cut;
      }
      for (const PathPoint& p : crossings) {
        EXPECT_EQ(p.face, f);
        EXPECT_NEAR(offset(plane, p.x), 0.0, 1e-9) << "face " << f;
        EXPECT_NEAR(p.bary[0] + p.bary[1] + p.bary[2], 1.0, 1e-12);
        for (const double b : p.bary) EXPECT_TRUE(b >= 0 && b <= 1);
        EXPECT_LE((TearerProbe::at(t, f, p.bary) - p.x).norm(), 1e-12);
        if (p.kind == PathPoint::Kind::edge) {  // the edge's two ends lie on opposite sides of Π
          EXPECT_LT(corner_offset[static_cast<std::size_t>(p.corner)] *
                        corner_offset[static_cast<std::size_t>((p.corner + 1) % 3)],
                    0.0);
        }
      }
    }
    EXPECT_GE(cut, 4) << "Π crosses the grid";
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
      EXPECT_LE((TearerProbe::at(t, p.face, p.bary) - p.x).norm(), 1e-12) << "point " << i;
      EXPECT_NEAR(offset(TearerProbe::plane(t, p.step), p.x), 0.0, 1e-9) << "point " << i;
      if (i == 0) continue;
      const PathPoint& q = path[i - 1];
      // The segment from q to p lies in p's segment face: both ends are points of it.
      for (const PathPoint* end : {&q, &p})
        EXPECT_LE((TearerProbe::at(t, p.segment_face, TearerProbe::bary_in(t, *end, p.segment_face)) - end->x).norm(),
                  1e-12)
            << "segment " << i;
      // A point's step is that of the segment leaving it (an entry point's, the next step's).
      const Eigen::Vector3d dir = (entry(q.step + 1) - entry(q.step)).normalized();
      EXPECT_GT((p.x - q.x).dot(dir), 1e-6) << "point " << i << " is not beyond point " << i - 1;
      EXPECT_LE((p.x - q.x).cross(dir).norm(), 1e-9) << "segment " << i << " leaves the blade's line";
      length += (p.x - q.x).norm();
    }
    EXPECT_NEAR(length, straight, 1e-9);
  }
}

// Every face around a path vertex lies on one side of the (straight) path: the faces on each
// side form one group, and the two sides two different groups. One stroke crosses edges only,
// the other passes through grid vertices, whose whole fans are split.
TEST(TearerSteps, SideGroupsPutFacesOnOppositeSidesOfThePathApart) {
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
    TearerProbe::split_faces(t, path);
    for (int i = 1; i + 1 < static_cast<int>(path.size()); ++i) {
      const auto [faces, group] = TearerProbe::groups_at(t, path, i);
      ASSERT_EQ(faces.size(), group.size());
      ASSERT_GE(faces.size(), 2u);
      const StepPlane& plane = TearerProbe::plane(t, path[static_cast<std::size_t>(i)].step);
      std::map<int, int> group_of_side;  // side of Π (±1) -> the group of its faces
      for (std::size_t a = 0; a < faces.size(); ++a) {
        Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
        for (const int x : t.edit().new_faces()[static_cast<std::size_t>(faces[a])])
          centroid += x < nv ? g.vertex(x) : t.edit().new_vertices()[static_cast<std::size_t>(x - nv)].placed;
        const double side = offset(plane, centroid / 3);
        ASSERT_GT(std::abs(side), 1e-3) << "a face around point " << i << " lies on the path";
        const auto [it, added] = group_of_side.try_emplace(side > 0 ? 1 : -1, group[a]);
        EXPECT_EQ(it->second, group[a]) << "faces on one side of point " << i << " in two groups";
      }
      ASSERT_EQ(group_of_side.size(), 2u) << "faces on both sides of point " << i;
      EXPECT_NE(group_of_side[1], group_of_side[-1]) << "the two sides of point " << i << " in one group";
    }
  }
}

}  // namespace
