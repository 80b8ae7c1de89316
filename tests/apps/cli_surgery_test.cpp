// The surgery commands run as processes: JSON summaries, outputs that keep skin and clips, and
// failures that exit with the documented code and write nothing (not even one of two pieces).

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/surgery/placement.hpp"

#include "anim/model_fixtures.hpp"
#include "apps/cli_util.hpp"
#include "support/js_oracles.hpp"
#include "surgery/surgery_fixtures.hpp"

namespace {

using namespace cgamesh_cli_test;
using cgamesh_test::asset;
using cgamesh_test::demo_model;

TEST(CliCut, CutsTheAnimatedModelIntoTwoRiggedPieces) {
  TempDir dir;
  const fs::path a = dir / "a.glb", b = dir / "b.gltf";
  const Result r = run_ok(dir, {"cut", demo_model().string(), "--plane", "0,2,0,1.6", "--anim", "0", "--time", "1.2",
                                "-o", a.string(), b.string(), "--json"});
  const nlohmann::json j = parse_json(r);
  EXPECT_GT(j["intersection_points"].get<int>(), 10);
  EXPECT_GT(j["new_vertices"].get<int>(), j["intersection_points"].get<int>());
  EXPECT_GE(j["milliseconds"].get<double>(), 0.0);
  EXPECT_EQ(j["faces_in"].get<int>(), 4672);
  EXPECT_GT(j["faces_out"][0].get<int>() + j["faces_out"][1].get<int>(), 4672);
  EXPECT_EQ(j["predicates"], "cga");
  // Both pieces keep the skin, skeleton and clip; piece A is above y = 0.8 where it was cut.
  const cgamesh::anim::RiggedModel original = cgamesh::io::load_model(demo_model());
  for (const fs::path& piece : {a, b}) {
    const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(piece);
    ASSERT_EQ(m.meshes.size(), 1u) << piece;
    EXPECT_FALSE(m.meshes[0].skin.empty()) << piece;
    EXPECT_EQ(m.clips.size(), original.clips.size()) << piece;
  }
  if (!cgamesh_test::validator_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules is missing";
  for (const fs::path& piece : {a, b}) {
    std::string log;
    EXPECT_EQ(cgamesh_test::validate_gltf(piece, log), 0) << log;
    EXPECT_TRUE(contains(log, " 0 error(s)")) << log;
  }
}

TEST(CliCut, ObjAndPlyOutputsHoldThePlacedSurfaceOnEachSide) {
  TempDir dir;
  run_ok(dir, {"cut", asset("spot.obj").string(), "--plane", "0,1,0,0.1", "--cap", "-o", (dir / "a.obj").string(),
               (dir / "b.ply").string()});
  const Points a = read_obj_vertices(dir / "a.obj"), b = read_ply_vertices(dir / "b.ply");
  ASSERT_GT(a.rows(), 0);
  ASSERT_GT(b.rows(), 0);
  EXPECT_GE(a.col(1).minCoeff(), 0.1f - 1e-6f);
  EXPECT_LE(b.col(1).maxCoeff(), 0.1f + 1e-6f);
}

TEST(CliCut, EuclideanPredicatesGiveTheSameCounts) {
  TempDir dir;
  const std::vector<std::string> base{"cut",
                                      demo_model().string(),
                                      "--plane",
                                      "1,0.3,0,0.02",
                                      "-o",
                                      (dir / "a.glb").string(),
                                      (dir / "b.glb").string(),
                                      "--json"};
  std::vector<std::string> eu = base;
  eu.push_back("--euclidean");
  const nlohmann::json ga = parse_json(run_ok(dir, base)), e = parse_json(run_ok(dir, eu));
  EXPECT_EQ(ga["faces_out"], e["faces_out"]);
  EXPECT_EQ(ga["intersection_points"], e["intersection_points"]);
  EXPECT_EQ(e["predicates"], "euclidean");
}

TEST(CliCut, FailuresWriteNothing) {
  Failure f;
  const fs::path a = f.outputs / "a.glb", b = f.outputs / "b.glb";
  const std::string model = demo_model().string();
  expect_failure(f, {"cut", model, "--plane", "0,1,0,7", "-o", a.string(), b.string()}, 4, "misses the model", a);
  expect_failure(f, {"cut", model, "--plane", "0,0,0,1", "-o", a.string(), b.string()}, 2, "zero vector", a);
  expect_failure(f, {"cut", model, "--plane", "0,1,0", "-o", a.string(), b.string()}, 2, "expected 4", a);
  expect_failure(f, {"cut", model, "--plane", "0,nan,0,1", "-o", a.string(), b.string()}, 2, "not finite", a);
  expect_failure(f, {"cut", model, "--plane", "0,1,0,0.5", "-o", a.string(), b.string(), a.string()}, 2, "-o", a);
  expect_failure(f, {"cut", model, "--plane", "0,1,0,0.5", "--anim", "walk", "-o", a.string(), b.string()}, 2,
                 "no animation 'walk'", a);
  // A clip the model lacks (--time alone on a model without clips is only a warning).
  expect_failure(
      f, {"cut", asset("spot.obj").string(), "--plane", "0,1,0,0.1", "--anim", "0", "-o", a.string(), b.string()}, 2,
      "no animation '0' (the model has 0)", a);
  // The second piece cannot be written: the first must not appear either.
  expect_failure(f,
                 {"cut", model, "--plane", "0,1,0,0.5", "-o", a.string(), (f.outputs / "no/such/dir/b.glb").string()},
                 2, "cannot write", a);
  expect_failure(f, {"cut", (f.inputs / "missing.glb").string(), "--plane", "0,1,0,0.5", "-o", a.string(), b.string()},
                 3, "no such file", a);
}

// One output holds both pieces, as a viewer session keeps them (its replay commands write so).
TEST(CliCut, OneOutputHoldsBothPieces) {
  TempDir dir;
  const fs::path a = dir / "a.glb", b = dir / "b.glb", both = dir / "both.glb";
  const std::string model = demo_model().string();
  run_ok(dir, {"cut", model, "--plane", "0,1,0,0.5", "--cap", "-o", a.string(), b.string()});
  run_ok(dir, {"cut", model, "--plane", "0,1,0,0.5", "--cap", "-o", both.string()});
  const cgamesh::anim::RiggedModel pa = cgamesh::io::load_model(a), pb = cgamesh::io::load_model(b),
                                   joined = cgamesh::io::load_model(both);
  ASSERT_EQ(joined.meshes.size(), pa.meshes.size() + pb.meshes.size());
  EXPECT_EQ(joined.meshes.front().face_count(), pa.meshes.front().face_count());
  EXPECT_EQ(joined.meshes.back().face_count(), pb.meshes.back().face_count());
  EXPECT_EQ(joined.clips.size(), pa.clips.size());
}

/// "X,Y,Z" of a point.
std::string coords(const Eigen::Vector3d& p) {
  return std::to_string(p.x()) + "," + std::to_string(p.y()) + "," + std::to_string(p.z());
}

/// The centre of CesiumMan's torso (at 60% of its height) placed at `time` of its clip.
Eigen::Vector3d torso_centre(double time) {
  const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(demo_model());
  const auto placed =
      cgamesh::surgery::place(m, cgamesh::anim::sample(m.skeleton, m.clips[0], time, cgamesh::anim::BlendMode::format))
          .positions[0];
  return cgamesh_test::torso_centre(placed);
}

/// A drill along z through CesiumMan's torso placed at `time` of its clip: tip, base.
std::array<std::string, 2> torso_drill(double time) {
  const Eigen::Vector3d c = torso_centre(time);
  return {coords(c + Eigen::Vector3d(0, 0, 2)), coords(c - Eigen::Vector3d(0, 0, 2))};
}

// Assimp's skinned quad (a sheet, 200 units wide) drilled with a wall, the tip 50 units below
// it: no tube hangs below the sheet; the rim stays open, named in a warning and counted.
TEST(CliDrill, AWallThroughASheetStaysOpenAndNamesTheRim) {
  TempDir dir;
  const fs::path out = dir / "sheet.obj";
  const Result r = run_ok(dir, {"drill", (fs::path(CGAMESH_TEST_ASSETS) / "quad_skin.glb").string(), "--base", "0,10,0",
                                "--tip", "0,-50,0", "--radius", "5", "--wall", "-o", out.string(), "--json"});
  const nlohmann::json j = parse_json(r);
  EXPECT_EQ(j["rims"].get<int>(), 1) << r;
  EXPECT_EQ(j["walls"].get<int>(), 0);
  EXPECT_EQ(j["open_rims"].get<int>(), 1);
  EXPECT_EQ(j["wall_triangles"].get<int>(), 0);
  int named = 0;
  for (const auto& w : j["warnings"]) named += contains(w.get<std::string>(), "left open: ") ? 1 : 0;
  EXPECT_EQ(named, 1) << r;
  EXPECT_LT(read_obj_vertices(out).col(1).cwiseAbs().maxCoeff(), 1e-3) << "a tube off the sheet";
}

TEST(CliDrill, DrillsTheAnimatedModelThroughAndKeepsTheRig) {
  TempDir dir;
  const fs::path out = dir / "drilled.glb";
  const auto [tip, base] = torso_drill(1.2);
  const Result r = run_ok(dir, {"drill", demo_model().string(), "--tip", tip, "--base", base, "--radius", "0.05",
                                "--anim", "0", "--time", "1.2", "-o", out.string(), "--json"});
  const nlohmann::json j = parse_json(r);
  EXPECT_GE(j["intersection_points"].get<int>(), 12) << r;
  EXPECT_GE(j["new_vertices"].get<int>(), j["intersection_points"].get<int>());
  EXPECT_EQ(j["faces_in"].get<int>(), 4672);
  EXPECT_GT(j["faces_removed"].get<int>(), 0);
  EXPECT_GT(j["faces_out"].get<int>(), 0);
  EXPECT_GE(j["milliseconds"].get<double>(), 0.0);
  EXPECT_GE(j["refinements"].get<int>(), 0);
  EXPECT_EQ(j["wall_triangles"].get<int>(), 0);
  EXPECT_EQ(j["predicates"], "cga");
  EXPECT_TRUE(j["warnings"].is_array());
  const cgamesh::anim::RiggedModel original = cgamesh::io::load_model(demo_model());
  const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(out);
  ASSERT_EQ(m.meshes.size(), 1u);
  EXPECT_FALSE(m.meshes[0].skin.empty());
  EXPECT_EQ(m.clips.size(), original.clips.size());
  EXPECT_EQ(m.meshes[0].face_count(), j["faces_out"].get<int>());
  if (!cgamesh_test::validator_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules is missing";
  std::string log;
  EXPECT_EQ(cgamesh_test::validate_gltf(out, log), 0) << log;
  EXPECT_TRUE(contains(log, " 0 error(s)")) << log;
}

TEST(CliDrill, WallAndEuclideanPredicates) {
  TempDir dir;
  const auto [tip, base] = torso_drill(0.5);
  const std::vector<std::string> args{
      "drill", demo_model().string(),    "--tip", tip, "--base", base, "--radius", "0.03", "--time", "0.5",
      "-o",    (dir / "d.obj").string(), "--json"};
  std::vector<std::string> eu = args, wall = args;
  eu.push_back("--euclidean");
  wall.push_back("--wall");
  const nlohmann::json ga = parse_json(run_ok(dir, args)), e = parse_json(run_ok(dir, eu));
  const nlohmann::json w = parse_json(run_ok(dir, wall));
  EXPECT_EQ(e["predicates"], "euclidean");
  EXPECT_EQ(ga["faces_out"], e["faces_out"]);
  EXPECT_EQ(ga["intersection_points"], e["intersection_points"]);
  EXPECT_EQ(w["intersection_points"], ga["intersection_points"]);
  EXPECT_EQ(w["faces_out"].get<int>(), ga["faces_out"].get<int>() + w["wall_triangles"].get<int>());
  EXPECT_FALSE(read_obj_vertices(dir / "d.obj").rows() == 0);
}

TEST(CliDrill, FailuresWriteNothing) {
  Failure f;
  const fs::path out = f.outputs / "d.glb";
  const std::string model = demo_model().string();
  expect_failure(f, {"drill", model, "--tip", "5,9,1", "--base", "5,9,-1", "--radius", "0.1", "-o", out.string()}, 4,
                 "misses the model", out);
  expect_failure(f, {"drill", model, "--tip", "0,1,1", "--base", "0,1,-1", "--radius", "0", "-o", out.string()}, 2,
                 "radius", out);
  expect_failure(f, {"drill", model, "--tip", "0,1,1", "--base", "0,1,1", "--radius", "0.1", "-o", out.string()}, 2,
                 "same point", out);
  expect_failure(f, {"drill", model, "--tip", "0,1", "--base", "0,1,-1", "--radius", "0.1", "-o", out.string()}, 2,
                 "expected 3", out);
  expect_failure(f, {"drill", model, "--tip", "0,1,1", "--base", "0,1,-1", "-o", out.string()}, 2, "--radius", out);
  expect_failure(f,
                 {"drill", (f.inputs / "missing.glb").string(), "--tip", "0,1,1", "--base", "0,1,-1", "--radius", "0.1",
                  "-o", out.string()},
                 3, "no such file", out);
  // Work that cannot make sense is refused before any is done.
  const std::vector<std::string> drill{"drill",  model,      "--tip", "0,1,1", "--base",
                                       "0,1,-1", "--radius", "0.1",   "-o",    out.string()};
  for (const auto& [option, value] : std::vector<std::pair<std::string, std::string>>{{"--min-rim-points", "1048576"},
                                                                                      {"--max-refinements", "20"},
                                                                                      {"--max-region-faces", "0"},
                                                                                      {"--rest", "somewhere"}}) {
    std::vector<std::string> args = drill;
    args.push_back(option);
    args.push_back(value);
    expect_failure(f, args, 2, option, out);
  }
}

// The rest position rule is an option of every surgery command, and the summary says which.
TEST(CliDrill, RestPositionsExactByDefaultOrParametric) {
  TempDir dir;
  const Eigen::Vector3d c = torso_centre(0.5);
  const std::vector<std::string> args{"drill",    demo_model().string(),
                                      "--time",   "0.5",
                                      "--tip",    coords(c + Eigen::Vector3d(0, 0, 1)),
                                      "--base",   coords(c - Eigen::Vector3d(0, 0, 1)),
                                      "--radius", "0.03",
                                      "-o",       (dir / "d.glb").string(),
                                      "--json"};
  EXPECT_EQ(parse_json(run_ok(dir, args))["rest"], "exact");
  std::vector<std::string> parametric = args;
  parametric.push_back("--rest");
  parametric.push_back("parametric");
  EXPECT_EQ(parse_json(run_ok(dir, parametric))["rest"], "parametric");
}

/// A scalpel stroke over the front of CesiumMan's torso placed at `time`: 3 blade positions
/// (handle in front of the body, tip at the torso's centre line) moving up and sideways, clear
/// of the arms.
std::vector<std::string> torso_stroke(double time) {
  const Eigen::Vector3d centre = torso_centre(time);
  std::vector<std::string> out;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d c = centre + Eigen::Vector3d(-0.015 * i, 0.03 * i, 0);
    out.push_back("--scalpel");
    out.push_back(coords(c + Eigen::Vector3d(0, 0, 2)) + "," + coords(c));
  }
  return out;
}

TEST(CliTear, TearsTheAnimatedModelAndKeepsTheRig) {
  TempDir dir;
  const fs::path out = dir / "torn.glb";
  std::vector<std::string> args{"tear", demo_model().string(), "--anim", "0", "--time", "1.2", "--open", "0.01",
                                "-o",   out.string(),          "--json"};
  for (const std::string& a : torso_stroke(1.2)) args.push_back(a);
  const nlohmann::json j = parse_json(run_ok(dir, args));
  EXPECT_GE(j["intersection_points"].get<int>(), 3);
  EXPECT_EQ(j["path"].size(), j["intersection_points"].get<std::size_t>());
  EXPECT_GE(j["new_vertices"].get<int>(), j["intersection_points"].get<int>());
  EXPECT_EQ(j["faces_in"].get<int>(), 4672);
  EXPECT_GT(j["faces_out"].get<int>(), 4672);
  EXPECT_GT(j["faces_split"].get<int>(), 0);
  EXPECT_GE(j["milliseconds"].get<double>(), 0.0);
  EXPECT_EQ(j["predicates"], "cga");
  const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(out);
  ASSERT_EQ(m.meshes.size(), 1u);
  EXPECT_FALSE(m.meshes[0].skin.empty());
  EXPECT_EQ(m.meshes[0].face_count(), j["faces_out"].get<int>());
  EXPECT_EQ(m.clips.size(), cgamesh::io::load_model(demo_model()).clips.size());
  if (!cgamesh_test::validator_available()) GTEST_SKIP() << "node or tests/oracle/js/node_modules is missing";
  std::string log;
  EXPECT_EQ(cgamesh_test::validate_gltf(out, log), 0) << log;
  EXPECT_TRUE(contains(log, " 0 error(s)")) << log;
}

TEST(CliTear, EuclideanPredicatesGiveTheSamePath) {
  TempDir dir;
  std::vector<std::string> args{"tear", demo_model().string(),    "--time", "0.5",
                                "-o",   (dir / "t.ply").string(), "--json"};
  for (const std::string& a : torso_stroke(0.5)) args.push_back(a);
  std::vector<std::string> eu = args;
  eu.push_back("--euclidean");
  const nlohmann::json ga = parse_json(run_ok(dir, args)), e = parse_json(run_ok(dir, eu));
  EXPECT_EQ(e["predicates"], "euclidean");
  EXPECT_EQ(ga["faces_out"], e["faces_out"]);
  EXPECT_EQ(ga["path"].size(), e["path"].size());
  EXPECT_EQ(read_ply_vertices(dir / "t.ply").rows(), 3273 + ga["new_vertices"].get<int>());
}

TEST(CliTear, FailuresWriteNothing) {
  Failure f;
  const fs::path out = f.outputs / "t.glb";
  const std::string model = demo_model().string();
  const std::string blade = "0,1,2,0,1,0";
  expect_failure(f, {"tear", model, "--scalpel", "5,9,1,5,9,-1", "--scalpel", blade, "-o", out.string()}, 4,
                 "does not meet the surface", out);
  expect_failure(f, {"tear", model, "--scalpel", blade, "-o", out.string()}, 2, "2 or more", out);
  expect_failure(f, {"tear", model, "--scalpel", "0,1,2,0,1", "--scalpel", blade, "-o", out.string()}, 2, "expected 6",
                 out);
  expect_failure(f, {"tear", model, "--scalpel", blade, "--scalpel", blade, "--open", "-1", "-o", out.string()}, 2,
                 "--open", out);
  expect_failure(
      f, {"tear", (f.inputs / "missing.glb").string(), "--scalpel", blade, "--scalpel", blade, "-o", out.string()}, 3,
      "no such file", out);
  // A model whose faces share no vertices, torn along edges it has split already: nothing changes.
  const fs::path wuson = cgamesh_test::assimp_model("X/Testwuson.X");
  if (fs::exists(wuson))
    expect_failure(f,
                   {"tear", wuson.string(), "--anim", "0", "--time", "0.1063", "--scalpel",
                    "0.08496656,1.1456598,1.3966679,0.08581335,1.0641147,1.3391586", "--scalpel",
                    "0.09564638,1.1972935,1.3246605,0.07510358,1.1028301,1.2999157", "--scalpel",
                    "0.092015105,1.2266289,1.2105637,0.073164837,1.1315791,1.1867342", "-o", out.string()},
                   4, "changes nothing", out);
}

// OBJ outputs of cut, drill and tear carry normals, skinned into the pose the tool was placed in
// as `pose` skins them: where a result vertex is an untouched one, its normal is pose's.
TEST(CliSurgery, ObjOutputsCarryTheNormalsOfThePlacedSurface) {
  TempDir dir;
  const std::string model = demo_model().string();
  run_ok(dir, {"pose", model, "--time", "1.2", "-o", (dir / "p.obj").string()});
  const Points px = read_obj_vertices(dir / "p.obj"), pn = read_obj_rows(dir / "p.obj", "vn");
  ASSERT_EQ(pn.rows(), px.rows());
  const auto [tip, base] = torso_drill(1.2);
  std::vector<std::string> tear{"tear", model, "--time", "1.2", "-o", (dir / "t.obj").string()};
  for (const std::string& a : torso_stroke(1.2)) tear.push_back(a);
  run_ok(dir, {"cut", model, "--time", "1.2", "--plane", "0,2,0,1.6", "--cap", "-o", (dir / "a.obj").string(),
               (dir / "b.obj").string()});
  run_ok(dir, {"drill", model, "--time", "1.2", "--tip", tip, "--base", base, "--radius", "0.05", "-o",
               (dir / "d.obj").string()});
  run_ok(dir, tear);
  for (const char* out : {"a.obj", "b.obj", "d.obj", "t.obj"}) {
    SCOPED_TRACE(out);
    const Points x = read_obj_vertices(dir / out), n = read_obj_rows(dir / out, "vn");
    ASSERT_EQ(n.rows(), x.rows());
    Eigen::Index same = 0, untouched = 0;
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
      EXPECT_NEAR(n.row(v).norm(), 1.0, 1e-5) << "vertex " << v;
      bool found = false, agrees = false;
      for (Eigen::Index w = 0; w < px.rows(); ++w) {
        if ((px.row(w) - x.row(v)).norm() > 1e-7) continue;
        found = true;
        agrees = agrees || (pn.row(w) - n.row(v)).norm() < 1e-5;
      }
      untouched += found ? 1 : 0;
      same += agrees ? 1 : 0;
    }
    EXPECT_GT(untouched, x.rows() / 2);
    EXPECT_EQ(same, untouched);
  }
}
}  // namespace

namespace {

TEST(CliTearSoft, TheWoundOpensWithTheTensionAndTheResultAnimates) {
  TempDir dir;
  const std::string model = (fs::path(CGAMESH_DATA_DIR) / "CesiumMan.glb").string();
  const std::vector<std::string> tear{"tear",       model, "--scalpel", "0.01,0.90,2,0.01,0.90,0.06", "--scalpel",
                                      "-0.03,1.0,2,-0.03,1.0,0.06", "--soft", "--gravity", "0,0,0", "--json"};
  const auto opening = [&](const std::string& tension, const std::string& out) {
    std::vector<std::string> args = tear;
    args.insert(args.end(), {"--tension", tension, "-o", (dir / out).string()});
    return parse_json(run_ok(dir, args))["soft"];
  };
  const nlohmann::json closed = opening("0", "closed.glb"), open = opening("0.2", "open.glb");
  EXPECT_LT(closed["mean_opening"].get<double>(), 1e-6);
  EXPECT_GT(open["mean_opening"].get<double>(), 0.005);
  EXPECT_TRUE(open["settled"].get<bool>());
  // The written model animates with the wound open: it validates and has CesiumMan's clip.
  const cgamesh::anim::RiggedModel baked = cgamesh::io::load_model(dir / "open.glb");
  EXPECT_EQ(baked.clips.size(), 1u);
  ASSERT_TRUE(cgamesh_test::validator_available()) << "scripts/install-deps.sh installs the glTF validator";
  std::string log;
  EXPECT_EQ(cgamesh_test::validate_gltf(dir / "open.glb", log), 0) << log;
  // three.js, an independent renderer, shows the wound open all through the clip: the baked
  // file's surface, posed by three.js, stands apart from the closed one's near the wound only.
  ASSERT_TRUE(cgamesh_test::three_available()) << "scripts/install-deps.sh installs three.js";
  const std::vector<double> times{0.0, 0.5, 1.0, 1.5};
  const nlohmann::json a = cgamesh_test::three_reference(dir / "open.glb", times);
  const nlohmann::json b = cgamesh_test::three_reference(dir / "closed.glb", times);
  for (const double t : times) {
    std::ostringstream key;
    key << t;
    const auto& pa = a["meshes"][0]["posed"][key.str()];
    const auto& pb = b["meshes"][0]["posed"][key.str()];
    ASSERT_EQ(pa.size(), pb.size());
    double apart = 0;
    std::size_t still = 0;
    for (std::size_t i = 0; i + 2 < pa.size(); i += 3) {
      double d2 = 0;
      for (std::size_t c = 0; c < 3; ++c) d2 += std::pow(pa[i + c].get<double>() - pb[i + c].get<double>(), 2);
      apart = std::max(apart, std::sqrt(d2));
      still += d2 < 1e-10 ? 1 : 0;
    }
    EXPECT_GT(apart, 0.005) << "t = " << t << ": the wound is open (metres)";
    EXPECT_GT(still, pa.size() / 3 * 8 / 10) << "t = " << t << ": the rest of the body as skinned";
  }
}

TEST(CliTearSoft, BadTissueOptionsWriteNothing) {
  Failure f;
  const std::string model = (fs::path(CGAMESH_DATA_DIR) / "CesiumMan.glb").string();
  const fs::path out = f.outputs / "t.glb";
  const std::vector<std::string> tear{"tear", model, "--scalpel", "0.01,0.90,2,0.01,0.90,0.06", "--scalpel",
                                      "-0.03,1.0,2,-0.03,1.0,0.06", "--soft", "-o", out.string()};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = tear;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  expect_failure(f, with({"--tension", "1"}), 2, "pretension", out);
  expect_failure(f, with({"--stiffness", "0"}), 2, "--stiffness", out);
  expect_failure(f, with({"--gravity", "0,nan,0"}), 2, "--gravity", out);
}

}  // namespace

namespace {

TEST(CliSoft, CutAndDrillSettleTheirWoundsToo) {
  TempDir dir;
  const std::string model = (fs::path(CGAMESH_DATA_DIR) / "CesiumMan.glb").string();
  const nlohmann::json drill = parse_json(run_ok(dir, {"drill", model, "--tip", "0,1.3,-0.5", "--base", "0,1.3,0.5",
                                                       "--radius", "0.04", "--soft", "--json", "-o",
                                                       (dir / "d.glb").string()}));
  EXPECT_GT(drill["soft"]["mean_opening"].get<double>(), 1e-3);
  EXPECT_EQ(drill["soft"]["wound_vertices"].get<int>(), drill["new_vertices"].get<int>());
  const nlohmann::json cut = parse_json(
      run_ok(dir, {"cut", model, "--plane", "0,1,0,0.9", "--soft", "--json", "-o", (dir / "c.glb").string()}));
  EXPECT_GT(cut["soft"]["wound_vertices"].get<int>(), 0);
  EXPECT_EQ(cgamesh::io::load_model(dir / "c.glb").clips.size(), 1u);
  // The baked models are valid glTF (Khronos) and animate: they keep the clip.
  ASSERT_TRUE(cgamesh_test::validator_available()) << "scripts/install-deps.sh installs the glTF validator";
  for (const char* name : {"d.glb", "c.glb"}) {
    std::string log;
    EXPECT_EQ(cgamesh_test::validate_gltf(dir / name, log), 0) << name << "\n" << log;
  }
  EXPECT_EQ(cgamesh::io::load_model(dir / "d.glb").clips.size(), 1u);
  Failure f;
  const fs::path out = f.outputs / "c.glb";
  expect_failure(f, {"cut", model, "--plane", "0,1,0,0.9", "--soft", "--cap", "-o", out.string()}, 2, "--cap", out);
  expect_failure(f, {"cut", model, "--plane", "0,1,0,0.9", "--soft", "-o", out.string(), (f.outputs / "b.glb").string()},
                 2, "one file", out);
}

}  // namespace
