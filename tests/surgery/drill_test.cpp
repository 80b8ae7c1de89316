// Drilling (Algorithm 3): hand-checked holes in a grid and a box, refinement of a drill smaller
// than the faces, degenerate and bad drills, and hundreds of random drills through real models
// with every invariant of a drill checked on every result.
#include "cgamesh/surgery/drill.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/subdivide.hpp"
#include "cgamesh/mesh/triangle_bvh.hpp"

#include "surgery/surgery_checks.hpp"
#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;
using namespace cgamesh_test;
using surgery::DrillOptions;
using surgery::kMaxRefinements;
using surgery::kMaxRimPoints;
using surgery::ModelDrill;
using V3 = Eigen::Vector3d;

/// Distance of x from the axis through `base` along `tip − base`.
double axis_distance(const V3& x, const V3& tip, const V3& base) {
  const V3 n = (tip - base).normalized(), d = x - base;
  return (d - n.dot(d) * n).norm();
}

V3 row(const Points& p, Eigen::Index v) { return p.row(v).cast<double>().transpose(); }

/// Whether x lies inside the finite cylinder of radius r from `base` to `tip`.
bool in_drill(const V3& x, const V3& tip, const V3& base, double r) {
  const V3 n = (tip - base).normalized();
  const double h = n.dot(x - base);
  return h > 0 && h < (tip - base).norm() && axis_distance(x, tip, base) < r;
}

/// Vertex ids of a drilled mesh welded through their origins (weld_points).
std::vector<int> weld_points(const ModelDrill& d, std::size_t k, const anim::RiggedModel& before) {
  return cgamesh_test::weld_points(d.origins[k],
                                   weld(before.meshes[static_cast<std::size_t>(d.source_mesh[k])].positions));
}

/// The boundary edges of a drilled mesh (welded through origins) with both ends on the
/// cylinder: the rims.
std::vector<std::pair<int, int>> rim_edges(const ModelDrill& d, std::size_t k, const anim::RiggedModel& before,
                                           const V3& tip, const V3& base, double radius, double tol) {
  const auto w = weld_points(d, k, before);
  std::vector<std::pair<int, int>> out;
  for (const auto& [a, b] : boundary_edges(d.model.meshes[k].faces, w))
    if (std::abs(axis_distance(row(d.placed[k], a), tip, base) - radius) <= tol &&
        std::abs(axis_distance(row(d.placed[k], b), tip, base) - radius) <= tol)
      out.emplace_back(a, b);
  return out;
}

/// Number of closed loops of a set of directed edges in which every vertex has one edge out.
int loop_count(const std::vector<std::pair<int, int>>& edges) {
  std::map<int, int> next;
  for (const auto& [a, b] : edges) next[a] = b;
  std::set<int> seen;
  int loops = 0;
  for (const auto& [a, b] : next) {
    if (seen.contains(a)) continue;
    ++loops;
    for (int v = a; !seen.contains(v) && next.contains(v); v = next[v]) seen.insert(v);
  }
  return loops;
}

// ---- hand-checked cases ------------------------------------------------------------------------

TEST(Drill, GridHoleIsOneLoopOnTheCylinderWithTheInscribedArea) {
  const anim::RiggedModel model = static_model(grid(10));
  const V3 base(5.3, 4.6, -1), tip(5.3, 4.6, 1);
  const double r = 1.7;
  const ModelDrill d = surgery::drill(model, rest_placement(model), tip, base, r);
  ASSERT_EQ(d.model.meshes.size(), 1u);
  EXPECT_EQ(d.rims, 1);
  EXPECT_EQ(d.refinements, 0);
  EXPECT_TRUE(d.warnings.empty());
  EXPECT_GT(d.intersection_points, 8);
  const mesh::Mesh& m = d.model.meshes[0];
  expect_sane_mesh(m, "grid");
  const auto rim = rim_edges(d, 0, model, tip, base, r, 1e-5);
  EXPECT_TRUE(boundary_is_loops(rim));
  EXPECT_EQ(loop_count(rim), 1);
  EXPECT_GE(static_cast<int>(rim.size()), 8);
  // The rim is a polygon inscribed in the circle, and exactly what was removed.
  double rim_area = 0;
  for (const auto& [a, b] : rim) rim_area += 0.5 * row(d.placed[0], a).cross(row(d.placed[0], b)).z();
  rim_area = std::abs(rim_area);
  const double removed = 100 - area(m.faces, d.placed[0]);
  EXPECT_NEAR(removed, rim_area, 1e-4);
  EXPECT_LE(removed, std::numbers::pi * r * r);
  EXPECT_GE(removed, 0.8 * std::numbers::pi * r * r);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    EXPECT_GE(axis_distance(row(d.placed[0], v), tip, base), r - 1e-5) << "vertex " << v << " left inside the hole";
  // Every new vertex is on an old edge, on the circle.
  for (const mesh::VertexSource& o : d.origins[0])
    if (o.count() > 1) {
      EXPECT_EQ(o.count(), 2);
    }
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const V3 a = row(d.placed[0], m.faces(f, 0)), b = row(d.placed[0], m.faces(f, 1)),
             c = row(d.placed[0], m.faces(f, 2));
    EXPECT_GT((b - a).cross(c - a).z(), 1e-6) << "face " << f << ": flipped or degenerate";
  }
}

mesh::Mesh fine_box() { return mesh::subdivide_midpoint(mesh::subdivide_midpoint(cube())); }

TEST(Drill, BoxDrilledThroughWithAWallIsClosedAndWithoutItHasTwoRims) {
  const anim::RiggedModel model = static_model(fine_box());
  const auto placement = rest_placement(model);
  const V3 base(0.45, 0.55, -0.5), tip(0.45, 0.55, 1.5);
  const double r = 0.3;
  const ModelDrill open = surgery::drill(model, placement, tip, base, r);
  EXPECT_EQ(open.rims, 2);
  const auto rim = rim_edges(open, 0, model, tip, base, r, 1e-5);
  EXPECT_EQ(loop_count(rim), 2);
  const auto w = weld_points(open, 0, model);
  EXPECT_EQ(boundary_edges(open.model.meshes[0].faces, w).size(), rim.size()) << "every boundary edge is a rim edge";

  DrillOptions wall;
  wall.wall = true;
  const ModelDrill closed = surgery::drill(model, placement, tip, base, r, wall);
  EXPECT_TRUE(closed.warnings.empty()) << closed.warnings.front();
  EXPECT_GT(closed.wall_triangles, 0);
  EXPECT_EQ(closed.intersection_points, open.intersection_points);
  const mesh::Mesh& m = closed.model.meshes[0];
  expect_sane_mesh(m, "box");
  EXPECT_TRUE(closed_and_oriented(m.faces, weld_points(closed, 0, model)));
  const double v = volume(m.faces, closed.placed[0]);
  EXPECT_LT(v, 1 - 0.8 * std::numbers::pi * r * r);
  EXPECT_GT(v, 1 - std::numbers::pi * r * r);

  // The wall has vertices of its own, whose normals are the wall's (the box's would shade it
  // black where they point away from the wall's winding).
  anim::RiggedModel with_normals = model;
  mesh::Mesh& b = with_normals.meshes[0];
  b.normals = (b.positions.rowwise() - Eigen::RowVector3f(0.5f, 0.5f, 0.5f)).rowwise().normalized();
  const ModelDrill shaded = surgery::drill(with_normals, rest_placement(with_normals), tip, base, r, wall);
  const mesh::Mesh& s = shaded.model.meshes[0];
  ASSERT_GT(shaded.wall_triangles, 0);
  double worst = 1;
  for (Eigen::Index f = s.face_count() - shaded.wall_triangles; f < s.face_count(); ++f) {
    const V3 a = row(shaded.placed[0], s.faces(f, 0)), p = row(shaded.placed[0], s.faces(f, 1)),
             c = row(shaded.placed[0], s.faces(f, 2));
    const V3 n = (p - a).cross(c - a).normalized();
    EXPECT_LT(std::abs(n.dot((tip - base).normalized())), 0.2) << "a wall face along the axis";
    for (int k = 0; k < 3; ++k) worst = std::min(worst, n.dot(s.normals.row(s.faces(f, k)).cast<double>().transpose()));
  }
  EXPECT_GT(worst, 0.8);

  // A drill stopping inside the box leaves its one rim open, with a warning.
  const ModelDrill blind = surgery::drill(model, placement, V3(0.45, 0.55, 0.5), base, r, wall);
  EXPECT_EQ(blind.rims, 1);
  EXPECT_EQ(blind.wall_triangles, 0);
  EXPECT_EQ(blind.warnings.size(), 1u);
}

TEST(Drill, ADrillSmallerThanTheFacesRefinesUntilTheRimHasEnoughPoints) {
  const anim::RiggedModel model = static_model(grid(4));
  const V3 base(1.3, 1.6, -1), tip(1.3, 1.6, 1);
  const double r = 0.06;
  DrillOptions opt;
  const ModelDrill d = surgery::drill(model, rest_placement(model), tip, base, r, opt);
  EXPECT_GT(d.refinements, 2);
  EXPECT_TRUE(d.warnings.empty());
  EXPECT_EQ(d.rims, 1);
  const auto rim = rim_edges(d, 0, model, tip, base, r, 1e-5);
  EXPECT_EQ(loop_count(rim), 1);
  EXPECT_GE(static_cast<int>(rim.size()), opt.min_rim_points);
  expect_sane_mesh(d.model.meshes[0], "grid");
  // Red-green refinement leaves no T-junction: the only boundaries are the grid's and the rim.
  const auto w = weld_points(d, 0, model);
  EXPECT_EQ(boundary_edges(d.model.meshes[0].faces, w).size(), rim.size() + 16);
  for (Eigen::Index v = 0; v < d.model.meshes[0].vertex_count(); ++v)
    EXPECT_GE(axis_distance(row(d.placed[0], v), tip, base), r - 1e-5);

  // Without refinements the disk inside one face makes no hole: a drill that changes nothing
  // is an error, in place too (and leaves the model as it was).
  opt.max_refinements = 0;
  EXPECT_THROW((void)surgery::drill(model, rest_placement(model), tip, base, r, opt), TopologyError);
  surgery::LiveModel live(model, rest_placement(model));
  EXPECT_THROW((void)surgery::drill(live, tip, base, r, opt), TopologyError);
  EXPECT_EQ(live.model().meshes[0].faces, model.meshes[0].faces);
}

// The work budget stops refinement before the region passes it, with a warning; the result is
// still a (coarser) hole.
TEST(Drill, RefinementStaysWithinItsBudget) {
  const anim::RiggedModel model = static_model(grid(4));
  const V3 base(1.3, 1.6, -1), tip(1.3, 1.6, 1);
  DrillOptions opt;
  opt.min_rim_points = kMaxRimPoints;
  opt.max_refinements = kMaxRefinements;
  opt.max_region_faces = 400;
  const ModelDrill d = surgery::drill(model, rest_placement(model), tip, base, 0.3, opt);
  EXPECT_LE(d.faces_out, 32 + 400);
  ASSERT_FALSE(d.warnings.empty());
  EXPECT_NE(d.warnings.front().find("max_region_faces"), std::string::npos) << d.warnings.front();
  EXPECT_EQ(d.rims, 1);
}

// Axes through a corner of a cube (along its diagonal) or along one of its edges hit it.
TEST(Drill, AxisThroughACubeCornerOrAlongAnEdgeIsAHit) {
  const anim::RiggedModel model = static_model(cube());
  const auto placement = rest_placement(model);
  const V3 corner(1, 1, 1), diagonal = V3(1, 1, 1).normalized();
  const V3 tip = corner - 0.3 * diagonal, base = corner + 0.5 * diagonal;
  const ModelDrill d = surgery::drill(model, placement, tip, base, 0.2);
  EXPECT_GT(d.faces_removed, 0);
  EXPECT_GT(d.new_vertices, 0);
  EXPECT_EQ(d.rims, 1);
  for (Eigen::Index v = 0; v < d.model.meshes[0].vertex_count(); ++v)
    EXPECT_FALSE(in_drill(row(d.placed[0], v), tip, base, 0.2 - 1e-5)) << row(d.placed[0], v).transpose();
  const ModelDrill e = surgery::drill(model, placement, V3(1, 0, 1.5), V3(1, 0, -0.5), 0.25);
  EXPECT_GT(e.faces_removed, 0);
  for (Eigen::Index v = 0; v < e.model.meshes[0].vertex_count(); ++v)
    EXPECT_FALSE(in_drill(row(e.placed[0], v), V3(1, 0, 1.5), V3(1, 0, -0.5), 0.25 - 1e-5));
}

TEST(Drill, AxisThroughAnEdgeOrAVertex) {
  const anim::RiggedModel model = static_model(grid(6));
  const auto placement = rest_placement(model);
  for (const V3& at : {V3(2, 2.5, 0), V3(3, 3, 0), V3(2.5, 2.5, 0)}) {
    const V3 base = at - V3(0, 0, 1), tip = at + V3(0, 0, 1);
    const ModelDrill d = surgery::drill(model, placement, tip, base, 0.8);
    SCOPED_TRACE(at.transpose());
    EXPECT_EQ(d.rims, 1);
    const auto rim = rim_edges(d, 0, model, tip, base, 0.8, 1e-5);
    EXPECT_EQ(loop_count(rim), 1);
    const double removed = 36 - area(d.model.meshes[0].faces, d.placed[0]);
    EXPECT_LE(removed, std::numbers::pi * 0.64);
    EXPECT_GE(removed, 0.8 * std::numbers::pi * 0.64);
  }
}

TEST(Drill, MissOrBadDrillIsAnError) {
  const anim::RiggedModel model = static_model(grid(3));
  const auto placement = rest_placement(model);
  const V3 base(1.5, 1.5, -1), tip(1.5, 1.5, 1);
  EXPECT_THROW((void)surgery::drill(model, placement, V3(9, 9, 1), V3(9, 9, -1), 0.5), TopologyError);
  EXPECT_THROW((void)surgery::drill(model, placement, V3(1.5, 1.5, -0.5), base, 0.5), TopologyError)
      << "the tip stops before the surface";
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, 0.0), InvalidInputError);
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, -1.0), InvalidInputError);
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, std::nan("")), InvalidInputError);
  EXPECT_THROW((void)surgery::drill(model, placement, base, base, 0.5), InvalidInputError);
  EXPECT_THROW((void)surgery::drill(model, placement, V3(std::nan(""), 0, 0), base, 0.5), InvalidInputError);
  DrillOptions bad;
  bad.min_rim_points = 2;
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, 0.5, bad), InvalidInputError);
  bad.min_rim_points = kMaxRimPoints + 1;
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, 0.5, bad), InvalidInputError);
  bad = {};
  bad.max_refinements = kMaxRefinements + 1;
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, 0.5, bad), InvalidInputError);
  bad.max_refinements = -1;
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, 0.5, bad), InvalidInputError);
  bad = {};
  bad.max_region_faces = 0;
  EXPECT_THROW((void)surgery::drill(model, placement, tip, base, 0.5, bad), InvalidInputError);
  const surgery::SurfaceIndex other =
      surgery::SurfaceIndex::build(static_model(cube()), rest_placement(static_model(cube())));
  EXPECT_THROW((void)surgery::drill(model, placement, other, tip, base, 0.5), InvalidInputError);
}

TEST(Drill, ADrillWiderThanTheModelRemovesIt) {
  const anim::RiggedModel model = static_model(grid(2));
  const ModelDrill d = surgery::drill(model, rest_placement(model), V3(1, 1, 1), V3(1, 1, -1), 5);
  EXPECT_TRUE(d.model.meshes.empty());
  EXPECT_EQ(d.faces_out, 0);
  EXPECT_EQ(d.warnings.size(), 1u);
}

// ---- properties on real models -----------------------------------------------------------------

/// Old welded vertices strictly inside the cylinder that the drill must remove: those joined by
/// edges inside the cylinder to a face the axis pierces (an independent flood fill).
std::set<int> must_go(const mesh::Mesh& old, const Points& placed, const std::vector<int>& w, const V3& tip,
                      const V3& base, double r, double tol) {
  const mesh::TriangleBvh bvh(placed, old.faces);
  const auto inside = [&](int v) { return axis_distance(row(placed, v), tip, base) < r - tol; };
  std::map<int, std::vector<int>> adjacent;  // welded, between inside vertices
  for (Eigen::Index f = 0; f < old.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = old.faces(f, k), b = old.faces(f, (k + 1) % 3);
      if (inside(a) && inside(b)) {
        adjacent[w[static_cast<std::size_t>(a)]].push_back(w[static_cast<std::size_t>(b)]);
        adjacent[w[static_cast<std::size_t>(b)]].push_back(w[static_cast<std::size_t>(a)]);
      }
    }
  std::set<int> out;
  std::vector<int> stack;
  for (const auto& hit : bvh.segment_hits(base, tip))
    for (int k = 0; k < 3; ++k)
      if (inside(old.faces(hit.face, k))) stack.push_back(w[static_cast<std::size_t>(old.faces(hit.face, k))]);
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    if (!out.insert(v).second) continue;
    for (int u : adjacent[v]) stack.push_back(u);
  }
  return out;
}

/// Every invariant of one drill of `s`.
void check_drill(const Subject& s, const surgery::SurfaceIndex& index, const V3& tip, const V3& base, double r,
                 const DrillOptions& opt) {
  const double diag = model_diagonal(s);
  const double tol = 1e-5 * diag;
  const ModelDrill d = surgery::drill(s.model, s.placement, index, tip, base, r, opt);
  ASSERT_EQ(d.model.meshes.size(), d.origins.size());
  ASSERT_EQ(d.model.meshes.size(), d.placed.size());
  int faces_out = 0;
  for (std::size_t k = 0; k < d.model.meshes.size(); ++k) {
    const mesh::Mesh& m = d.model.meshes[k];
    const auto src = static_cast<std::size_t>(d.source_mesh[k]);
    const mesh::Mesh& old = s.model.meshes[src];
    const Points& placed = d.placed[k];
    const auto& origins = d.origins[k];
    const std::string what = s.name + " mesh " + m.name;
    faces_out += static_cast<int>(m.face_count());
    expect_sane_mesh(m, what);
    ASSERT_EQ(placed.rows(), m.vertex_count());
    const auto old_weld = weld(old.positions);
    const auto w = weld_points(d, k, s.model);
    const std::set<int> gone = must_go(old, s.placement.positions[src], old_weld, tip, base, r, tol);
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
      const mesh::VertexSource& o = origins[static_cast<std::size_t>(v)];
      if (o.count() == 1) {
        ASSERT_FALSE(gone.contains(old_weld[static_cast<std::size_t>(o.vertex[0])]))
            << what << ": vertex left in the hole";
      } else {
        ASSERT_GE(axis_distance(row(placed, v), tip, base), r - tol) << what << ": a new vertex inside the drill";
      }
    }
    // New boundary edges are rim chords on the cylinder, or pieces of old boundary edges.
    std::set<std::pair<int, int>> old_boundary;
    for (const auto& [a, b] : boundary_edges(old.faces, old_weld))
      old_boundary.insert({std::min(a, b), std::max(a, b)});
    const auto on_old_boundary = [&](int a, int b) {
      std::set<int> ends;
      for (int v : {a, b})
        for (int j = 0; j < origins[static_cast<std::size_t>(v)].count(); ++j)
          ends.insert(old_weld[static_cast<std::size_t>(
              origins[static_cast<std::size_t>(v)].vertex[static_cast<std::size_t>(j)])]);
      return ends.size() == 2 && old_boundary.contains({*ends.begin(), *ends.rbegin()});
    };
    const auto boundary = boundary_edges(m.faces, w);
    for (const auto& [a, b] : boundary) {
      const bool rim = std::abs(axis_distance(row(placed, a), tip, base) - r) <= tol &&
                       std::abs(axis_distance(row(placed, b), tip, base) - r) <= tol;
      ASSERT_TRUE(rim || on_old_boundary(a, b)) << what << ": a new boundary edge off the cylinder";
    }
    if (s.closed) {
      EXPECT_TRUE(boundary_is_loops(boundary)) << what << ": the rims are not closed loops";
      const bool unpaired = std::any_of(d.warnings.begin(), d.warnings.end(),
                                        [](const std::string& x) { return x.find("no partner") != std::string::npos; });
      if (opt.wall && !unpaired) {
        EXPECT_TRUE(closed_and_oriented(m.faces, w)) << what << ": not closed with the wall";
      }
    }
    if (!opt.wall) {
      EXPECT_LE(area(m.faces, placed), area(old.faces, s.placement.positions[src]) * (1 + 1e-6)) << what;
    }
    expect_reanimates_like(s.model, src, d.model, k, origins, 1e-6 * diag);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_EQ(faces_out, d.faces_out);
  EXPECT_GE(d.rims, 1);

  // The other predicates give the same drill.
  DrillOptions other = opt;
  other.predicates =
      opt.predicates == surgery::Predicates::cga ? surgery::Predicates::euclidean : surgery::Predicates::cga;
  const ModelDrill e = surgery::drill(s.model, s.placement, index, tip, base, r, other);
  ASSERT_EQ(e.faces_out, d.faces_out);
  ASSERT_EQ(e.intersection_points, d.intersection_points);
  ASSERT_EQ(e.refinements, d.refinements);
  for (std::size_t k = 0; k < d.model.meshes.size(); ++k)
    EXPECT_LE((e.placed[k] - d.placed[k]).cwiseAbs().maxCoeff(), 1e-6 * diag);
}

class DrillProperties : public ::testing::TestWithParam<int> {};

TEST_P(DrillProperties, RandomDrillsThroughThePlacedSurface) {
  const Subject& s = subjects()[static_cast<std::size_t>(GetParam())];
  const surgery::SurfaceIndex index = surgery::SurfaceIndex::build(s.model, s.placement);
  std::mt19937 rng(4321 + GetParam());
  const double diag = model_diagonal(s);
  std::uniform_real_distribution<double> u(0, 1);
  std::uniform_int_distribution<std::size_t> pick_mesh(0, s.model.meshes.size() - 1);
  const int cases = 10 * kCaseScale;
  for (int i = 0; i < cases; ++i) {
    // Through a point inside a random face, in a random direction, from outside the model;
    // the tip beyond it, or (one case in five) just past the surface.
    const std::size_t k = pick_mesh(rng);
    const auto& faces = s.model.meshes[k].faces;
    const Points& p = s.placement.positions[k];
    const Eigen::Index f = std::uniform_int_distribution<Eigen::Index>(0, faces.rows() - 1)(rng);
    double b0 = 0.1 + 0.8 * u(rng), b1 = (1 - b0) * (0.1 + 0.8 * u(rng));
    const V3 at = b0 * row(p, faces(f, 0)) + b1 * row(p, faces(f, 1)) + (1 - b0 - b1) * row(p, faces(f, 2));
    const V3 n = random_direction(rng);
    const V3 base = at - diag * n;
    const V3 tip = at + (i % 5 == 4 ? 0.01 : 1.0) * diag * n;
    DrillOptions opt;
    opt.wall = i % 2 == 1;
    opt.predicates = i % 3 == 0 ? surgery::Predicates::euclidean : surgery::Predicates::cga;
    const double r = diag * (0.002 + 0.03 * u(rng));
    SCOPED_TRACE(s.name + " drill " + std::to_string(i) + " r=" + std::to_string(r));
    check_drill(s, index, tip, base, r, opt);
    if (HasFatalFailure()) return;
  }
}

INSTANTIATE_TEST_SUITE_P(Models, DrillProperties, ::testing::Values(0, 1, 2, 3),
                         [](const auto& info) { return subjects()[static_cast<std::size_t>(info.param)].name; });

}  // namespace
