// Drilling (Algorithm 3): hand-checked holes in a grid and a box, refinement of a drill smaller
// than the faces, degenerate and bad drills, and hundreds of random drills through real models
// with every invariant of a drill checked on every result.
#include "cgamesh/surgery/drill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"
#include "cgamesh/mesh/triangle_bvh.hpp"

#include "anim/model_fixtures.hpp"
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

/// Height above the base along the axis, and distance from the axis, of x.
std::pair<double, double> drill_coordinates(const V3& x, const V3& tip, const V3& base) {
  const V3 n = (tip - base).normalized();
  return {n.dot(x - base), axis_distance(x, tip, base)};
}

/// Whether x lies inside the finite drill by more than tol.
bool deep_inside(const V3& x, const V3& tip, const V3& base, double r, double tol) {
  const auto [h, rho] = drill_coordinates(x, tip, base);
  return h > tol && h < (tip - base).norm() - tol && rho < r - tol;
}

/// Whether x lies outside the finite drill by more than tol.
bool clearly_outside(const V3& x, const V3& tip, const V3& base, double r, double tol) {
  const auto [h, rho] = drill_coordinates(x, tip, base);
  return h < -tol || h > (tip - base).norm() + tol || rho > r + tol;
}

/// Whether x lies on the drill's boundary (the cylinder between the disks, or an end disk).
bool on_drill_boundary(const V3& x, const V3& tip, const V3& base, double r, double tol) {
  return !deep_inside(x, tip, base, r, tol) && !clearly_outside(x, tip, base, r, tol);
}

/// Vertex ids of a drilled mesh welded through their origins (weld_points).
std::vector<int> weld_points(const ModelDrill& d, std::size_t k, const anim::RiggedModel& before) {
  return cgamesh_test::weld_points(
      d.origins[k], weld_by_position(before.meshes[static_cast<std::size_t>(d.source_mesh[k])].positions));
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

  // A drill stopping inside the box makes a blind hole: without the wall one open rim; with it
  // a tube down to the tip's disk and that disk, so the box stays closed, less the hole.
  const V3 inside(0.45, 0.55, 0.5);
  const ModelDrill blind_open = surgery::drill(model, placement, inside, base, r);
  EXPECT_EQ(blind_open.rims, 1);
  EXPECT_EQ(boundary_edges(blind_open.model.meshes[0].faces, weld_points(blind_open, 0, model)).size(),
            rim_edges(blind_open, 0, model, inside, base, r, 1e-5).size());
  const ModelDrill blind = surgery::drill(model, placement, inside, base, r, wall);
  EXPECT_EQ(blind.rims, 1);
  EXPECT_GT(blind.wall_triangles, 0);
  EXPECT_TRUE(blind.warnings.empty()) << blind.warnings.front();
  const mesh::Mesh& bm = blind.model.meshes[0];
  expect_sane_mesh(bm, "box");
  EXPECT_TRUE(closed_and_oriented(bm.faces, weld_by_position(blind.placed[0])));
  const double bv = volume(bm.faces, blind.placed[0]), hole = std::numbers::pi * r * r * 0.5;
  EXPECT_LT(bv, 1 - 0.8 * hole);
  EXPECT_GT(bv, 1 - hole);
}

// A slanted blind hole whose tip's disk cuts the surface it enters: the rim runs on the cylinder
// and, across the entry face, on the tip's disk. With a wall, the tube goes down from the
// cylinder part, the disk is closed between the tube and the surface, and the box stays closed.
TEST(Drill, BlindHoleWhoseTipDiskCutsTheEntryFaceIsClosed) {
  const anim::RiggedModel model = static_model(fine_box());
  const auto placement = rest_placement(model);
  const V3 axis = V3(0.6, 0, 0.8);
  const V3 tip(0.5, 0.5, 0.08), base = tip - 0.8 * axis;
  const double r = 0.3, length = 0.8;
  DrillOptions wall;
  wall.wall = true;
  const ModelDrill blind = surgery::drill(model, placement, tip, base, r, wall);
  EXPECT_EQ(blind.rims, 1);
  EXPECT_TRUE(blind.warnings.empty()) << blind.warnings.front();
  const mesh::Mesh& m = blind.model.meshes[0];
  expect_sane_mesh(m, "box");
  ASSERT_TRUE(closed_and_oriented(m.faces, weld_by_position(blind.placed[0])));
  // Some of the disk's triangles border the entry face directly; all face back up the hole.
  int disk = 0;
  for (Eigen::Index f = m.face_count() - blind.wall_triangles; f < m.face_count(); ++f) {
    std::array<V3, 3> c;
    bool at_tip = true;
    for (int k = 0; k < 3; ++k) {
      c[static_cast<std::size_t>(k)] = row(blind.placed[0], m.faces(f, k));
      at_tip = at_tip && std::abs(axis.dot(c[static_cast<std::size_t>(k)] - base) - length) < 1e-6;
    }
    if (!at_tip) continue;
    ++disk;
    EXPECT_LT((c[1] - c[0]).cross(c[2] - c[0]).normalized().dot(axis), -0.999);
  }
  EXPECT_GT(disk, 0);
  // The volume taken: the part of the finite cylinder above the entry face z = 0, integrated
  // over the disk (the mesh's rim is an inscribed polygon, so a little less is taken).
  const V3 e1 = V3(0, 1, 0), e2 = axis.cross(e1);
  const int n = 400;
  double taken = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = r * (2 * (i + 0.5) / n - 1), v = r * (2 * (j + 0.5) / n - 1);
      if (u * u + v * v > r * r) continue;
      const V3 foot = base + u * e1 + v * e2;  // z(h) = foot.z + 0.8 h
      const double enter = std::clamp(-foot.z() / axis.z(), 0.0, length);
      taken += (length - enter) * (2 * r / n) * (2 * r / n);
    }
  const double kept = volume(m.faces, blind.placed[0]);
  EXPECT_GT(kept, 1 - taken);
  EXPECT_LT(kept, 1 - 0.9 * taken);
}

/// Whether every warning of `d` that names a rim left open says so.
bool names_open_rims(const ModelDrill& d) {
  return d.open_rims > 0 && std::count_if(d.warnings.begin(), d.warnings.end(), [](const std::string& w) {
                              return w.find("the rim of ") != std::string::npos &&
                                     w.find(" left open: ") != std::string::npos;
                            }) == d.open_rims;
}

// A wall runs only inside the material. Through a sheet, the rim bounds no hole in a body: with a
// tip far past it (or a base far before it), it stays open, named in a warning, and nothing is
// built off the sheet.
TEST(Drill, WallsOnASheetStayOpenWithAWarningNamingTheRim) {
  const anim::RiggedModel model = static_model(grid(8));
  const auto placement = rest_placement(model);
  DrillOptions wall;
  wall.wall = true;
  for (const double direction : {-1.0, 1.0}) {  // against the sheet's normal (an entry), and along it
    const V3 base(4.3, 4.4, 1 * -direction), tip(4.3, 4.4, 50 * direction);
    const ModelDrill d = surgery::drill(model, placement, tip, base, 0.7, wall);
    SCOPED_TRACE(direction);
    EXPECT_EQ(d.rims, 1);
    EXPECT_EQ(d.walls, 0);
    EXPECT_EQ(d.open_rims, 1);
    EXPECT_EQ(d.wall_triangles, 0);
    EXPECT_TRUE(names_open_rims(d));
    EXPECT_NEAR(d.placed[0].col(2).cwiseAbs().maxCoeff(), 0.0, 1e-6) << "a tube off the sheet";
  }
}

// A box whose back the drill leaves through a mesh boundary (the back is cut open there): the
// exit rim is open, so the entry rim has no partner; the material ends 0.5 before the tip, so a
// blind hole down to the tip would stick out of the back. Both rims stay open.
TEST(Drill, ThroughDrillLeavingTheBodyBeforeItsTipWallsNothingOutside) {
  mesh::Mesh box = fine_box();
  std::vector<Eigen::Vector3i> kept;
  for (Eigen::Index f = 0; f < box.face_count(); ++f) {
    Eigen::Vector3f c = Eigen::Vector3f::Zero();
    for (int k = 0; k < 3; ++k) c += box.positions.row(box.faces(f, k)).transpose();
    c /= 3;
    if (!(c.z() > 0.999f && c.x() > 0.5f)) kept.emplace_back(box.faces.row(f).transpose());
  }
  box.faces.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t f = 0; f < kept.size(); ++f) box.faces.row(static_cast<Eigen::Index>(f)) = kept[f].transpose();
  const anim::RiggedModel model = static_model(box);
  DrillOptions wall;
  wall.wall = true;
  const V3 base(0.45, 0.55, -0.5), tip(0.45, 0.55, 1.5);
  const ModelDrill d = surgery::drill(model, rest_placement(model), tip, base, 0.3, wall);
  EXPECT_EQ(d.rims, 2);
  EXPECT_EQ(d.walls, 0);
  EXPECT_EQ(d.open_rims, 2);
  EXPECT_EQ(d.wall_triangles, 0);
  EXPECT_TRUE(names_open_rims(d));
  EXPECT_LE(d.placed[0].col(2).maxCoeff(), 1.0f + 1e-6f) << "a tube out of the back";
  EXPECT_TRUE(std::any_of(d.warnings.begin(), d.warnings.end(),
                          [](const std::string& w) { return w.find("leaves the material 0.5") != std::string::npos; }));
}

// A blind hole, a through hole whose tip lies far past the body, and two boxes one behind the
// other: walls where the material is, each counted; the result closed.
TEST(Drill, WallsCountTubesAndBlindHoles) {
  // Two unit cubes (positions and faces only, so stacking them is a whole mesh), then refined.
  mesh::Mesh two = cube();
  two.positions.conservativeResize(16, 3);
  two.positions.bottomRows(8) = two.positions.topRows(8);
  two.positions.bottomRows(8).col(2).array() += 2;
  two.faces.conservativeResize(24, 3);
  two.faces.bottomRows(12) = two.faces.topRows(12).array() + 8;
  const anim::RiggedModel model = static_model(mesh::subdivide_midpoint(mesh::subdivide_midpoint(two)));
  const auto placement = rest_placement(model);
  DrillOptions wall;
  wall.wall = true;
  const V3 base(0.45, 0.55, -0.5);
  struct Case {
    double tip_z;
    int walls;
  };
  // Far past both boxes: two tubes. Inside the second: a tube and a blind hole. Between them:
  // one tube (the second box is not reached).
  for (const Case c : {Case{60, 2}, Case{2.5, 2}, Case{1.5, 1}}) {
    SCOPED_TRACE(c.tip_z);
    const ModelDrill d = surgery::drill(model, placement, V3(0.45, 0.55, c.tip_z), base, 0.3, wall);
    EXPECT_EQ(d.walls, c.walls);
    EXPECT_EQ(d.open_rims, 0);
    EXPECT_TRUE(d.warnings.empty()) << d.warnings.front();
    EXPECT_TRUE(closed_and_oriented(d.model.meshes[0].faces, weld_by_position(d.placed[0])));
  }
}

// The drill is finite: between base and tip only. Of two parallel layers it holes the one it
// reaches, and a second mesh that its body grazes (the axis passes beside it) is cut as well.
TEST(Drill, OnlyWhatLiesBetweenBaseAndTipGoesInEveryMesh) {
  mesh::Mesh near = grid(4), far = grid(4), side = grid(4);
  far.positions.col(2).setConstant(1.0f);
  far.name = "far";
  // `side` stands upright in x = 2.3, beside the axis x = 2 (within the radius 0.5).
  side.positions.col(2) = side.positions.col(0).array() * 0.25f - 0.5f;
  side.positions.col(0).setConstant(2.3f);
  side.name = "side";
  anim::RiggedModel model = static_model(near);
  model.meshes.push_back(far);
  model.meshes.push_back(side);
  for (auto& m : model.meshes) m.node = 0;
  const auto placement = rest_placement(model);
  const V3 base(2, 2, -0.5), tip(2, 2, 0.5);
  const ModelDrill d = surgery::drill(model, placement, tip, base, 0.5);
  ASSERT_EQ(d.model.meshes.size(), 3u);
  EXPECT_LT(area(d.model.meshes[0].faces, d.placed[0]), 16 - 0.6);    // holed
  EXPECT_NEAR(area(d.model.meshes[1].faces, d.placed[1]), 16, 1e-9);  // beyond the tip: untouched
  EXPECT_EQ(d.model.meshes[1].faces, far.faces);
  EXPECT_LT(area(d.model.meshes[2].faces, d.placed[2]), 16 - 0.05);  // grazed: a slot cut out
  for (std::size_t k = 0; k < 3; ++k)
    for (Eigen::Index v = 0; v < d.placed[k].rows(); ++v)
      EXPECT_FALSE(deep_inside(row(d.placed[k], v), tip, base, 0.5, 1e-6)) << "mesh " << k << " vertex " << v;
}

/// The reported drills on real models, re-posed at the drill's time: no vertex inside the
/// finite cylinder, and every vertex outside it kept.
void expect_exact_finite_drill(const std::filesystem::path& path, double time, const V3& tip, const V3& base,
                               double r) {
  const anim::RiggedModel model = io::load_model(path);
  const surgery::Placement placement =
      surgery::place(model, anim::sample(model.skeleton, model.clips[0], time, anim::BlendMode::format));
  const ModelDrill d = surgery::drill(model, placement, tip, base, r);
  SCOPED_TRACE(path.string());
  double diag = 0;
  for (const Points& p : placement.positions)
    diag = std::max(diag, static_cast<double>((p.colwise().maxCoeff() - p.colwise().minCoeff()).norm()));
  const double tol = 1e-5 * diag;
  for (std::size_t k = 0; k < d.model.meshes.size(); ++k) {
    const Points posed = skinned(d.model, d.model.meshes[k], time);
    for (Eigen::Index v = 0; v < posed.rows(); ++v)
      ASSERT_FALSE(deep_inside(row(posed, v), tip, base, r, tol)) << "mesh " << k << " vertex " << v;
  }
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    std::set<int> kept;
    for (std::size_t k = 0; k < d.model.meshes.size(); ++k)
      if (d.source_mesh[k] == static_cast<int>(i))
        for (const mesh::VertexSource& o : d.origins[k])
          if (o.count() == 1) kept.insert(o.vertex[0]);
    for (Eigen::Index v = 0; v < placement.positions[i].rows(); ++v)
      if (clearly_outside(row(placement.positions[i], v), tip, base, r, tol)) {
        ASSERT_TRUE(kept.contains(static_cast<int>(v))) << "mesh " << i << ": vertex " << v << " outside removed";
      }
  }
}

TEST(Drill, ReportedDrillsTakeExactlyWhatTheFiniteCylinderHolds) {
  // Vertices 28 % of the drill's length past the tip were removed.
  expect_exact_finite_drill(asset("RiggedFigure.glb"), 0.5, V3(-0.26027551, 0.91589758, -0.037529802),
                            V3(-0.27406076, 0.89667625, -0.17349415), 0.025876221);
  // 9 vertices behind the base were removed.
  expect_exact_finite_drill(demo_model(), 0.2527, V3(0.13120415, 1.3030337, 0.0099706531),
                            V3(0.11531163, 1.1269964, 0.027217668), 0.034332581);
  // Faces sharing no vertices, with a crack in the pose: 21 vertices were left inside.
  if (std::filesystem::exists(assimp_model("X/Testwuson.X")))
    expect_exact_finite_drill(assimp_model("X/Testwuson.X"), 0.4831, V3(0.13825737, 0.63089703, 0.85702889),
                              V3(-0.18315479, 0.58993731, 1.0141245), 0.069050168);
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
    EXPECT_FALSE(deep_inside(row(d.placed[0], v), tip, base, 0.2, 1e-5)) << row(d.placed[0], v).transpose();
  const ModelDrill e = surgery::drill(model, placement, V3(1, 0, 1.5), V3(1, 0, -0.5), 0.25);
  EXPECT_GT(e.faces_removed, 0);
  for (Eigen::Index v = 0; v < e.model.meshes[0].vertex_count(); ++v)
    EXPECT_FALSE(deep_inside(row(e.placed[0], v), V3(1, 0, 1.5), V3(1, 0, -0.5), 0.25, 1e-5));
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

/// Welded ids of the vertices of `old` (placed at `placed`) inside the finite drill: every one
/// of them must go, in every mesh, whether the axis pierces its faces or not.
std::set<int> must_go(const mesh::Mesh& old, const Points& placed, const std::vector<int>& w, const V3& tip,
                      const V3& base, double r, double tol) {
  std::set<int> out;
  for (Eigen::Index v = 0; v < old.vertex_count(); ++v)
    if (deep_inside(row(placed, v), tip, base, r, tol)) out.insert(w[static_cast<std::size_t>(v)]);
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
    const auto old_weld = weld_by_position(old.positions);
    const auto w = weld_points(d, k, s.model);
    const std::set<int> gone = must_go(old, s.placement.positions[src], old_weld, tip, base, r, tol);
    std::set<int> kept;
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
      const mesh::VertexSource& o = origins[static_cast<std::size_t>(v)];
      if (o.count() == 1) {
        kept.insert(old_weld[static_cast<std::size_t>(o.vertex[0])]);
        ASSERT_FALSE(gone.contains(old_weld[static_cast<std::size_t>(o.vertex[0])]))
            << what << ": vertex left in the hole";
      } else {
        ASSERT_FALSE(deep_inside(row(placed, v), tip, base, r, tol)) << what << ": a new vertex inside the drill";
      }
    }
    // Only what the finite drill holds goes: nothing beyond the tip or behind the base.
    for (Eigen::Index v = 0; v < old.vertex_count(); ++v)
      if (clearly_outside(row(s.placement.positions[src], v), tip, base, r, tol)) {
        ASSERT_TRUE(kept.contains(old_weld[static_cast<std::size_t>(v)]))
            << what << ": vertex " << v << " outside the drill removed";
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
      const bool rim =
          on_drill_boundary(row(placed, a), tip, base, r, tol) && on_drill_boundary(row(placed, b), tip, base, r, tol);
      ASSERT_TRUE(rim || on_old_boundary(a, b))
          << what << ": a new boundary edge off the drill's boundary: (h, ρ) = ("
          << drill_coordinates(row(placed, a), tip, base).first << ", "
          << drill_coordinates(row(placed, a), tip, base).second << "), ("
          << drill_coordinates(row(placed, b), tip, base).first << ", "
          << drill_coordinates(row(placed, b), tip, base).second << ") L " << (tip - base).norm() << " r " << r
          << " origins " << origins[static_cast<std::size_t>(a)].count()
          << origins[static_cast<std::size_t>(b)].count();
    }
    if (s.closed) {
      EXPECT_TRUE(boundary_is_loops(boundary)) << what << ": the rims are not closed loops";
      if (opt.wall && d.open_rims == 0) {
        EXPECT_TRUE(closed_and_oriented(m.faces, w)) << what << ": not closed with the wall";
      }
    }
    if (!opt.wall) {
      EXPECT_LE(area(m.faces, placed), area(old.faces, s.placement.positions[src]) * (1 + 1e-6)) << what;
    }
    expect_reanimates_like(s.model, src, d.model, k, origins, 1e-6 * diag, &placed);
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

namespace {

// Found by the field sweep: a drill through models of hundreds of small meshes printed a
// warning per mesh (400-1400 lines).
TEST(Drill, WarningsOfManyMeshesAreBounded) {
  cgamesh::anim::RiggedModel model;
  for (int k = 0; k < 30; ++k) {
    cgamesh::mesh::Mesh sheet = cgamesh_test::grid(4);
    sheet.name = "sheet" + std::to_string(k);
    for (Eigen::Index v = 0; v < sheet.vertex_count(); ++v) sheet.positions(v, 2) = 0.1f * static_cast<float>(k);
    model.meshes.push_back(std::move(sheet));
  }
  const cgamesh::surgery::Placement placed =
      cgamesh::surgery::place(model, cgamesh::anim::rest_pose(model.skeleton));
  cgamesh::surgery::DrillOptions options;
  options.wall = true;
  const cgamesh::surgery::ModelDrill d =
      cgamesh::surgery::drill(model, placed, {2.1, 2.1, 5}, {2.1, 2.1, -1}, 0.7, options);
  EXPECT_EQ(d.open_rims, 30);
  ASSERT_EQ(d.warnings.size(), 13u);
  EXPECT_NE(d.warnings.back().find("18 more warnings"), std::string::npos) << d.warnings.back();
}

}  // namespace
