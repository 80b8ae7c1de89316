// The deform command: the shipped example specs run, identity keys keep the mesh, bad specs
// name the field and exit 2, an unreadable spec exits 3; world space by default for a rigged
// model, a .glb that keeps the rig, parts without a handle.
#include <fstream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/io/mesh_writer.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "apps/cli_util.hpp"
#include "deform/deform_fixtures.hpp"

namespace {

using namespace cgamesh_cli_test;  // NOLINT(google-build-using-namespace)

fs::path spec(const std::string& name) { return fs::path(CGAMESH_DATA_DIR) / "specs" / name; }

fs::path write_spec(const TempDir& dir, const std::string& text) {
  const fs::path p = dir.path() / "spec.json";
  std::ofstream(p) << text;
  return p;
}

/// `spec` (identity keys) deforms spot.obj into itself.
void expect_spot_kept(const TempDir& dir, const std::string& spec) {
  const fs::path out = dir.path() / "same.obj";
  const std::string model = cgamesh_test::asset("spot.obj").string();
  const fs::path s = write_spec(dir, spec);
  ASSERT_EQ(run_cli({"deform", model, "--spec", s.string(), "-o", out.string()}, dir.path()).code, 0);
  const Points a = read_obj_vertices(out);
  const Points b = cgamesh::io::load_model(model).meshes.at(0).positions.cast<double>();
  ASSERT_EQ(a.rows(), b.rows());
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(CliDeform, ExampleSpecsRun) {
  TempDir dir;
  for (const char* name : {"cesiumman_bend.json", "cesiumman_handles.json", "cesiumman_ik.json", "ffd_twist_motor.json",
                           "ffd_twist_classic.json", "cage_motor.json", "cage_classic.json"}) {
    const fs::path out = dir.path() / "out.obj";
    const Result r = run_cli(
        {"deform", cgamesh_test::demo_model().string(), "--spec", spec(name).string(), "-o", out.string(), "--json"},
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
  expect_spot_kept(dir, R"({"method": "harmonic", "handles": [[0, 1, 2], [500, 501]],
                             "keys": [{}, {"rotate": [0, 0, 1, 0]}]})");
}

TEST(CliDeform, BadSpecsNameTheField) {
  TempDir dir;
  const std::string model = cgamesh_test::asset("spot.obj").string(), out = (dir.path() / "out.obj").string();
  const std::pair<const char*, const char*> cases[] = {
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "basis": "nurbs"})", "spec.basis"},
      {R"({"method": "twist", "handles": [[0], [1]], "keys": [{}, {}]})", "spec.method"},
      {R"({"method": "spline", "handles": [[0], [99999999]], "keys": [{}, {}]})", "spec.handles[1]"},
      {R"({"method": "spline", "handles": [[0], {"sphere": [0, 0, 0]}], "keys": [{}, {}]})", "spec.handles[1].sphere"},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {"rotate": [0, 0, 0, 10]}]})",
       "spec.keys[1].rotate"},
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
  const Result missing =
      run_cli({"deform", model, "--spec", (dir.path() / "none.json").string(), "-o", out}, dir.path());
  EXPECT_EQ(missing.code, 3) << missing;
  std::filesystem::create_directories(dir.path() / "spec_dir.json");
  const Result directory =
      run_cli({"deform", model, "--spec", (dir.path() / "spec_dir.json").string(), "-o", out}, dir.path());
  EXPECT_EQ(directory.code, 3) << directory;
  EXPECT_NE(directory.err.find("is a directory"), std::string::npos) << directory;
}

/// Each spec text exits 2 naming its field.
void expect_bad_specs(const TempDir& dir, const std::string& model,
                      std::span<const std::pair<std::string, const char*>> cases) {
  const std::string out = (dir.path() / "out.obj").string();
  for (const auto& [text, field] : cases) {
    const Result r = run_cli({"deform", model, "--spec", write_spec(dir, text).string(), "-o", out}, dir.path());
    EXPECT_EQ(r.code, 2) << text << "\n" << r;
    EXPECT_NE(r.err.find(field), std::string::npos) << r;
  }
}

// Every ffd field: a bad value exits 2 naming it.
TEST(CliDeform, FfdBadSpecsNameTheField) {
  TempDir dir;
  const std::string model = cgamesh_test::asset("spot.obj").string();
  const std::string tail = R"("handles": [[[0, 0, 0]]], "keys": [{}]})";
  const std::pair<std::string, const char*> cases[] = {
      {R"({"method": "ffd", "variant": "soft", )" + tail, "spec.variant"},
      {R"({"method": "ffd", "lattice": 3, )" + tail, "spec.lattice"},
      {R"({"method": "ffd", "lattice": {"resolution": [2, 2, 65]}, )" + tail, "spec.lattice.resolution"},
      {R"({"method": "ffd", "lattice": {"basis": "nurbs"}, )" + tail, "spec.lattice.basis"},
      {R"({"method": "ffd", "lattice": {"basis": "bspline", "ends": 1}, )" + tail, "spec.lattice.ends"},
      {R"({"method": "ffd", "lattice": {"margin": "wide"}, )" + tail, "spec.lattice.margin"},
      {R"({"method": "ffd", "lattice": {"box": {"size": [1, 1, 1]}}, )" + tail, "spec.lattice.box"},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0, "a"], "size": [1, 1, 1]}}, )" + tail,
       "spec.lattice.box.origin"},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0, 0], "size": [1, -1, 1]}}, )" + tail,
       "spec.lattice.box.size"},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0, 0], "size": [1, 1, 1], "rotate": [1, 0, 0]}}, )" +
           tail,
       "spec.lattice.box.rotate"},
      {R"({"method": "ffd", "handles": [[[0, 3, 0]]], "keys": [{}]})", "spec.handles[0]"},
      {R"({"method": "ffd", "handles": [[5, 6]], "keys": [{}]})", "spec.handles[0]"},
      {R"({"method": "ffd", "handles": [{"sphere": [1e6, 0, 0, 1]}], "keys": [{}]})", "spec.handles[0]"},
      {R"({"method": "ffd", "handles": [[[0, 0, 0]]], "keys": []})", "spec.keys"},
      {R"({"method": "ffd", "degree": 2, )" + tail, "spec.degree"},
      {R"({"method": "spline", "variant": "motor", "handles": [[0], [1]], "keys": [{}, {}]})", "spec.variant"},
  };
  expect_bad_specs(dir, model, cases);
}

// Every arap field: a bad value exits 2 naming it.
TEST(CliDeform, ArapBadSpecsNameTheField) {
  TempDir dir;
  const std::string model = cgamesh_test::asset("spot.obj").string();
  const std::string tail = R"("handles": [[0], [1]], "keys": [{}, {}]})";
  const std::pair<std::string, const char*> cases[] = {
      {R"({"method": "arap", "weights": "mean_value", )" + tail, "spec.weights"},
      {R"({"method": "arap", "weights": 1, )" + tail, "spec.weights"},
      {R"({"method": "arap", "energy": "rims", )" + tail, "spec.energy"},
      {R"({"method": "arap", "local_step": "qr", )" + tail, "spec.local_step"},
      {R"({"method": "arap", "iterations": 0, )" + tail, "spec.iterations"},
      {R"({"method": "arap", "iterations": 2.5, )" + tail, "spec.iterations"},
      {R"({"method": "arap", "iterations": 10000000000, )" + tail, "spec.iterations"},
      {R"({"method": "arap", "tolerance": -0.1, )" + tail, "spec.tolerance"},
      {R"({"method": "arap", "tolerance": "small", )" + tail, "spec.tolerance"},
      {R"({"method": "arap", "degree": 2, )" + tail, "spec.degree"},
      {R"({"method": "arap", "handles": [[0], [99999999]], "keys": [{}, {}]})", "spec.handles[1]"},
      {R"({"method": "arap", "handles": [[0], [1]], "keys": [{}]})", "spec.keys"},
      {R"({"method": "harmonic", "iterations": 3, )" + tail, "spec.iterations"},
      {R"({"method": "spline", "energy": "spokes", )" + tail, "spec.energy"},
  };
  expect_bad_specs(dir, model, cases);
}

// The example ARAP bends run and move the mesh; --json reports the energy per iteration, never
// increasing; identity keys keep the mesh with every option set.
TEST(CliDeform, ArapExampleSpecsRunAndReportTheEnergy) {
  TempDir dir;
  for (const auto& [asset, name] :
       {std::pair{"cow.obj", "arap_cow_bend.json"}, std::pair{"arm_16k.ply", "arap_arm_bend.json"}}) {
    const fs::path out = dir.path() / "out.obj";
    const Result r = run_cli(
        {"deform", cgamesh_test::asset(asset).string(), "--spec", spec(name).string(), "-o", out.string(), "--json"},
        dir.path());
    ASSERT_EQ(r.code, 0) << r;
    const auto summary = nlohmann::json::parse(r.out);
    EXPECT_EQ(summary["method"], "arap");
    const auto energies = summary["arap"]["energies"].get<std::vector<double>>();
    EXPECT_EQ(summary["arap"]["iterations"], 10);
    ASSERT_EQ(energies.size(), 11u);
    for (std::size_t k = 1; k < energies.size(); ++k) EXPECT_LE(energies[k], energies[k - 1] * (1 + 1e-12)) << name;
    const Points p = read_obj_vertices(out);
    const Points rest = cgamesh::io::load_model(cgamesh_test::asset(asset)).meshes.at(0).positions.cast<double>();
    ASSERT_EQ(p.rows(), rest.rows());
    EXPECT_TRUE(p.allFinite());
    EXPECT_GT((p - rest).cwiseAbs().maxCoeff(), 0.1) << name;  // it moved
  }
  // Identity keys keep the mesh (the rest shape has zero energy).
  expect_spot_kept(dir, R"({"method": "arap", "handles": [[0, 1, 2], [500, 501]], "keys": [{}, {}],
                             "local_step": "svd", "energy": "spokes", "weights": "clamped_cotangent",
                             "iterations": 3, "tolerance": 0.01})");
}

// Every cage field: a bad value exits 2 naming it; a missing cage exits 3; the coordinates cache
// is written once and read back.
TEST(CliDeform, CageBadSpecsNameTheFieldAndTheCacheIsReused) {
  TempDir dir;
  const std::string model = cgamesh_test::demo_model().string(), out = (dir.path() / "out.obj").string();
  fs::copy_file(fs::path(CGAMESH_DATA_DIR) / "cesiumman_cage.obj", dir.path() / "cage.obj");
  std::ofstream(dir.path() / "tetra.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  std::ofstream(dir.path() / "open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n";
  const std::string head = R"({"method": "cage", "cage": "cage.obj", )";
  const std::string tail = R"("handles": [[0]], "keys": [{}]})";
  const std::pair<std::string, const char*> cases[] = {
      {head + R"("resolution": 1000, )" + tail, "spec.resolution"},
      {head + R"("max_weights": 0, )" + tail, "spec.max_weights"},
      {head + R"("coordinates": 5, )" + tail, "spec.coordinates"},
      {head + R"("variant": "soft", )" + tail, "spec.variant"},
      {head + R"("deformed_cage": "tetra.obj", )" + tail, "spec.deformed_cage"},
      {head + R"("variant": "classic", "deformed_cage": "tetra.obj"})", "spec.deformed_cage"},
      {head + R"("lattice": {}, )" + tail, "spec.lattice"},
      {R"({"method": "cage", "cage": "", )" + tail, "spec.cage"},
      {R"({"method": "cage", "cage": "open.obj", )" + tail, "spec.cage"},
      {R"({"method": "cage", "cage": "tetra.obj", )" + tail, "spec.cage"},
      {head + R"("handles": [[60]], "keys": [{}]})", "spec.handles[0]"},
      {head + R"("handles": [{"sphere": [9, 9, 9, 0.1]}], "keys": [{}]})", "spec.handles[0]"},
      {head + R"("handles": [[0]], "keys": []})", "spec.keys"},
  };
  for (const auto& [text, field] : cases) {
    const Result r = run_cli({"deform", model, "--spec", write_spec(dir, text).string(), "-o", out}, dir.path());
    EXPECT_EQ(r.code, 2) << text << "\n" << r;
    EXPECT_NE(r.err.find(field), std::string::npos) << r;
  }
  for (const char* text :
       {R"({"method": "cage", "cage": "none.obj", "handles": [[0]], "keys": [{}]})",
        R"({"method": "cage", "variant": "classic", "cage": "cage.obj", "deformed_cage": "none.obj"})"}) {
    const Result r = run_cli({"deform", model, "--spec", write_spec(dir, text).string(), "-o", out}, dir.path());
    EXPECT_EQ(r.code, 3) << text << "\n" << r;
    EXPECT_NE(r.err.find("none.obj"), std::string::npos) << r;
  }

  const std::string cached = head + R"("resolution": 24, "coordinates": "c.npy", "handles": [[0, 1]],
      "keys": [{"translate": [0, 0.05, 0]}]})";
  const fs::path first = dir.path() / "first.obj", second = dir.path() / "second.obj";
  ASSERT_EQ(
      run_cli({"deform", model, "--spec", write_spec(dir, cached).string(), "-o", first.string()}, dir.path()).code, 0);
  ASSERT_TRUE(fs::exists(dir.path() / "c.npy"));
  const auto written = fs::last_write_time(dir.path() / "c.npy");
  ASSERT_EQ(
      run_cli({"deform", model, "--spec", write_spec(dir, cached).string(), "-o", second.string()}, dir.path()).code,
      0);
  EXPECT_EQ(fs::last_write_time(dir.path() / "c.npy"), written);
  EXPECT_EQ(read_obj_vertices(first), read_obj_vertices(second));
  // A cache of another mesh is refused (not overwritten), naming the field.
  const std::string other = R"({"method": "cage", "space": "mesh", "cage": "tetra.obj", "coordinates": "c.npy",
      "handles": [[0]], "keys": [{}]})";
  const Result stale = run_cli(
      {"deform", cgamesh_test::asset("spot.obj").string(), "--spec", write_spec(dir, other).string(), "-o", out},
      dir.path());
  EXPECT_EQ(stale.code, 3) << stale;
  EXPECT_NE(stale.err.find("spec.coordinates"), std::string::npos) << stale;
}

// Both variants of the example twist run to a .glb with the rig; identity keys keep the mesh.
TEST(CliDeform, FfdWritesGlbAndIdentityKeepsTheMesh) {
  TempDir dir;
  const fs::path glb = dir.path() / "twist.glb";
  const Result r = run_cli({"deform", cgamesh_test::demo_model().string(), "--spec",
                            spec("ffd_twist_motor.json").string(), "-o", glb.string(), "--json"},
                           dir.path());
  ASSERT_EQ(r.code, 0) << r;
  const auto summary = nlohmann::json::parse(r.out);
  EXPECT_EQ(summary["method"], "ffd");
  EXPECT_EQ(summary["control_points"], 16);
  EXPECT_EQ(summary["handle_control_points"], nlohmann::json::parse("[4, 4, 4]"));
  const auto model = cgamesh::io::load_model(glb);
  EXPECT_GT(model.skeleton.size(), 0U);
  EXPECT_FALSE(model.clips.empty());

  const fs::path out = dir.path() / "out.obj";
  const std::string spot = cgamesh_test::asset("spot.obj").string();
  for (const char* variant : {"classic", "motor"}) {
    const fs::path s = write_spec(dir, std::string(R"({"method": "ffd", "variant": ")") + variant + R"(",
        "lattice": {"resolution": [3, 3, 3], "basis": "bspline"},
        "handles": [[[1, 1, 1]], {"box": [-1e3, -1e3, -1e3, 1e3, 1e3, 1e3]}], "keys": [{}, {"rotate": [0, 0, 1, 0]}]})");
    ASSERT_EQ(run_cli({"deform", spot, "--spec", s.string(), "-o", out.string(), "--force"}, dir.path()).code, 0);
    const Points a = read_obj_vertices(out);
    const Points b = cgamesh::io::load_model(spot).meshes.at(0).positions.cast<double>();
    ASSERT_EQ(a.rows(), b.rows());
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-5) << variant;
  }
}

// World space is the default for a rigged model; a .glb keeps skin, skeleton and clips, and its
// bind pose is the deformed shape the .obj holds.
TEST(CliDeform, GltfKeepsTheRigAndReposesToTheObj) {
  TempDir dir;
  const fs::path s = spec("cesiumman_handles.json");  // world space, the default
  const fs::path obj = dir.path() / "out.obj", glb = dir.path() / "out.glb";
  const std::string model = cgamesh_test::demo_model().string();
  const Result r = run_ok(dir, {"deform", model, "--spec", s.string(), "-o", obj.string(), "--json"});
  EXPECT_EQ(parse_json(r)["pose"]["space"], "world");
  run_ok(dir, {"deform", model, "--spec", s.string(), "-o", glb.string()});
  const auto original = cgamesh::io::load_model(model);
  const auto back = cgamesh::io::load_model(glb);
  ASSERT_EQ(back.meshes.size(), 1U);
  EXPECT_EQ(back.clips.size(), original.clips.size());
  EXPECT_EQ(back.skeleton.size(), original.skeleton.size());
  EXPECT_FALSE(back.meshes[0].skin.empty());
  const Points reposed = cgamesh::deform::rest_positions(back, cgamesh::deform::DeformSpace::world)[0].cast<double>();
  const Points written = read_obj_vertices(obj);
  EXPECT_LT(max_distance(reposed, written), 1e-4 * diagonal(written));
  const Points rest = cgamesh::deform::rest_positions(original, cgamesh::deform::DeformSpace::world)[0].cast<double>();
  EXPECT_GT(max_distance(rest, written), 1e-2 * diagonal(written));
}

TEST(CliDeform, SpaceIsMeshForStaticModelsAndWhenTheSpecSaysSo) {
  TempDir dir;
  const fs::path out = dir.path() / "out.obj";
  const fs::path s = write_spec(dir, R"({"method": "harmonic", "handles": [[0, 1, 2], [500, 501]], "keys": [{}, {}]})");
  const Result plain = run_ok(
      dir, {"deform", cgamesh_test::asset("spot.obj").string(), "--spec", s.string(), "-o", out.string(), "--json"});
  EXPECT_EQ(parse_json(plain)["pose"]["space"], "mesh");
  const fs::path in_mesh =
      write_spec(dir, R"({"method": "harmonic", "space": "mesh", "handles": [[0], [1500]], "keys": [{}, {}]})");
  const Result rigged = run_ok(
      dir, {"deform", cgamesh_test::demo_model().string(), "--spec", in_mesh.string(), "-o", out.string(), "--json"});
  EXPECT_EQ(parse_json(rigged)["pose"]["space"], "mesh");
  const Result example = run_ok(dir, {"deform", cgamesh_test::demo_model().string(), "--spec",
                                      spec("cesiumman_bend.json").string(), "-o", out.string(), "--json"});
  EXPECT_EQ(parse_json(example)["pose"]["space"], "world");
  const Result bad =
      run_cli({"deform", cgamesh_test::asset("spot.obj").string(), "--spec",
               write_spec(dir, R"({"method": "harmonic", "space": "screen", "handles": [[0]], "keys": [{}]})").string(),
               "-o", out.string()},
              dir.path());
  EXPECT_EQ(bad.code, 2) << bad;
  EXPECT_TRUE(contains(bad.err, "spec.space")) << bad;
}

// A second cylinder with no handle vertex follows the nearest handle's key, or stays.
TEST(CliDeform, FreePartsMoveWithTheNearestHandleOrStay) {
  TempDir dir;
  const cgamesh::mesh::Mesh one = cgamesh_deform_test::cylinder(16, 6);
  cgamesh::mesh::Mesh two;
  two.positions.resize(2 * one.vertex_count(), 3);
  two.positions << one.positions, one.positions.rowwise() + Eigen::RowVector3f(0, 0, 3);
  two.faces.resize(2 * one.face_count(), 3);
  two.faces << one.faces, one.faces.array() + static_cast<int>(one.vertex_count());
  const fs::path input = dir.path() / "two.obj";
  cgamesh::io::write_mesh(std::span<const cgamesh::mesh::Mesh>(&two, 1),
                          std::span<const cgamesh::mesh::RowMatrixXf<3>>(&two.positions, 1), input);
  const Points rest = cgamesh::io::load_model(input).meshes.at(0).positions.cast<double>();
  const std::string base = R"({"method": "harmonic", "handles": [{"box": [-2, -2, -1, 2, 2, 0.01]},
      {"box": [-2, -2, 0.99, 2, 2, 1.01]}], "keys": [{}, {"translate": [0.5, 0, 0]}])";
  for (const std::string free : {"nearest", "keep"}) {
    const fs::path out = dir.path() / ("out_" + free + ".obj");
    const Result r = run_ok(
        dir, {"deform", input.string(), "--spec",
              write_spec(dir, base + R"(, "free_parts": ")" + free + "\"}").string(), "-o", out.string(), "--json"});
    EXPECT_EQ(parse_json(r)["free_vertices"], (rest.col(2).array() > 2).count());
    const Points p = read_obj_vertices(out);
    ASSERT_EQ(p.rows(), rest.rows());
    for (Eigen::Index v = 0; v < p.rows(); ++v) {
      if (rest(v, 2) > 2) {
        EXPECT_NEAR(p(v, 0), rest(v, 0) + (free == "nearest" ? 0.5 : 0.0), 1e-5) << free << v;
      }
    }
  }
}

// An OBJ of a deformation carries normals: those of the rigged .glb result, posed in its bind
// pose (the bent mesh's reshaped normals, in world space like its positions).
TEST(CliDeform, ObjNormalsAreThoseOfTheRiggedResultAtRest) {
  TempDir dir;
  const std::string model = cgamesh_test::demo_model().string(), s = spec("cesiumman_bend.json").string();
  const fs::path obj = dir.path() / "bent.obj", glb = dir.path() / "bent.glb", posed = dir.path() / "posed.obj";
  ASSERT_EQ(run_cli({"deform", model, "--spec", s, "-o", obj.string()}, dir.path()).code, 0);
  ASSERT_EQ(run_cli({"deform", model, "--spec", s, "-o", glb.string()}, dir.path()).code, 0);
  ASSERT_EQ(run_cli({"pose", glb.string(), "--bind-pose", "-o", posed.string()}, dir.path()).code, 0);
  const Points x = read_obj_vertices(obj), n = read_obj_rows(obj, "vn");
  const Points px = read_obj_vertices(posed), pn = read_obj_rows(posed, "vn");
  ASSERT_EQ(n.rows(), x.rows());
  ASSERT_EQ(px.rows(), x.rows());
  EXPECT_LT((x - px).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT((n - pn).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT((n.rowwise().norm().array() - 1).abs().maxCoeff(), 1e-5);
  const Points rest =
      read_obj_rows((run_ok(dir, {"pose", model, "--bind-pose", "-o", (dir / "r.obj").string()}), dir / "r.obj"), "vn");
  EXPECT_GT((n - rest).cwiseAbs().maxCoeff(), 0.1) << "the bend turns some normals";
}
}  // namespace
