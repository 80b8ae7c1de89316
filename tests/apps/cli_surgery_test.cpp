// The surgery commands run as processes: JSON summaries, outputs that keep skin and clips, and
// failures that exit with the documented code and write nothing (not even one of two pieces).

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "anim/model_fixtures.hpp"
#include "apps/cli_util.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "support/js_oracles.hpp"

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
  const std::vector<std::string> base{"cut", demo_model().string(), "--plane", "1,0.3,0,0.02",
                                      "-o",  (dir / "a.glb").string(), (dir / "b.glb").string(), "--json"};
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
  expect_failure(f, {"cut", model, "--plane", "0,1,0,0.5", "-o", a.string()}, 2, "-o", a);
  expect_failure(f, {"cut", model, "--plane", "0,1,0,0.5", "--anim", "walk", "-o", a.string(), b.string()}, 2,
                 "no animation 'walk'", a);
  expect_failure(f, {"cut", asset("spot.obj").string(), "--plane", "0,1,0,0.1", "--time", "1", "-o", a.string(),
                     b.string()},
                 2, "no animation", a);
  // The second piece cannot be written: the first must not appear either.
  expect_failure(f, {"cut", model, "--plane", "0,1,0,0.5", "-o", a.string(), (f.outputs / "no/such/dir/b.glb").string()},
                 2, "cannot write", a);
  expect_failure(f, {"cut", (f.inputs / "missing.glb").string(), "--plane", "0,1,0,0.5", "-o", a.string(), b.string()},
                 3, "no such file", a);
}

}  // namespace
