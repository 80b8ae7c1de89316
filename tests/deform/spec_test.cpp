#include "cgamesh/deform/spec.hpp"
#include "cgamesh/deform/bound_deformer.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/deform/harmonic_handles.hpp"
#include "cgamesh/deform/spline_deform.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/normals.hpp"
#include "cgamesh/mesh/weld.hpp"

#include "anim/model_fixtures.hpp"
#include "deform/deform_fixtures.hpp"
#include "support/temp_dir.hpp"

namespace {

using namespace cgamesh;              // NOLINT(google-build-using-namespace)
using namespace cgamesh_deform_test;  // NOLINT(google-build-using-namespace)
using deform::BoundDeformer;
using deform::DeformSpace;
using deform::DeformSpec;
using deform::parse_spec;
using Versor = cga::Versor<double>;

std::string message_of(const std::string& text) {
  try {
    (void)parse_spec(text, "test.json");
  } catch (const InvalidInputError& e) {
    return e.what();
  }
  return "(no error)";
}

anim::RiggedModel model_of(mesh::Mesh m) {
  anim::RiggedModel model;
  model.meshes.push_back(std::move(m));
  return model;
}

/// The key versor as the CLI built it before the spec moved into the library.
Versor reference_key(const Eigen::Vector3d& axis, double degrees, const Eigen::Vector3d& center,
                     const Eigen::Vector3d& translate, double scale) {
  const auto r = cga::rotor(axis, degrees * std::numbers::pi / 180.0);
  return cga::project<cga::mask::versor>(cga::translator(Eigen::Vector3d(center + translate)) *
                                         cga::similarity(Eigen::Vector3d(Eigen::Vector3d::Zero()), r, scale) *
                                         cga::translator(Eigen::Vector3d(-center)));
}

double max_difference(const mesh::RowMatrixXf<3>& a, const mesh::RowMatrixXf<3>& b) {
  EXPECT_EQ(a.rows(), b.rows());
  return a.rows() == b.rows() ? static_cast<double>((a - b).cwiseAbs().maxCoeff()) : INFINITY;
}

TEST(DeformSpecParse, ErrorsNameTheField) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "basis": "nurbs"})", "spec.basis: "},
      {R"({"method": "twist", "handles": [[0], [1]], "keys": [{}, {}]})", "spec.method: "},
      {R"({"handles": [[0], [1]], "keys": [{}, {}]})", "spec.method: "},
      {R"({"method": "spline", "handles": [[0], [-1]], "keys": [{}, {}]})", "spec.handles[1]: "},
      {R"({"method": "spline", "handles": [[0], {"sphere": [0, 0, 0]}], "keys": [{}, {}]})",
       "spec.handles[1].sphere: "},
      {R"({"method": "spline", "handles": [{"box": [0, 0, 0, 1, 1, "x"]}, [1]], "keys": [{}, {}]})",
       "spec.handles[0].box: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {"rotate": [0, 0, 0, 10]}]})",
       "spec.keys[1].rotate: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {"scale": -1}]})", "spec.keys[1].scale: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {"spin": 1}]})", "spec.keys[1].spin: "},
      {R"({"method": "harmonic", "handles": [[0]], "ik": {"joints": [], "target": [0, 0, 0]}})",
       "spec.ik: not a field of the harmonic method (spline takes it)"},
      {R"({"method": "harmonic", "handles": [[0]], "keys": [{}], "basis": "linear"})",
       "spec.basis: not a field of the harmonic method (spline takes it)"},
      {R"({"method": "arap", "handles": [[0]], "keys": [{}], "variant": "motor"})",
       "spec.variant: not a field of the arap method (ffd and cage take it)"},
      {R"({"method": "ffd", "handles": [], "keys": [], "weights": "cotangent"})",
       "spec.weights: not a field of the ffd method (spline, harmonic and arap take it)"},
      {R"({"method": "spline", "handles": [[0], [1]], "ik": {"joints": [[0, 0, 0]], "target": [0, 0, 1], "pole": 1}})",
       "spec.ik.pole: unknown field"},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "space": "camera"})", "spec.space: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "free_parts": "drop"})", "spec.free_parts: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "mesh": -1})", "spec.mesh: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "degree": 0})", "spec.degree: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "colour": 1})", "spec.colour: "},
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {})", "spec test.json is not valid JSON"},
      {R"([1, 2])", "spec test.json: expected a JSON object"},
  };
  for (const auto& [text, field] : cases)
    EXPECT_NE(message_of(text).find(field), std::string::npos) << message_of(text);
}

TEST(DeformSpecParse, ReadsTheArapFields) {
  const DeformSpec s = parse_spec(R"({"method": "arap", "handles": [[0], [1]], "keys": [{}, {}],
      "weights": "clamped_cotangent", "energy": "spokes", "local_step": "svd", "iterations": 25, "tolerance": 0.001})",
                                  "inline");
  EXPECT_EQ(s.method(), deform::DeformMethod::arap);
  const deform::ArapOptions& a = std::get<deform::ArapSpec>(s.fields).options;
  EXPECT_EQ(a.weights, deform::LaplacianWeights::clamped_cotangent);
  EXPECT_EQ(a.energy, deform::ArapEnergy::spokes);
  EXPECT_EQ(a.local_step, deform::ArapLocalStep::svd);
  EXPECT_EQ(a.iterations, 25);
  EXPECT_EQ(a.tolerance, 0.001);
  const DeformSpec d = parse_spec(R"({"method": "arap", "handles": [[0]], "keys": [{}]})", "inline");
  const deform::ArapOptions& b = std::get<deform::ArapSpec>(d.fields).options;
  EXPECT_EQ(b.weights, deform::LaplacianWeights::cotangent);  // not the harmonic default
  EXPECT_EQ(b.energy, deform::ArapEnergy::spokes_and_rims);
  EXPECT_EQ(b.local_step, deform::ArapLocalStep::rotor);
  EXPECT_EQ(b.iterations, 10);
  EXPECT_EQ(b.tolerance, 0);
}

TEST(DeformSpecParse, ReadsEveryField) {
  const DeformSpec s = parse_spec(R"({"method": "spline", "mesh": 1, "space": "world", "weights": "cotangent",
      "handles": [[3, 4], {"sphere": [1, 2, 3, 0.5]}], "basis": "linear", "free_parts": "keep",
      "keys": [{}, {"rotate": [0, 1, 0, 30], "translate": [1, 2, 3], "center": [0, 0, 1], "scale": 2}]})",
                                  "inline");
  EXPECT_EQ(s.method(), deform::DeformMethod::spline);
  const auto& spline = std::get<deform::SplineSpec>(s.fields);
  EXPECT_EQ(s.mesh, 1);
  EXPECT_EQ(s.space, DeformSpace::world);
  EXPECT_EQ(spline.weights, deform::LaplacianWeights::cotangent);
  EXPECT_EQ(spline.basis, deform::SplineBasis::linear);
  EXPECT_EQ(s.free_parts(), deform::FreeParts::keep);
  ASSERT_EQ(s.handles.size(), 2U);
  EXPECT_EQ(s.handles[0].indices, (std::vector<int>{3, 4}));
  EXPECT_EQ(s.handles[1].kind, deform::HandleSelection::Kind::sphere);
  EXPECT_EQ(s.handles[1].shape[3], 0.5);
  ASSERT_EQ(s.keys.size(), 2U);
  EXPECT_EQ(s.keys[1].degrees, 30);
  EXPECT_EQ(s.keys[1].scale, 2);
  EXPECT_EQ(s.keys[1].center, Eigen::Vector3d(0, 0, 1));
  EXPECT_FALSE(parse_spec(R"({"method": "harmonic", "handles": [[0]], "keys": [{}]})", "x").space.has_value());
}

TEST(DeformSpecParse, ReadSpecReportsUnreadableFiles) {
  cgamesh_test::TempDir dir;
  EXPECT_THROW((void)deform::read_spec(dir.path() / "none.json"), FileError);
  EXPECT_THROW((void)deform::read_spec(dir.path()), FileError);
}

// The library's bind/apply gives what the CLI computed before the spec moved: the same
// selection, key versors and bind calls.
TEST(DeformSpecBind, EqualsTheDirectBind) {
  const anim::RiggedModel model = io::load_model(cgamesh_test::asset("spot.obj"));
  const mesh::Mesh& m = model.meshes[0];
  const DeformSpec harmonic = parse_spec(R"({"method": "harmonic", "handles": [[0, 1, 2], [500, 501]],
      "keys": [{}, {"rotate": [0, 0, 1, 40], "center": [0.1, 0.2, 0.3], "translate": [0, 0.1, 0], "scale": 1.1}]})",
                                         "inline");
  const BoundDeformer bound(harmonic, model);
  EXPECT_EQ(bound.space(), DeformSpace::mesh);
  const std::vector<Versor> keys = {Versor(cga::basis_blade<double, cga::blade::scalar>()),
                                    reference_key({0, 0, 1}, 40, {0.1, 0.2, 0.3}, {0, 0.1, 0}, 1.1)};
  const std::vector<Versor> rest(2, Versor(cga::basis_blade<double, cga::blade::scalar>()));
  // Indices are the OBJ's `v` lines (from 0): each selects every loaded vertex split from it.
  // Handles list them in the order given, the copies of one in ascending order.
  std::vector<std::vector<int>> handles(2);
  for (const auto& [h, file_vertices] : {std::pair{0, std::vector{0, 1, 2}}, std::pair{1, std::vector{500, 501}}})
    for (const int f : file_vertices)
      for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
        if (m.file_index[v] == f) handles[static_cast<std::size_t>(h)].push_back(static_cast<int>(v));
  ASSERT_GE(handles[0].size(), 3u);
  ASSERT_GE(handles[1].size(), 2u);
  EXPECT_EQ(bound.handles(), handles);
  mesh::RowMatrixXf<3> expected;
  deform::bind_harmonic_handles(m, handles, rest).deform(keys, expected);
  EXPECT_EQ(max_difference(bound.apply(bound.keys()), expected), 0.0);
  EXPECT_TRUE(bound.free_vertices().empty());

  const DeformSpec spline = parse_spec(R"({"method": "spline", "basis": "linear", "handles": [[0, 1, 2], [500, 501]],
      "keys": [{}, {"rotate": [1, 0, 0, 60], "center": [0, 0.5, 0]}]})",
                                       "inline");
  deform::SplineOptions options;
  options.basis = deform::SplineBasis::linear;
  const std::vector<Versor> spline_keys = {keys[0], reference_key({1, 0, 0}, 60, {0, 0.5, 0}, {0, 0, 0}, 1)};
  deform::bind_spline(m, handles[0], handles[1], rest, options).deform(spline_keys, expected);
  EXPECT_EQ(max_difference(BoundDeformer(spline, model).apply(spline_keys), expected), 0.0);
}

// A viewer moves one key per frame: the bind is reused and apply() keeps no state.
TEST(DeformSpecBind, KeysChangeBetweenFrames) {
  const anim::RiggedModel model = model_of(cylinder(24, 11));
  const DeformSpec s = parse_spec(R"({"method": "harmonic", "handles": [{"box": [-2, -2, -1, 2, 2, 0.01]},
      {"box": [-2, -2, 0.99, 2, 2, 2]}], "keys": [{}, {"rotate": [1, 0, 0, 30], "center": [0, 0, 1]}]})",
                                  "inline");
  const BoundDeformer bound(s, model);
  ASSERT_EQ(bound.handles().size(), 2U);
  EXPECT_EQ(bound.handles()[0].size(), 24U);
  EXPECT_EQ(bound.handles()[1].size(), 24U);
  const mesh::RowMatrixXf<3> first = bound.apply(bound.keys());
  std::vector<Versor> keys = bound.keys();
  deform::KeyTransform moved;
  moved.translate = {0, 0, 0.5};
  keys[1] = moved.versor();
  const mesh::RowMatrixXf<3> second = bound.apply(keys);
  for (const int v : bound.handles()[1]) EXPECT_NEAR(second(v, 2), model.meshes[0].positions(v, 2) + 0.5, 1e-5);
  EXPECT_EQ(max_difference(bound.apply(bound.keys()), first), 0.0);
  const std::vector<Versor> identity(2, Versor(cga::basis_blade<double, cga::blade::scalar>()));
  EXPECT_LT(max_difference(bound.apply(identity), model.meshes[0].positions), 1e-6);
}

/// What binding the spec `text` to `model` throws (InvalidInputError), or "(no error)".
std::string bind_error(const std::string& text, const anim::RiggedModel& model) {
  try {
    (void)BoundDeformer(parse_spec(text, "inline"), model);
  } catch (const InvalidInputError& e) {
    return std::string(e.what());
  }
  return std::string("(no error)");
}

TEST(DeformSpecBind, MeshErrorsNameTheField) {
  const anim::RiggedModel model = model_of(cylinder(12, 5));
  const auto message = [&](const std::string& text) { return bind_error(text, model); };
  EXPECT_NE(message(R"({"method": "harmonic", "mesh": 1, "handles": [[0]], "keys": [{}]})").find("spec.mesh: "),
            std::string::npos);
  // Counts the method or basis cannot take, named after the selections (as the CLI always did).
  const std::pair<const char*, const char*> counts[] = {
      {R"({"method": "spline", "handles": [[0], [1]], "keys": [{}, {}], "basis": "quadratic_lagrange"})",
       "spec.keys: "},
      {R"({"method": "spline", "handles": [[0], [1], [2]], "keys": [{}, {}]})", "spec.handles: "},
      {R"({"method": "harmonic", "handles": [[0], [1]], "keys": [{}]})", "spec.keys: "},
      {R"({"method": "spline", "handles": [[0], [1]], "ik": {"joints": [[0, 0, 0]], "target": [0, 0, 1]}})",
       "spec.ik.joints: "},
      {R"({"method": "spline", "handles": [[0], [99]], "keys": [{}, {}]})", "spec.handles[1]: "},
  };
  for (const auto& [text, field] : counts) EXPECT_NE(message(text).find(field), std::string::npos) << message(text);
  EXPECT_NE(message(R"({"method": "harmonic", "handles": [[0], [60]], "keys": [{}, {}]})").find("spec.handles[1]: "),
            std::string::npos);
  EXPECT_NE(message(R"({"method": "harmonic", "handles": [[0], {"sphere": [9, 9, 9, 1]}], "keys": [{}, {}]})")
                .find("spec.handles[1]: selects no vertex"),
            std::string::npos);
  EXPECT_NE(message(R"({"method": "harmonic", "handles": [[0, 1], [1, 2]], "keys": [{}, {}]})")
                .find("spec.handles[1]: vertex 1"),
            std::string::npos);
}

// Issue #33 item 7: one rule for every point and length a spec gives, as for tools and joint
// edits: no farther than io::kMaxReach (10^6) mesh sizes (an IK target of 1e308 was accepted).
TEST(DeformSpecBind, EveryPointIsWithinReachOfTheMesh) {
  const anim::RiggedModel model = model_of(cylinder(12, 5));
  const auto message = [&](const std::string& text) { return bind_error(text, model); };
  const std::string far = "1e308", two = R"("handles": [[0], [1]], )", linear = R"("basis": "linear", )";
  const std::pair<std::string, std::string> cases[] = {
      {R"({"method": "spline", )" + linear + two + R"("ik": {"joints": [[0, 0, 0], [0, 0, 1]], "target": [0, 0, )" + far + "]}}",
       "spec.ik.target: lies 1e+308 from the mesh, more than 1e+06 times the mesh's size"},
      {R"({"method": "spline", )" + linear + two + R"("ik": {"joints": [[0, 0, 0], [0, )" + far +
           R"(, 1]], "target": [0, 0, 1]}})",
       "spec.ik.joints[1]: "},
      {R"({"method": "harmonic", )" + two + R"("keys": [{}, {"translate": [)" + far + ", 0, 0]}]}",
       "spec.keys[1].translate: "},
      {R"({"method": "harmonic", )" + two + R"("keys": [{"center": [0, 0, -)" + far + "]}, {}]}",
       "spec.keys[0].center: "},
      {R"({"method": "harmonic", "handles": [[0], {"sphere": [0, 0, 0, )" + far + R"(]}], "keys": [{}, {}]})",
       "spec.handles[1].sphere: "},
      {R"({"method": "harmonic", "handles": [[0], {"box": [0, 0, 0, 1, 1, )" + far + R"(]}], "keys": [{}, {}]})",
       "spec.handles[1].box: "},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [)" + far +
           R"(, 0, 0], "size": [1, 1, 1]}}, "handles": [[[0, 0, 0]]], "keys": [{}]})",
       "spec.lattice.box.origin: "},
      {R"({"method": "ffd", "lattice": {"margin": 1e300}, "handles": [[[0, 0, 0]]], "keys": [{}]})",
       "spec.lattice.margin: "},
  };
  for (const auto& [text, field] : cases) EXPECT_NE(message(text).find(field), std::string::npos) << message(text);
  // Within reach, far from the mesh is still a point: an IK target 10 sizes away binds.
  EXPECT_EQ(
      message(R"({"method": "spline", )" + linear + two +
              R"("ik": {"joints": [[0, 0, 0], [0, 0, 1]], "target": [0, 0, 50]}})"),
      "(no error)");
}

// Messages and index handles use the file's numbering (here an OBJ whose `v` lines are in
// another order than the loader's vertices, with one unused line), not the loaded mesh's.
TEST(DeformSpecBind, IndicesAndMessagesUseTheFilesNumbering) {
  cgamesh_test::TempDir dir;
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  // v lines 0-4: the apex (outside the cage below), unused, then the base used first.
  const std::string obj = write("pyramid.obj",
                                "v 0 0 5\nv 9 9 9\nv -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                                "f 3 5 4\nf 3 6 5\nf 3 4 1\nf 4 5 1\nf 5 6 1\nf 6 3 1\n");
  const anim::RiggedModel model = io::load_model(obj);
  const mesh::Mesh& m = model.meshes.at(0);
  ASSERT_EQ(m.vertex_count(), 5);
  const Eigen::Index apex = std::find(m.file_index.data(), m.file_index.data() + 5, 0) - m.file_index.data();
  ASSERT_NE(apex, 0) << "the test needs the loader to number the apex otherwise than the file";
  const auto message = [&](const std::string& text) {
    try {
      (void)BoundDeformer(parse_spec(text, (dir / "spec.json").string()), model);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const BoundDeformer bound(parse_spec(R"({"method": "harmonic", "handles": [[2, 3], [0]],
      "keys": [{}, {"translate": [0, 0, 1]}]})",
                                       "inline"),
                            model);
  EXPECT_EQ(bound.handles()[1], std::vector<int>{static_cast<int>(apex)});
  EXPECT_NEAR(bound.apply(bound.keys())(apex, 2), 6.0f, 1e-5f);
  EXPECT_NE(message(R"({"method": "harmonic", "handles": [[2], [1]], "keys": [{}, {}]})")
                .find("spec.handles[1]: vertex 1 of the file is on no triangle"),
            std::string::npos);
  EXPECT_NE(message(R"({"method": "harmonic", "handles": [[2], [6]], "keys": [{}, {}]})")
                .find("spec.handles[1]: expected vertex indices of the file in [0, 6)"),
            std::string::npos);
  EXPECT_NE(message(R"({"method": "harmonic", "handles": [[2, 0], [0]], "keys": [{}, {}]})")
                .find("spec.handles[1]: vertex 0 (or a vertex at its position)"),
            std::string::npos);
  write("cage.obj",
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n");
  EXPECT_NE(message(R"({"method": "cage", "space": "mesh", "cage": "cage.obj", "resolution": 8, "handles": [[0]],
      "keys": [{}]})")
                .find("cage: vertex 0 at (0 0 5) is outside the cage"),
            std::string::npos)
      << message(
             R"({"method": "cage", "space": "mesh", "cage": "cage.obj", "resolution": 8, "handles": [[0]], "keys": [{}]})");
}

/// A harmonic spec for CesiumMan in world space: the lowest and highest fifth of the figure in
/// the bind pose (y is up in its scene) as handles, the top one turned and moved.
DeformSpec cesiumman_world_spec(const mesh::RowMatrixXf<3>& world) {
  const float lo = world.col(1).minCoeff(), hi = world.col(1).maxCoeff(), h = hi - lo;
  const auto n = [](double x) { return std::to_string(x); };
  return parse_spec(R"({"method": "harmonic", "handles": [{"box": [-9, )" + n(lo - 1) + ", -9, 9, " + n(lo + 0.2 * h) +
                        R"(, 9]}, {"box": [-9, )" + n(hi - 0.2 * h) + ", -9, 9, " + n(hi + 1) +
                        R"(, 9]}], "keys": [{}, {"rotate": [0, 0, 1, 30], "center": [0, )" + n(hi - 0.2 * h) +
                        R"(, 0], "translate": [0.1, 0, 0]}]})",
                    "inline");
}

// World space is the bind pose of `info`: selections, centres and results are world
// coordinates, and the edited rest shape re-skins to the result.
TEST(DeformSpecSpace, WorldIsTheBindPoseAndMapsBackExactly) {
  const anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  EXPECT_EQ(deform::default_space(model), DeformSpace::world);
  const mesh::RowMatrixXf<3> rest = deform::rest_positions(model, DeformSpace::world)[0];
  ASSERT_GT(max_difference(rest, model.meshes[0].positions), 0.1) << "CesiumMan's bind pose is not its mesh space";
  const DeformSpec s = cesiumman_world_spec(rest);
  const BoundDeformer bound(s, model);
  EXPECT_EQ(bound.space(), DeformSpace::world);
  EXPECT_EQ(max_difference(bound.rest_positions(), rest), 0.0);
  const float top = rest.col(1).maxCoeff() - 0.2F * (rest.col(1).maxCoeff() - rest.col(1).minCoeff());
  ASSERT_FALSE(bound.handles()[1].empty());
  for (const int v : bound.handles()[1]) EXPECT_GE(rest(v, 1), top - 1e-5F);

  const mesh::RowMatrixXf<3> deformed = bound.apply(bound.keys());
  // The top handle moved by its key, in world coordinates.
  const Eigen::Matrix<double, 3, 4> key = cga::PointMap<double>(bound.keys()[1]).affine_matrix();
  for (const int v : bound.handles()[1]) {
    const Eigen::Vector3d p = key.leftCols<3>() * rest.row(v).transpose().cast<double>() + key.col(3);
    EXPECT_LT((deformed.row(v).transpose().cast<double>() - p).norm(), 1e-4);
  }
  const anim::RiggedModel edited = bound.deformed_model(model, deformed);
  EXPECT_LT(max_difference(deform::rest_positions(edited, DeformSpace::world)[0], deformed), 1e-4);
  EXPECT_EQ(edited.meshes[0].skin.palette, model.meshes[0].skin.palette);

  // In mesh space the same vertices are the stored positions, and nothing needs mapping back.
  DeformSpec in_mesh = s;
  in_mesh.space = DeformSpace::mesh;
  for (std::size_t h = 0; h < 2; ++h)
    in_mesh.handles[h] = {deform::HandleSelection::Kind::indices, bound.handles()[h], {}};
  const BoundDeformer mesh_bound(in_mesh, model);
  EXPECT_EQ(max_difference(mesh_bound.rest_positions(), model.meshes[0].positions), 0.0);
  const mesh::RowMatrixXf<3> mesh_result = mesh_bound.apply(mesh_bound.keys());
  EXPECT_EQ(max_difference(mesh_bound.to_mesh_space(mesh_result), mesh_result), 0.0);
  EXPECT_GT(max_difference(mesh_result, bound.to_mesh_space(deformed)), 1e-3) << "the key acts in another space";
}

TEST(DeformSpecSpace, GltfKeepsSkinSkeletonAndClipsAndReposes) {
  const anim::RiggedModel model = io::load_model(cgamesh_test::demo_model());
  const BoundDeformer bound(cesiumman_world_spec(deform::rest_positions(model, DeformSpace::world)[0]), model);
  const mesh::RowMatrixXf<3> deformed = bound.apply(bound.keys());
  cgamesh_test::TempDir dir;
  const auto out = dir.path() / "bent.glb";
  (void)io::write_gltf(bound.deformed_model(model, deformed), out);
  const anim::RiggedModel back = io::load_model(out);
  ASSERT_EQ(back.meshes.size(), model.meshes.size());
  EXPECT_EQ(back.clips.size(), model.clips.size());
  EXPECT_EQ(back.skeleton.size(), model.skeleton.size());
  EXPECT_EQ(back.meshes[0].skin.palette.size(), model.meshes[0].skin.palette.size());
  EXPECT_LT(max_difference(deform::rest_positions(back, DeformSpace::world)[0], deformed), 1e-4);
  // Normals of the new shape, written: where the key is the identity they are the rest shape's.
  ASSERT_EQ(back.meshes[0].normals.rows(), back.meshes[0].vertex_count());
  const mesh::RowMatrixXf<3> at_rest = mesh::reshaped_normals(model.meshes[0], model.meshes[0].positions);
  // (Not next to a moved vertex, through a seam copy's faces too.)
  const mesh::Mesh& rest_mesh = model.meshes[0];
  const std::vector<int> at = mesh::weld_by_position(rest_mesh.positions);
  std::vector<char> fixed(static_cast<std::size_t>(rest_mesh.vertex_count()), 0), near_moved = fixed;
  for (const int v : bound.handles()[0]) fixed[static_cast<std::size_t>(v)] = 1;
  for (Eigen::Index f = 0; f < rest_mesh.face_count(); ++f)
    if (!fixed[rest_mesh.faces(f, 0)] || !fixed[rest_mesh.faces(f, 1)] || !fixed[rest_mesh.faces(f, 2)])
      for (int k = 0; k < 3; ++k) near_moved[static_cast<std::size_t>(at[rest_mesh.faces(f, k)])] = 1;
  int inside = 0;
  for (const int v : bound.handles()[0]) {
    if (near_moved[static_cast<std::size_t>(at[static_cast<std::size_t>(v)])]) continue;
    ++inside;
    EXPECT_LT((back.meshes[0].normals.row(v) - at_rest.row(v)).norm(), 1e-4f);
  }
  EXPECT_GT(inside, 20);
  double turned = 0;
  for (const int v : bound.handles()[1])
    turned = std::max(turned, static_cast<double>((back.meshes[0].normals.row(v) - at_rest.row(v)).norm()));
  EXPECT_GT(turned, 0.2) << "the moved handle's normals did not turn with it";

  // It re-animates: in a clip frame the fixed handle is where the original puts it, the moved
  // one elsewhere.
  ASSERT_FALSE(back.clips.empty());
  const auto posed = [](const anim::RiggedModel& m) {
    const anim::Pose pose = anim::sample(m.skeleton, m.clips[0], 0.5 * m.clips[0].duration, anim::BlendMode::format);
    const auto palette = anim::make_palette(m.meshes[0], anim::global_versors(m.skeleton, pose),
                                            anim::global_matrices(m.skeleton, pose), anim::SkinningMode::matrix);
    return anim::skin(m.meshes[0], palette);
  };
  const mesh::RowMatrixXf<3> before = posed(model), after = posed(back);
  for (const int v : bound.handles()[0]) EXPECT_LT((after.row(v) - before.row(v)).norm(), 1e-4);
  double moved = 0;
  for (const int v : bound.handles()[1])
    moved = std::max(moved, static_cast<double>((after.row(v) - before.row(v)).norm()));
  EXPECT_GT(moved, 0.05);
}

/// Two copies of a cylinder: the second shifted by `shift`.
mesh::Mesh two_cylinders(const Eigen::Vector3f& shift) {
  const mesh::Mesh a = cylinder(16, 6);
  mesh::Mesh m;
  m.positions.resize(2 * a.vertex_count(), 3);
  m.positions << a.positions, a.positions.rowwise() + shift.transpose();
  m.faces.resize(2 * a.face_count(), 3);
  m.faces << a.faces, a.faces.array() + static_cast<int>(a.vertex_count());
  return m;
}

// A part without a handle moves with the nearest handle's key, or stays; the handled part
// deforms as if it were alone.
TEST(DeformSpecFreeParts, MoveWithTheNearestHandleOrStay) {
  const anim::RiggedModel model = model_of(two_cylinders({0, 0, 3}));
  const Eigen::Index n = 16 * 6;
  const std::string handles = R"("handles": [{"box": [-2, -2, -1, 2, 2, 0.01]}, {"box": [-2, -2, 0.99, 2, 2, 1.01]}])";
  for (const std::string method : {"harmonic", "spline"}) {
    const std::string keys =
        method == "harmonic"
            ? R"("keys": [{}, {"rotate": [1, 0, 0, 20], "center": [0, 0, 1]}])"
            : R"("keys": [{}, {"translate": [0, 0.1, 0]}, {"rotate": [1, 0, 0, 20], "center": [0, 0, 1]}], "basis": "linear")";
    const std::string base = R"({"method": ")" + method + "\", " + handles + ", " + keys;
    const BoundDeformer nearest(parse_spec(base + "}", "inline"), model);
    ASSERT_EQ(static_cast<Eigen::Index>(nearest.free_vertices().size()), n) << method;
    EXPECT_EQ(nearest.free_vertices().front(), n);
    const mesh::RowMatrixXf<3> moved = nearest.apply(nearest.keys());
    const Eigen::Matrix<double, 3, 4> key = cga::PointMap<double>(nearest.keys().back()).affine_matrix();
    for (Eigen::Index v = n; v < 2 * n; ++v) {
      const Eigen::Vector3d p =
          key.leftCols<3>() * model.meshes[0].positions.row(v).transpose().cast<double>() + key.col(3);
      EXPECT_LT((moved.row(v).transpose().cast<double>() - p).norm(), 1e-5) << method << " vertex " << v;
    }
    // The handled cylinder alone gives the same positions.
    const BoundDeformer alone(parse_spec(base + "}", "inline"), model_of(cylinder(16, 6)));
    EXPECT_LT(max_difference(alone.apply(alone.keys()), mesh::RowMatrixXf<3>(moved.topRows(n))), 1e-6) << method;

    const BoundDeformer keep(parse_spec(base + R"(, "free_parts": "keep"})", "inline"), model);
    const mesh::RowMatrixXf<3> kept = keep.apply(keep.keys());
    EXPECT_EQ(max_difference(mesh::RowMatrixXf<3>(kept.bottomRows(n)),
                             mesh::RowMatrixXf<3>(model.meshes[0].positions.bottomRows(n))),
              0.0)
        << method;
  }
}

// The nearest handle is chosen per part: a part next to the bottom handle follows key 0.
TEST(DeformSpecFreeParts, NearestHandlePerPart) {
  const anim::RiggedModel model = model_of(two_cylinders({0, 0, -2}));
  const BoundDeformer bound(parse_spec(R"({"method": "harmonic",
      "handles": [{"box": [-2, -2, -0.01, 2, 2, 0.01]}, {"box": [-2, -2, 0.99, 2, 2, 1.01]}],
      "keys": [{"translate": [0.5, 0, 0]}, {"rotate": [1, 0, 0, 20], "center": [0, 0, 1]}]})",
                                       "inline"),
                            model);
  const mesh::RowMatrixXf<3> moved = bound.apply(bound.keys());
  for (const int v : bound.free_vertices()) EXPECT_NEAR(moved(v, 0), model.meshes[0].positions(v, 0) + 0.5, 1e-5);
}

}  // namespace
