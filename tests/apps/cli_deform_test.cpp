// The deform command: the shipped example specs run, identity keys keep the mesh, bad specs
// name the field and exit 2, an unreadable spec exits 3.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "anim/model_fixtures.hpp"
#include "apps/cli_util.hpp"
#include "cgamesh/io/model_loader.hpp"

namespace {

using namespace cgamesh_cli_test;  // NOLINT(google-build-using-namespace)

fs::path spec(const std::string& name) { return fs::path(CGAMESH_DATA_DIR) / "specs" / name; }

fs::path write_spec(const TempDir& dir, const std::string& text) {
  const fs::path p = dir.path() / "spec.json";
  std::ofstream(p) << text;
  return p;
}

TEST(CliDeform, ExampleSpecsRun) {
  TempDir dir;
  for (const char* name : {"cesiumman_bend.json", "cesiumman_handles.json", "cesiumman_ik.json"}) {
    const fs::path out = dir.path() / "out.obj";
    const Result r = run_cli({"deform", cgamesh_test::demo_model().string(), "--spec", spec(name).string(), "-o",
                              out.string(), "--json"},
                             dir.path());
    ASSERT_EQ(r.code, 0) << r;
    const auto summary = nlohmann::json::parse(r.out);
    EXPECT_EQ(summary["vertices"], 3273);
    const Points p = read_obj_vertices(out);
    EXPECT_EQ(p.rows(), 3273);
    EXPECT_TRUE(p.allFinite());
    if (summary.contains("ik")) {
      EXPECT_TRUE(summary["ik"]["reached"].get<bool>());
    }
  }
}

TEST(CliDeform, IdentityKeysKeepTheMesh) {
  TempDir dir;
  const fs::path out = dir.path() / "out.obj";
  const std::string model = cgamesh_test::asset("spot.obj").string();
  const fs::path s = write_spec(dir, R"({"method": "harmonic", "handles": [[0, 1, 2], [500, 501]],
                                         "keys": [{}, {"rotate": [0, 0, 1, 0]}]})");
  ASSERT_EQ(run_cli({"deform", model, "--spec", s.string(), "-o", out.string()}, dir.path()).code, 0);
  const Points a = read_obj_vertices(out);
  const Points b = cgamesh::io::load_model(model).meshes.at(0).positions.cast<double>();
  ASSERT_EQ(a.rows(), b.rows());
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(CliDeform, BadSpecsNameTheField) {
  TempDir dir;
  const std::string model = cgamesh_test::asset("spot.obj").string(), out = (dir.path() / "out.obj").string();
  const std::pair<const char*, const char*> cases[] = {
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "basis": "nurbs"})", "spec.basis"},
      {R"({"method": "twist", "handles": [[0], [1]], "keys": [{}, {}]})", "spec.method"},
      {R"({"method": "spline", "handles": [[0], [99999999]], "keys": [{}, {}]})", "spec.handles[1]"},
      {R"({"method": "spline", "handles": [[0], {"sphere": [0, 0, 0]}], "keys": [{}, {}]})", "spec.handles[1].sphere"},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {"rotate": [0, 0, 0, 10]}]})", "spec.keys[1].rotate"},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {"scale": -1}]})", "spec.keys[1].scale"},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "basis": "quadratic_lagrange"})", "spec.keys"},
      {R"({"method": "harmonic", "handles": [[0], [1]], "keys": [{}]})", "spec.keys"},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "colour": 1})", "spec.colour"},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {})", "not valid JSON"},
  };
  for (const auto& [text, field] : cases) {
    const Result r = run_cli({"deform", model, "--spec", write_spec(dir, text).string(), "-o", out}, dir.path());
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_NE(r.err.find(field), std::string::npos) << r;
  }
  const Result missing = run_cli({"deform", model, "--spec", (dir.path() / "none.json").string(), "-o", out}, dir.path());
  EXPECT_EQ(missing.code, 3) << missing;
  std::filesystem::create_directories(dir.path() / "spec_dir.json");
  const Result directory =
      run_cli({"deform", model, "--spec", (dir.path() / "spec_dir.json").string(), "-o", out}, dir.path());
  EXPECT_EQ(directory.code, 3) << directory;
  EXPECT_NE(directory.err.find("is a directory"), std::string::npos) << directory;
}

}  // namespace
