// Plane cuts (Algorithm 1): hand-checked cases, degenerate planes, and thousands of random
// planes through real models with every invariant of a cut checked on every result.
#include "cgamesh/surgery/cut.hpp"

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "surgery/surgery_checks.hpp"
#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh;
using namespace cgamesh_test;
using surgery::CutOptions;
using surgery::ModelCut;

// ---- hand-checked cases ------------------------------------------------------------------------

TEST(Cut, OneTriangleIntoATriangleAndAQuad) {
  mesh::Mesh tri;
  tri.positions.resize(3, 3);
  tri.positions << 0, 0, 0, 2, 0, 0, 0, 2, 0;
  tri.faces.resize(1, 3);
  tri.faces << 0, 1, 2;
  const anim::RiggedModel model = static_model(tri);
  const ModelCut c = surgery::cut(model, rest_placement(model), cga::plane<double>({1, 0, 0}, 1.0));
  EXPECT_EQ(c.intersection_points, 2);
  EXPECT_EQ(c.faces_split, 1);
  ASSERT_EQ(c.pieces[0].meshes.size(), 1u);
  const mesh::Mesh& a = c.pieces[0].meshes[0];  // x > 1: the corner (2, 0, 0)
  const mesh::Mesh& b = c.pieces[1].meshes[0];
  EXPECT_EQ(a.face_count(), 1);
  EXPECT_EQ(b.face_count(), 2);
  EXPECT_EQ(a.vertex_count(), 3);
  EXPECT_EQ(b.vertex_count(), 4);
  EXPECT_NEAR(area(a.faces, a.positions), 0.5, 1e-6);
  EXPECT_NEAR(area(b.faces, b.positions), 1.5, 1e-6);
  // The new vertices are (1, 0, 0) and (1, 1, 0), on edges (0,1) and (1,2).
  std::set<std::array<float, 3>> on_plane;
  for (Eigen::Index v = 0; v < a.vertex_count(); ++v)
    if (a.positions(v, 0) == 1.0f) on_plane.insert({a.positions(v, 0), a.positions(v, 1), a.positions(v, 2)});
  EXPECT_EQ(on_plane, (std::set<std::array<float, 3>>{{1, 0, 0}, {1, 1, 0}}));
  // Winding kept: all normals +z.
  for (const mesh::Mesh* m : {&a, &b})
    for (Eigen::Index f = 0; f < m->face_count(); ++f) {
      const Eigen::Vector3f p = m->positions.row(m->faces(f, 0)), q = m->positions.row(m->faces(f, 1)),
                            r = m->positions.row(m->faces(f, 2));
      EXPECT_GT((q - p).cross(r - p).z(), 0);
    }
}

TEST(Cut, PlaneThroughVerticesAddsNoPointsAndNoSlivers) {
  const anim::RiggedModel model = static_model(grid(4));
  const ModelCut c = surgery::cut(model, rest_placement(model), cga::plane<double>({1, 0, 0}, 2.0));
  EXPECT_EQ(c.intersection_points, 0);
  EXPECT_EQ(c.faces_split, 0);
  EXPECT_EQ(c.faces_out[0] + c.faces_out[1], 32);
  // The column x = 2 is in both pieces once; no vertex twice in a piece.
  for (const auto& piece : c.pieces) {
    const mesh::Mesh& m = piece.meshes[0];
    EXPECT_EQ(m.vertex_count(), 15);
    EXPECT_EQ(m.face_count(), 16);
  }
}

TEST(Cut, DiagonalPlaneThroughVerticesSplitsAtVertices) {
  // x − y = 0 passes through the grid's diagonal vertices; faces along it touch the plane at a
  // vertex or lie on one side, split faces are cut at one vertex into two triangles.
  const anim::RiggedModel model = static_model(grid(3));
  const ModelCut c = surgery::cut(model, rest_placement(model), cga::plane<double>({1, -1, 0}, 0.0));
  EXPECT_EQ(area(c.pieces[0].meshes[0].faces, c.pieces[0].meshes[0].positions), 4.5);
  EXPECT_EQ(area(c.pieces[1].meshes[0].faces, c.pieces[1].meshes[0].positions), 4.5);
}

TEST(Cut, CubeThroughVerticesWithCapIsClosed) {
  const anim::RiggedModel model = static_model(cube());
  CutOptions opt;
  opt.cap = true;
  // Through the diagonal plane x = y: vertices 0, 3, 4, 7 are on it; of the face diagonals,
  // only 1-2 and 5-6 cross it.
  const ModelCut c = surgery::cut(model, rest_placement(model), cga::plane<double>({1, -1, 0}, 0.0), opt);
  EXPECT_EQ(c.intersection_points, 2);
  for (const auto& piece : c.pieces) {
    const mesh::Mesh& m = piece.meshes[0];
    EXPECT_TRUE(closed_and_oriented(m.faces, m.positions));
    EXPECT_NEAR(volume(m.faces, m.positions), 0.5, 1e-6);
  }
}

TEST(Cut, CubeCapIsOrientedOutwardOnBothPieces) {
  const anim::RiggedModel model = static_model(cube());
  CutOptions opt;
  opt.cap = true;
  const ModelCut c = surgery::cut(model, rest_placement(model), cga::plane<double>({0.2, 0.1, 1}, 0.55), opt);
  EXPECT_EQ(c.intersection_points, 8);  // 4 cube edges and 4 face diagonals
  double total = 0;
  for (const auto& piece : c.pieces) {
    const mesh::Mesh& m = piece.meshes[0];
    EXPECT_TRUE(closed_and_oriented(m.faces, m.positions));
    const double v = volume(m.faces, m.positions);
    EXPECT_GT(v, 0);
    total += v;
  }
  EXPECT_NEAR(total, 1.0, 1e-6);
  EXPECT_GT(c.cap_triangles, 0);
}

/// Unit cubes moved by `offsets`, all in one mesh.
mesh::Mesh cubes(const std::vector<Eigen::Vector3f>& offsets) {
  const mesh::Mesh one = cube();
  mesh::Mesh m;
  m.name = "cubes";
  const auto n = static_cast<Eigen::Index>(offsets.size());
  m.positions.resize(8 * n, 3);
  m.faces.resize(12 * n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    m.positions.middleRows(8 * i, 8) = one.positions.rowwise() + offsets[static_cast<std::size_t>(i)].transpose();
    m.faces.middleRows(12 * i, 12) = one.faces.array() + static_cast<int>(8 * i);
  }
  return m;
}

// Two cubes that overlap (their sections cross) and one apart, in one mesh: the loop that can
// be capped is capped, the two crossing ones are left open with a warning.
TEST(Cut, CapsTheLoopsThatCanBeCappedAndWarnsAboutTheRest) {
  const anim::RiggedModel model = static_model(cubes({{0, 0, 0}, {0.5f, 0.5f, 0.1f}, {3, 0, 0}}));
  CutOptions opt;
  opt.cap = true;
  const ModelCut c = surgery::cut(model, rest_placement(model), cga::plane<double>({0, 0, 1}, 0.7), opt);
  ASSERT_EQ(c.warnings.size(), 2u);  // one per piece
  for (const std::string& w : c.warnings) EXPECT_NE(w.find("2 cross-section loop(s)"), std::string::npos) << w;
  EXPECT_EQ(c.cap_triangles, 12);  // the section of the cube apart (8 points: 4 corners, 4 face diagonals), twice
  for (const auto& piece : c.pieces) {
    const mesh::Mesh& m = piece.meshes[0];
    double area_at_cap = 0;
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      const Eigen::Vector3f a = m.positions.row(m.faces(f, 0)), b = m.positions.row(m.faces(f, 1)),
                            e = m.positions.row(m.faces(f, 2));
      if (std::abs(a.z() - 0.7f) < 1e-6f && std::abs(b.z() - 0.7f) < 1e-6f && std::abs(e.z() - 0.7f) < 1e-6f)
        area_at_cap += 0.5 * static_cast<double>((b - a).cross(e - a).norm());
    }
    EXPECT_NEAR(area_at_cap, 1.0, 1e-6);
  }
}

// ---- degenerate and bad input -------------------------------------------------------------------

TEST(Cut, MissingOrTangentPlaneIsATopologyError) {
  const anim::RiggedModel model = static_model(cube());
  const auto placement = rest_placement(model);
  EXPECT_THROW((void)surgery::cut(model, placement, cga::plane<double>({0, 0, 1}, 3.0)), TopologyError);
  EXPECT_THROW((void)surgery::cut(model, placement, cga::plane<double>({0, 0, 1}, 1.0)), TopologyError)
      << "the top face lies in the plane: nothing is on its positive side";
  EXPECT_THROW((void)surgery::cut(model, placement, cga::plane<double>({1, 1, 1}, 0.0)), TopologyError)
      << "touches the cube at one corner only";
}

TEST(Cut, BadPlaneOrPositionsAreInvalidInput) {
  const anim::RiggedModel model = static_model(cube());
  const auto placement = rest_placement(model);
  EXPECT_THROW((void)surgery::cut(model, placement, cga::Vector<double>{}), InvalidInputError);
  EXPECT_THROW((void)surgery::cut(model, placement, cga::up<double>({0, 0, 0})), InvalidInputError)
      << "a point is not a plane";
  EXPECT_THROW((void)cga::plane<double>({0, 0, 0}, 1.0), InvalidInputError);
  EXPECT_THROW((void)cga::plane<double>({0, 0, 1}, std::nan("")), InvalidInputError);
  surgery::Placement bad = placement;
  bad.positions[0](3, 1) = std::nanf("");
  EXPECT_THROW((void)surgery::cut(model, bad, cga::plane<double>({0, 0, 1}, 0.5)), InvalidInputError);
  bad.positions[0].conservativeResize(4, 3);
  EXPECT_THROW((void)surgery::cut(model, bad, cga::plane<double>({0, 0, 1}, 0.5)), InvalidInputError);
}

// ---- properties on real models -----------------------------------------------------------------

/// Every invariant of one cut of `s` by n·x = d.
void check_cut(const Subject& s, const Eigen::Vector3d& n, double d, const CutOptions& opt) {
  const double diag = model_diagonal(s);
  const double tol = 1e-5 * diag;
  const auto dist = [&](const Points& p, Eigen::Index v) { return n.dot(p.row(v).cast<double>().transpose()) - d; };
  ModelCut c;
  try {
    c = surgery::cut(s.model, s.placement, cga::plane(n, d), opt);
  } catch (const TopologyError& e) {
    SCOPED_TRACE(e.what());
    // A miss: then no placed vertex is clearly on both sides.
    bool pos = false, neg = false;
    for (const Points& p : s.placement.positions)
      for (Eigen::Index v = 0; v < p.rows(); ++v) {
        pos = pos || dist(p, v) > tol;
        neg = neg || dist(p, v) < -tol;
      }
    EXPECT_FALSE(pos && neg) << "a plane through the model was reported as missing it";
    return;
  }
  // A section that crosses itself is left open, with a warning; only where the mesh does.
  const bool uncapped = std::any_of(c.warnings.begin(), c.warnings.end(),
                                    [](const std::string& w) { return w.find("not capped") != std::string::npos; });
  if (uncapped) {
    EXPECT_TRUE(s.self_intersecting) << c.warnings.front();
  }
  double cut_area = 0, cut_volume = 0;
  for (int p = 0; p < 2; ++p) {
    const double sign = p == 0 ? 1 : -1;
    const auto& piece = c.pieces[static_cast<std::size_t>(p)];
    for (std::size_t k = 0; k < piece.meshes.size(); ++k) {
      const mesh::Mesh& m = piece.meshes[k];
      const Points& placed = c.placed[static_cast<std::size_t>(p)][k];
      const std::string what = s.name + " piece " + std::to_string(p) + " mesh " + m.name;
      expect_sane_mesh(m, what);
      ASSERT_EQ(placed.rows(), m.vertex_count());
      for (Eigen::Index v = 0; v < m.vertex_count(); ++v) ASSERT_GE(sign * dist(placed, v), -tol) << what << " v" << v;
      const int src = c.source_mesh[static_cast<std::size_t>(p)][k];
      const mesh::Mesh& old = s.model.meshes[static_cast<std::size_t>(src)];
      const auto old_weld = weld_by_position(old.positions);
      const auto w = weld_origins(c.origins[static_cast<std::size_t>(p)][k], old_weld);
      const auto boundary = boundary_edges(m.faces, w);
      if (!opt.cap) {
        cut_area += area(m.faces, placed);
        // New boundary edges lie on the plane; others were boundary edges before.
        std::set<std::pair<int, int>> old_boundary;
        for (const auto& e : boundary_edges(old.faces, old_weld)) old_boundary.insert(e);
        const auto& origins = c.origins[static_cast<std::size_t>(p)][k];
        for (const auto& [a, b] : boundary) {
          if (std::abs(dist(placed, a)) <= tol && std::abs(dist(placed, b)) <= tol) continue;
          const auto& oa = origins[static_cast<std::size_t>(a)];
          const auto& ob = origins[static_cast<std::size_t>(b)];
          EXPECT_TRUE(oa.count() == 1 && ob.count() == 1 &&
                      old_boundary.contains({old_weld[static_cast<std::size_t>(oa.vertex[0])],
                                             old_weld[static_cast<std::size_t>(ob.vertex[0])]}))
              << what << ": a new boundary edge off the plane";
        }
        if (s.closed) {
          EXPECT_TRUE(boundary_is_loops(boundary)) << what << ": the cut boundary is not closed loops";
        }
      } else if (s.closed && !uncapped) {
        EXPECT_TRUE(closed_and_oriented(m.faces, w)) << what << ": not closed after cap";
        cut_volume += volume(m.faces, placed);
      }
    }
  }
  double original_area = 0, original_volume = 0;
  for (std::size_t k = 0; k < s.model.meshes.size(); ++k) {
    original_area += area(s.model.meshes[k].faces, s.placement.positions[k]);
    original_volume += volume(s.model.meshes[k].faces, s.placement.positions[k]);
  }
  if (!opt.cap) {
    EXPECT_NEAR(cut_area / original_area, 1.0, 1e-6) << s.name << ": area not conserved";
  } else if (s.closed && !uncapped) {
    EXPECT_NEAR(cut_volume / original_volume, 1.0, 1e-5) << s.name << ": volume not conserved";
  }

  // Re-animation: old vertices move as in the uncut model, the pieces' seams coincide.
  if (opt.own_side_influences) return;
  for (double t : {0.3, 1.1}) {
    std::map<std::array<float, 6>, Eigen::Vector3f> seam;
    for (int p = 0; p < 2; ++p)
      for (std::size_t k = 0; k < c.pieces[static_cast<std::size_t>(p)].meshes.size(); ++k) {
        const mesh::Mesh& m = c.pieces[static_cast<std::size_t>(p)].meshes[k];
        const int src = c.source_mesh[static_cast<std::size_t>(p)][k];
        const Points now = skinned(c.pieces[static_cast<std::size_t>(p)], m, t);
        const Points before = skinned(s.model, s.model.meshes[static_cast<std::size_t>(src)], t);
        const auto& origins = c.origins[static_cast<std::size_t>(p)][k];
        for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
          const mesh::VertexSource& o = origins[static_cast<std::size_t>(v)];
          if (o.count() == 1) {
            ASSERT_LE((now.row(v) - before.row(o.vertex[0])).norm(), 1e-6 * diag) << s.name << " t=" << t;
            continue;
          }
          std::array<float, 6> key = origin_key(o);
          key[5] += static_cast<float>(1000 * src);  // origins of different meshes differ
          const auto [it, added] = seam.try_emplace(key, now.row(v).transpose());
          if (!added) {
            ASSERT_LE((it->second - now.row(v).transpose()).norm(), 1e-6 * diag) << s.name << ": seam cracks";
          }
        }
      }
  }
}

class CutProperties : public ::testing::TestWithParam<int> {};

TEST_P(CutProperties, RandomPlanesThroughTheBoundingBox) {
  const Subject& s = subjects()[static_cast<std::size_t>(GetParam())];
  std::mt19937 rng(1234 + GetParam());
  Points all(0, 3);
  for (const Points& p : s.placement.positions) {
    all.conservativeResize(all.rows() + p.rows(), 3);
    all.bottomRows(p.rows()) = p;
  }
  // Fewer planes on the 16k-face arm: each check walks every edge of both pieces.
  const int cases = (s.model.meshes[0].face_count() > 10000 ? 8 : 25) * kCaseScale;
  for (int i = 0; i < cases; ++i) {
    const Eigen::Vector3d n = random_direction(rng);
    const double d = n.dot(random_point_in_box(rng, all));
    CutOptions opt;
    opt.cap = s.closed && i % 2 == 1;
    opt.predicates = i % 3 == 0 ? surgery::Predicates::euclidean : surgery::Predicates::cga;
    SCOPED_TRACE(s.name + " plane " + std::to_string(i));
    check_cut(s, n, d, opt);
    if (HasFatalFailure()) return;
  }
}

TEST_P(CutProperties, PlanesThroughVerticesAndAlongEdges) {
  const Subject& s = subjects()[static_cast<std::size_t>(GetParam())];
  std::mt19937 rng(99 + GetParam());
  const Points& p = s.placement.positions[0];
  const auto& f = s.model.meshes[0].faces;
  std::uniform_int_distribution<Eigen::Index> pick_face(0, f.rows() - 1);
  for (int i = 0; i < 5 * kCaseScale; ++i) {
    const Eigen::Index face = pick_face(rng);
    const Eigen::Vector3d a = p.row(f(face, 0)).cast<double>(), b = p.row(f(face, 1)).cast<double>();
    // Through vertex a; on odd cases containing the whole edge ab.
    Eigen::Vector3d n = random_direction(rng);
    if (i % 2 == 1 && (b - a).norm() > 0) n = n.cross(b - a).normalized();
    CutOptions opt;
    opt.cap = s.closed;
    SCOPED_TRACE(s.name + " degenerate plane " + std::to_string(i));
    check_cut(s, n, n.dot(a), opt);
    if (HasFatalFailure()) return;
  }
}

INSTANTIATE_TEST_SUITE_P(Models, CutProperties, ::testing::Values(0, 1, 2, 3),
                         [](const auto& info) { return subjects()[static_cast<std::size_t>(info.param)].name; });

TEST(Cut, CgaAndEuclideanPredicatesGiveTheSameCut) {
  const Subject& s = subjects()[0];
  std::mt19937 rng(7);
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d n = random_direction(rng);
    const double d = n.dot(s.placement.positions[0].colwise().mean().cast<double>().transpose());
    CutOptions ga, eu;
    eu.predicates = surgery::Predicates::euclidean;
    const ModelCut a = surgery::cut(s.model, s.placement, cga::plane(n, d), ga);
    const ModelCut b = surgery::cut(s.model, s.placement, cga::plane(n, d), eu);
    ASSERT_EQ(a.faces_out, b.faces_out);
    ASSERT_EQ(a.intersection_points, b.intersection_points);
    for (int p = 0; p < 2; ++p)
      for (std::size_t k = 0; k < a.pieces[static_cast<std::size_t>(p)].meshes.size(); ++k)
        EXPECT_LE((a.pieces[static_cast<std::size_t>(p)].meshes[k].positions -
                   b.pieces[static_cast<std::size_t>(p)].meshes[k].positions)
                      .cwiseAbs()
                      .maxCoeff(),
                  1e-6 * model_diagonal(s));
  }
}

TEST(Cut, OwnSideInfluencesComeFromTheOwnSideOnly) {
  const Subject& s = subjects()[0];
  CutOptions opt;
  opt.own_side_influences = true;
  const Eigen::Vector3d n(0, 1, 0);
  const double d = s.placement.positions[0].col(1).cast<double>().mean();
  check_cut(s, n, d, opt);
  const ModelCut c = surgery::cut(s.model, s.placement, cga::plane(n, d), opt);
  for (int p = 0; p < 2; ++p) {
    const mesh::Mesh& m = c.pieces[static_cast<std::size_t>(p)].meshes[0];
    const mesh::Mesh& old = s.model.meshes[0];
    const Points& old_placed = s.placement.positions[0];
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
      const mesh::VertexSource& o = c.origins[static_cast<std::size_t>(p)][0][static_cast<std::size_t>(v)];
      if (o.count() != 2) continue;
      // The endpoint on this piece's side.
      const int own = (n.dot(old_placed.row(o.vertex[0]).cast<double>().transpose()) - d > 0) == (p == 0) ? o.vertex[0]
                                                                                                          : o.vertex[1];
      std::set<int> allowed;
      for (int k = 0; k < 4; ++k)
        if (old.skin.weights(own, k) > 0) allowed.insert(old.skin.joints(own, k));
      for (int k = 0; k < 4; ++k)
        if (m.skin.weights(v, k) > 0) {
          EXPECT_TRUE(allowed.contains(m.skin.joints(v, k)));
        }
    }
  }
}

}  // namespace
