// Tearing (Algorithm 2): hand-checked tears of a flat grid and a cube, degenerate scalpels, and
// hundreds of random scalpel strokes over real models with every invariant checked.
#include "cgamesh/surgery/tear.hpp"

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/surgery/live_model.hpp"

#include "surgery/surgery_checks.hpp"
#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;
using namespace cgamesh_test;
using surgery::ModelTear;
using surgery::Scalpel;
using surgery::TearOptions;

/// A vertical blade over (x, y) of the grid (the grid lies in z = 0).
Scalpel blade_at(double x, double y) { return {{x, y, 1.0}, {x, y, -1.0}}; }

/// Vertex ids of a torn mesh welded through their origins, so seam copies count as one, while
/// the copies on the two sides of the tear stay two.
std::vector<int> weld_torn(const mesh::Mesh& old, const ModelTear& t) {
  const auto w = weld_points(t.origins, weld_by_position(old.positions));
  std::map<std::pair<int, int>, int> first;
  std::vector<int> out(w.size());
  for (std::size_t v = 0; v < w.size(); ++v)
    out[v] = first.try_emplace({w[v], t.side[v]}, static_cast<int>(v)).first->second;
  return out;
}

/// Boundary edges of the result that were not boundary edges of the input.
std::vector<std::pair<int, int>> new_boundary(const mesh::Mesh& old, const ModelTear& t) {
  const auto old_weld = weld_by_position(old.positions);
  const auto w = weld_torn(old, t);
  std::set<std::pair<int, int>> before;
  for (const auto& e : boundary_edges(old.faces, old_weld)) before.insert(e);
  std::vector<std::pair<int, int>> out;
  for (const auto& [a, b] : boundary_edges(t.model.meshes[static_cast<std::size_t>(t.mesh)].faces, w)) {
    const auto& oa = t.origins[static_cast<std::size_t>(a)];
    const auto& ob = t.origins[static_cast<std::size_t>(b)];
    const bool old_edge = oa.count() == 1 && ob.count() == 1 &&
                          before.contains({old_weld[static_cast<std::size_t>(oa.vertex[0])],
                                           old_weld[static_cast<std::size_t>(ob.vertex[0])]});
    if (!old_edge) out.emplace_back(a, b);
  }
  return out;
}

/// Distance of a point from the polyline of the tear path.
double distance_to_path(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& x) {
  double best = INFINITY;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector3d a = path[i - 1], ab = path[i] - a;
    const double t = ab.squaredNorm() > 0 ? std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (a + t * ab - x).norm());
  }
  return best;
}

// ---- hand-checked cases ------------------------------------------------------------------------

TEST(Tear, OneStrokeAcrossAGridOpensASlit) {
  const anim::RiggedModel model = static_model(grid(4));
  const std::vector<Scalpel> steps{blade_at(0.7, 1.3), blade_at(3.4, 2.2)};
  const ModelTear t = surgery::tear(model, rest_placement(model), steps);
  const mesh::Mesh& m = t.model.meshes[0];
  expect_sane_mesh(m, "grid");
  // The path starts and ends at the blade's entry points, in the grid's plane.
  ASSERT_GE(t.path.size(), 3u);
  EXPECT_LE((t.path.front() - Eigen::Vector3d(0.7, 1.3, 0)).norm(), 1e-9);
  EXPECT_LE((t.path.back() - Eigen::Vector3d(3.4, 2.2, 0)).norm(), 1e-9);
  // Geometry unchanged without opening: the same area, every vertex where it was.
  EXPECT_NEAR(area(m.faces, m.positions), 16.0, 1e-5);
  // The new boundary is one closed loop: along the path on one side and back on the other.
  const auto boundary = new_boundary(model.meshes[0], t);
  EXPECT_TRUE(boundary_is_loops(boundary));
  EXPECT_EQ(boundary.size(), 2 * (t.path.size() - 1));
  for (const auto& [a, b] : boundary) {
    EXPECT_LE(distance_to_path(t.path, m.positions.row(a).cast<double>().transpose()), 1e-5);
    EXPECT_LE(distance_to_path(t.path, m.positions.row(b).cast<double>().transpose()), 1e-5);
  }
  // Every path point but the two ends is there twice.
  EXPECT_EQ(t.new_vertices, static_cast<int>(t.path.size() - 2) * 2 + 2);
  EXPECT_EQ(t.intersection_points, static_cast<int>(t.path.size()));
  EXPECT_GT(t.faces_split, 0);
}

TEST(Tear, OpeningMovesTheCopiesApartAlongThePlaneNormal) {
  const anim::RiggedModel model = static_model(grid(4));
  // A stroke along x at y = 2.5: Π is the plane y = 2.5, its normal ±y.
  const std::vector<Scalpel> steps{blade_at(0.5, 2.5), blade_at(3.5, 2.5)};
  TearOptions opt;
  opt.open = 0.2;
  const ModelTear t = surgery::tear(model, rest_placement(model), steps, opt);
  const mesh::Mesh& m = t.model.meshes[0];
  double widest = 0;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const auto& o = t.origins[static_cast<std::size_t>(v)];
    if (o.count() == 1) {
      EXPECT_EQ(m.positions.row(v), model.meshes[0].positions.row(o.vertex[0])) << "an old vertex moved";
      continue;
    }
    const double off = std::abs(m.positions(v, 1) - 2.5);
    EXPECT_LE(off, 0.1 + 1e-6);
    EXPECT_NEAR(m.positions(v, 2), 0.0, 1e-6) << "moved off the surface's plane";
    widest = std::max(widest, off);
  }
  EXPECT_GT(widest, 0.09) << "the middle of the tear opens by about the full width";
  EXPECT_NEAR(area(m.faces, m.positions), 16.0 - 0.2 * 3 * 2 / 3.14159265, 0.05) << "the opening is a lens";
}

TEST(Tear, ProgressiveStepsContinueOneTear) {
  const anim::RiggedModel model = static_model(grid(6));
  const std::vector<Scalpel> steps{blade_at(0.6, 0.7), blade_at(2.3, 2.1), blade_at(3.8, 2.4), blade_at(5.2, 4.6)};
  const ModelTear t = surgery::tear(model, rest_placement(model), steps);
  const auto boundary = new_boundary(model.meshes[0], t);
  EXPECT_TRUE(boundary_is_loops(boundary));
  EXPECT_EQ(boundary.size(), 2 * (t.path.size() - 1)) << "one slit, not one per step";
  // The intermediate entry points are on the path.
  for (const Scalpel& s : steps) EXPECT_LE(distance_to_path(t.path, {s.tip.x(), s.tip.y(), 0}), 1e-9);
}

TEST(Tear, StrokeAlongGridLinesSplitsAtVerticesWithoutSlivers) {
  const anim::RiggedModel model = static_model(grid(4));
  // Along y = 2 from vertex (1, 2) to vertex (3, 2): the path runs along existing edges.
  const ModelTear t = surgery::tear(model, rest_placement(model), std::vector<Scalpel>{blade_at(1, 2), blade_at(3, 2)});
  const mesh::Mesh& m = t.model.meshes[0];
  EXPECT_EQ(t.path.size(), 3u);  // (1,2), (2,2), (3,2)
  EXPECT_EQ(t.new_vertices, 1);  // (2,2) twice
  EXPECT_EQ(m.face_count(), 32);
  for (Eigen::Index f = 0; f < m.face_count(); ++f) {
    const Eigen::Vector3f a = m.positions.row(m.faces(f, 0)), b = m.positions.row(m.faces(f, 1)),
                          c = m.positions.row(m.faces(f, 2));
    EXPECT_GT((b - a).cross(c - a).norm(), 1e-3) << "sliver face " << f;
  }
}

TEST(Tear, ThroughACubeEdgeAndAroundACorner) {
  const anim::RiggedModel model = static_model(cube());
  // On the top face, then over the edge y = 1 down the side.
  const std::vector<Scalpel> steps{{{0.3, 0.4, 2}, {0.3, 0.4, 0.5}}, {{0.6, 2, 0.6}, {0.6, 0.5, 0.6}}};
  const ModelTear t = surgery::tear(model, rest_placement(model), steps);
  const mesh::Mesh& m = t.model.meshes[0];
  expect_sane_mesh(m, "cube");
  EXPECT_NEAR(area(m.faces, m.positions), 6.0, 1e-5);
  const auto boundary = new_boundary(model.meshes[0], t);
  EXPECT_TRUE(boundary_is_loops(boundary));
  EXPECT_FALSE(closed_and_oriented(m.faces, weld_torn(model.meshes[0], t)));
  EXPECT_TRUE(closed_and_oriented(m.faces, weld_origins(t.origins, weld_by_position(model.meshes[0].positions))))
      << "closed again when the two sides are welded back together";
}

// ---- degenerate and bad input -------------------------------------------------------------------

/// `m` with no vertex shared between faces (#V = 3 #F), as some .x and .smd files are.
mesh::Mesh unshared(const mesh::Mesh& m) {
  mesh::Mesh out;
  out.name = m.name + " (unshared)";
  out.positions.resize(3 * m.face_count(), 3);
  out.faces.resize(m.face_count(), 3);
  for (Eigen::Index f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      out.positions.row(3 * f + k) = m.positions.row(m.faces(f, k));
      out.faces(f, k) = static_cast<int>(3 * f + k);
    }
  return out;
}

// Faces that share no vertices are one surface where their corners meet: a stroke across them
// tears them as it tears the shared grid, with the same path and the same slit.
TEST(Tear, AMeshWithoutSharedVerticesTearsLikeTheSharedOne) {
  const std::vector<Scalpel> steps{blade_at(0.7, 1.3), blade_at(3.4, 2.2)};
  const anim::RiggedModel shared = static_model(grid(4)), soup = static_model(unshared(grid(4)));
  const ModelTear a = surgery::tear(shared, rest_placement(shared), steps, {.open = 0.1});
  const ModelTear b = surgery::tear(soup, rest_placement(soup), steps, {.open = 0.1});
  ASSERT_EQ(a.path.size(), b.path.size());
  for (std::size_t i = 0; i < a.path.size(); ++i) EXPECT_LE((a.path[i] - b.path[i]).norm(), 1e-9);
  EXPECT_EQ(a.faces_split, b.faces_split);
  EXPECT_EQ(a.faces_out, b.faces_out);
  EXPECT_NEAR(area(a.model.meshes[0].faces, a.placed), area(b.model.meshes[0].faces, b.placed), 1e-6);
  EXPECT_EQ(new_boundary(grid(4), a).size(), new_boundary(unshared(grid(4)), b).size());
}

// Along grid lines of the soup the faces are apart already: without an opening the tear would
// change nothing, and says so; with one, the two sides move apart.
TEST(Tear, ATearThatChangesNothingIsATopologyError) {
  const anim::RiggedModel soup = static_model(unshared(grid(4)));
  const std::vector<Scalpel> steps{blade_at(1, 1), blade_at(1, 2), blade_at(1, 3)};
  EXPECT_THROW((void)surgery::tear(soup, rest_placement(soup), steps), TopologyError);
  surgery::LiveModel live(soup, rest_placement(soup));
  EXPECT_THROW((void)surgery::tear(live, steps), TopologyError);
  const ModelTear t = surgery::tear(soup, rest_placement(soup), steps, {.open = 0.2});
  EXPECT_EQ(t.new_vertices, 0);
  int moved = 0;
  for (Eigen::Index v = 0; v < t.placed.rows(); ++v)
    moved += (t.placed.row(v) - rest_placement(soup).positions[0].row(v)).norm() > 1e-3f ? 1 : 0;
  EXPECT_GE(moved, 4);  // the faces at (1, 2) on both sides
}

TEST(Tear, ScalpelThatMissesIsATopologyError) {
  const anim::RiggedModel model = static_model(grid(4));
  const auto placement = rest_placement(model);
  EXPECT_THROW((void)surgery::tear(model, placement, std::vector<Scalpel>{blade_at(9, 9), blade_at(1, 1)}),
               TopologyError);
  EXPECT_THROW((void)surgery::tear(model, placement, std::vector<Scalpel>{blade_at(1, 1), blade_at(1, 9)}),
               TopologyError);
  // Above the surface: the blade does not reach it.
  EXPECT_THROW((void)surgery::tear(model, placement, std::vector<Scalpel>{{{1, 1, 2}, {1, 1, 1}}, blade_at(2, 2)}),
               TopologyError);
}

TEST(Tear, BadScalpelsAreInvalidInput) {
  const anim::RiggedModel model = static_model(grid(4));
  const auto placement = rest_placement(model);
  EXPECT_THROW((void)surgery::tear(model, placement, std::vector<Scalpel>{blade_at(1, 1)}), InvalidInputError);
  EXPECT_THROW((void)surgery::tear(model, placement, std::vector<Scalpel>{blade_at(1, 1), {{2, 2, 0}, {2, 2, 0}}}),
               InvalidInputError);
  EXPECT_THROW((void)surgery::tear(model, placement, std::vector<Scalpel>{blade_at(1, 1), blade_at(std::nan(""), 2)}),
               InvalidInputError);
  TearOptions opt;
  opt.open = -1;
  EXPECT_THROW((void)surgery::tear(model, placement, std::vector<Scalpel>{blade_at(1, 1), blade_at(2, 2)}, opt),
               InvalidInputError);
}

TEST(Tear, PathRunningOffAnOpenBorderIsATopologyError) {
  // Two separate squares: the entry points lie on different parts of the surface.
  mesh::Mesh m = grid(3);
  m.faces.conservativeResize(m.faces.rows(), 3);
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f) {
    const float cx =
        (m.positions(m.faces(f, 0), 0) + m.positions(m.faces(f, 1), 0) + m.positions(m.faces(f, 2), 0)) / 3;
    if (cx > 1 && cx < 2) m.faces.row(f).setConstant(-1);
  }
  Eigen::Index kept = 0;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
    if (m.faces(f, 0) >= 0) m.faces.row(kept++) = m.faces.row(f);
  m.faces.conservativeResize(kept, 3);
  const anim::RiggedModel model = static_model(m);
  EXPECT_THROW(
      (void)surgery::tear(model, rest_placement(model), std::vector<Scalpel>{blade_at(0.5, 1.5), blade_at(2.5, 1.5)}),
      TopologyError);
}

// ---- properties on real models -----------------------------------------------------------------

class TearProperties : public ::testing::TestWithParam<int> {};

TEST_P(TearProperties, RandomStrokesKeepEveryInvariant) {
  const Subject& s = subjects()[static_cast<std::size_t>(GetParam())];
  const double diag = model_diagonal(s);
  const surgery::SurfaceIndex index = surgery::SurfaceIndex::build(s.model, s.placement);
  std::mt19937 rng(555 + GetParam());
  int torn = 0;
  const int cases = 12 * kCaseScale;
  for (int i = 0; i < cases; ++i) {
    SCOPED_TRACE(s.name + " stroke " + std::to_string(i));
    const std::vector<Scalpel> steps = random_stroke(s, rng, 2 + i % 3, (0.02 + 0.01 * (i % 5)) * diag);
    TearOptions opt;
    opt.predicates = i % 3 == 0 ? surgery::Predicates::euclidean : surgery::Predicates::cga;
    ModelTear t;
    try {
      t = surgery::tear(s.model, s.placement, index, steps, opt);
    } catch (const TopologyError& e) {
      // A stroke that leaves the surface at a border or jumps to another layer of it.
      SCOPED_TRACE(e.what());
      continue;
    }
    ++torn;
    const auto k = static_cast<std::size_t>(t.mesh);
    const mesh::Mesh& old = s.model.meshes[k];
    const mesh::Mesh& m = t.model.meshes[k];
    expect_sane_mesh(m, s.name);
    ASSERT_EQ(t.placed.rows(), m.vertex_count());
    // Without opening the surface does not move: the same placed area.
    EXPECT_NEAR(area(m.faces, t.placed) / area(old.faces, s.placement.positions[k]), 1.0, 1e-6);
    // The new border is the slit: closed loops of edges on the path.
    const auto boundary = new_boundary(old, t);
    EXPECT_FALSE(boundary.empty());
    if (s.closed) {
      EXPECT_TRUE(boundary_is_loops(boundary));
    }
    for (const auto& [a, b] : boundary)
      for (const int v : {a, b})
        ASSERT_LE(distance_to_path(t.path, t.placed.row(v).cast<double>().transpose()), 1e-5 * diag);
    expect_reanimates_like(s.model, k, t.model, k, t.origins, 1e-6 * diag);
    if (HasFatalFailure()) return;
  }
  EXPECT_GE(torn, cases / 2) << "most strokes over the surface should tear it";
}

INSTANTIATE_TEST_SUITE_P(Models, TearProperties, ::testing::Values(0, 1, 2, 3),
                         [](const auto& info) { return subjects()[static_cast<std::size_t>(info.param)].name; });

TEST(Tear, CgaAndEuclideanPredicatesGiveTheSameTear) {
  const Subject& s = subjects()[0];
  std::mt19937 rng(8);
  for (int i = 0; i < 20; ++i) {
    const std::vector<Scalpel> steps = random_stroke(s, rng, 3, 0.05 * model_diagonal(s));
    TearOptions ga, eu;
    eu.predicates = surgery::Predicates::euclidean;
    ModelTear a, b;
    try {
      a = surgery::tear(s.model, s.placement, steps, ga);
    } catch (const TopologyError&) {
      EXPECT_THROW((void)surgery::tear(s.model, s.placement, steps, eu), TopologyError);
      continue;
    }
    b = surgery::tear(s.model, s.placement, steps, eu);
    ASSERT_EQ(a.path.size(), b.path.size());
    ASSERT_EQ(a.faces_out, b.faces_out);
    for (std::size_t p = 0; p < a.path.size(); ++p) EXPECT_LE((a.path[p] - b.path[p]).norm(), 1e-6 * model_diagonal(s));
  }
}

TEST(Tear, OpenedTearOnAnAnimatedModelStaysOpenWhenReanimated) {
  const Subject& s = subjects()[0];
  const double diag = model_diagonal(s);
  std::mt19937 rng(21);
  TearOptions opened;
  opened.open = 0.01 * diag;
  const anim::Pose pose = anim::sample(s.model.skeleton, s.model.clips[0], 0.5, anim::BlendMode::format);
  for (int i = 0; i < 10; ++i) {
    const std::vector<Scalpel> steps = random_stroke(s, rng, 2, 0.05 * diag);
    ModelTear closed, open;
    try {
      closed = surgery::tear(s.model, s.placement, steps);
    } catch (const TopologyError&) {
      continue;
    }
    open = surgery::tear(s.model, s.placement, steps, opened);
    const auto k = static_cast<std::size_t>(open.mesh);
    ASSERT_EQ(open.placed.rows(), closed.placed.rows());
    // Skinning the new rest meshes in the pose of the tear moves each copy by its opening.
    const Points moved = open.placed - closed.placed;
    const Points reskinned =
        surgery::place(open.model, pose).positions[k] - surgery::place(closed.model, pose).positions[k];
    EXPECT_LE((reskinned - moved).cwiseAbs().maxCoeff(), 1e-5 * diag);
    EXPECT_GT(moved.rowwise().norm().maxCoeff(), 0.4 * opened.open) << "the middle of the tear opens";
    EXPECT_LE(moved.rowwise().norm().maxCoeff(), 0.5 * opened.open + 1e-6 * diag);
    expect_sane_mesh(open.model.meshes[k], "opened");
    return;
  }
  FAIL() << "no stroke tore the model";
}

}  // namespace
