// Harmonic cage coordinates (paper section VI): coordinates, the grid's reproduction bound,
// rigid cage motions (classic and motor), cage validation, the .npy cache, the OBJ reader and the
// cage spec.
#include "cgamesh/deform/cage_coordinates.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "deform/deform_fixtures.hpp"
#include "support/temp_dir.hpp"

namespace {

using cgamesh_deform_test::moved;

using namespace cgamesh;  // NOLINT(google-build-using-namespace)
using deform::Cage;
using deform::CageDeformation;
using Versor = cga::Versor<double>;
using cgamesh_test::TempDir;
namespace fs = std::filesystem;

const Versor kIdentity(cga::basis_blade<double, cga::blade::scalar>());

/// CesiumMan's skin in mesh space (3273 vertices): a real, non-convex mesh.
const mesh::Mesh& cesium_man() {
  static const mesh::Mesh m = io::load_model(cgamesh_test::demo_model()).meshes.at(0);
  return m;
}

/// A box cage 10 % larger than CesiumMan on every side, 2 × 2 × 4 segments (42 vertices).
Cage man_cage(double grow = 0.1) {
  const mesh::RowMatrixXf<3>& p = cesium_man().positions;
  const Eigen::Vector3d lo = p.colwise().minCoeff().transpose().cast<double>();
  const Eigen::Vector3d hi = p.colwise().maxCoeff().transpose().cast<double>();
  const Eigen::Vector3d margin = grow * (hi - lo);
  return deform::box_cage(lo - margin, hi + margin, {2, 2, 4});
}

/// The coordinates of CesiumMan in man_cage() at resolution 32, computed once.
const Eigen::MatrixXd& man_coordinates() {
  static const Eigen::MatrixXd c = [] {
    deform::CageOptions options;
    options.resolution = 32;
    return deform::cage_coordinates(cesium_man().positions, man_cage(), options);
  }();
  return c;
}

double cell_size(const Cage& cage, int resolution) {
  return (cage.vertices.colwise().maxCoeff() - cage.vertices.colwise().minCoeff()).maxCoeff() / resolution;
}

Versor rigid_motion() {
  return cga::project<cga::mask::versor>(cga::translator(Eigen::Vector3d(0.3, -0.2, 0.5)) *
                                         cga::rotor(Eigen::Vector3d(1, 2, 3).normalized(), 1.1));
}

TEST(CageCoordinates, PartitionOfUnityAndNonNegative) {
  const Eigen::MatrixXd& c = man_coordinates();
  ASSERT_EQ(c.rows(), cesium_man().vertex_count());
  ASSERT_EQ(c.cols(), man_cage().vertices.rows());
  EXPECT_GE(c.minCoeff(), 0.0);
  EXPECT_LT((c.rowwise().sum().array() - 1).abs().maxCoeff(), 1e-12);
}

// Linear functions are discrete-harmonic and the boundary values are within √3 h of them
// (header comment), so Σ λ ĉ is within √3 h of p̂ per coordinate.
TEST(CageCoordinates, RestCageReproducesTheMeshWithinTheGridError) {
  const Cage cage = man_cage();
  const double h = cell_size(cage, 32);
  const Eigen::MatrixXd reproduced = man_coordinates() * cage.vertices;
  const double error = (reproduced - cesium_man().positions.cast<double>()).cwiseAbs().maxCoeff();
  EXPECT_LE(error, std::sqrt(3.0) * h);
  RecordProperty("reproduction_error_in_cells", std::to_string(error / h));
  // Finer grids do better: at 64 the error is below the bound of 32 / 2.
  deform::CageOptions fine;
  fine.resolution = 64;
  const Eigen::MatrixXd c64 = deform::cage_coordinates(cesium_man().positions, cage, fine);
  const double error64 = (c64 * cage.vertices - cesium_man().positions.cast<double>()).cwiseAbs().maxCoeff();
  EXPECT_LE(error64, std::sqrt(3.0) * h / 2);
  std::cout << "reproduction error: " << error / h << " cells at 32, " << error64 / (h / 2) << " cells at 64\n";
}

TEST(CageCoordinates, RestCageAndIdentityMotorsKeepTheMesh) {
  const Cage cage = man_cage();
  const CageDeformation d(cesium_man().positions, cage, man_coordinates());
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index v = 0; v < cage.vertices.rows(); ++v) points.push_back(cage.vertices.row(v).transpose());
  mesh::RowMatrixXf<3> out;
  d.deform_points(points, out);
  EXPECT_LT((out - cesium_man().positions).cwiseAbs().maxCoeff(), 1e-6);
  const std::vector<Versor> motors(points.size(), kIdentity);
  d.deform_motors(motors, out);
  EXPECT_LT((out - cesium_man().positions).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(CageCoordinates, RigidCageMotionMovesTheMeshRigidly) {
  const Cage cage = man_cage();
  const Versor k = rigid_motion();
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  const mesh::RowMatrixXf<3> expected = moved(rest, k);
  // Motor cage: one motor everywhere is that motor exactly, whatever the coordinates kept.
  const CageDeformation sparse(rest, cage, man_coordinates());
  mesh::RowMatrixXf<3> out;
  sparse.deform_motors(std::vector<Versor>(static_cast<std::size_t>(cage.vertices.rows()), k), out);
  EXPECT_LT((out - expected).cwiseAbs().maxCoeff(), 1e-5);
  // Classic: p̂ + Σ λ (R ĉ − ĉ) = R p̂ + (R − I)(Σ λ ĉ − p̂): rigid within twice the reproduction
  // bound with every coordinate kept.
  deform::CageSparsity all;
  all.max_weights = static_cast<int>(cage.vertices.rows());
  all.min_weight = 0;
  const CageDeformation dense(rest, cage, man_coordinates(), all);
  const mesh::RowMatrixXf<3> posed = moved(cage.vertices.cast<float>(), k);
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index v = 0; v < posed.rows(); ++v) points.push_back(posed.row(v).transpose().cast<double>());
  dense.deform_points(points, out);
  EXPECT_LT((out - expected).rowwise().norm().maxCoeff(), 2 * 3 * cell_size(cage, 32));
}

// A frame runs a single-precision kernel over blocks of vertices (rigid blends) and the double
// exp for dilating ones: both equal the per-vertex blend to float precision.
TEST(CageCoordinates, MotorFramesEqualThePerVertexBlend) {
  const Cage cage = man_cage();
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  const double d = (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm();
  const CageDeformation deformation(rest, cage, man_coordinates());
  for (const bool dilate : {false, true}) {
    const auto motors = cgamesh_deform_test::varied_motors(static_cast<std::size_t>(cage.vertices.rows()), dilate);
    mesh::RowMatrixXf<3> out;
    deformation.deform_motors(motors, out);
    EXPECT_LE((out - cgamesh_deform_test::blended_reference(deformation, rest, motors)).cwiseAbs().maxCoeff(),
              2e-6 * d);
  }
}

TEST(CageCoordinates, SparsityKeepsTheLargestAndRenormalises) {
  deform::CageSparsity s;
  s.max_weights = 4;
  const CageDeformation d(cesium_man().positions, man_cage(), man_coordinates(), s);
  EXPECT_LE(d.mean_weights(), 4.0);
  for (Eigen::Index i = 0; i < d.vertex_count(); i += 97) {
    double sum = 0;
    for (const auto& [j, w] : d.weights(i)) {
      sum += w;
      EXPECT_GT(w, 0.0);
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
  }
  s.max_weights = 0;
  EXPECT_THROW(CageDeformation(cesium_man().positions, man_cage(), man_coordinates(), s), InvalidInputError);
}

TEST(CageCoordinates, CageNotEnclosingTheMeshNamesTheFirstVertexOutside) {
  const mesh::RowMatrixXf<3>& p = cesium_man().positions;
  const Eigen::Vector3d lo = p.colwise().minCoeff().transpose().cast<double>();
  Eigen::Vector3d hi = p.colwise().maxCoeff().transpose().cast<double>() + Eigen::Vector3d::Constant(0.01);
  hi[1] = 0.5 * (lo[1] + hi[1]);  // the half above sticks out
  const Cage cage = deform::box_cage(lo - Eigen::Vector3d::Constant(0.01), hi, {1, 1, 1});
  int first = -1;
  for (Eigen::Index i = 0; i < p.rows() && first < 0; ++i)
    if (p(i, 1) > hi[1]) first = static_cast<int>(i);
  ASSERT_GE(first, 0);
  try {
    (void)deform::cage_coordinates(p, cage);
    FAIL() << "expected an error";
  } catch (const InvalidInputError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex " + std::to_string(first) + " "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("outside the cage"), std::string::npos) << e.what();
  }
}

TEST(CageCoordinates, OpenNonManifoldOrMisorientedCagesAreTopologyErrors) {
  const Cage good = deform::box_cage(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), {1, 1, 1});
  EXPECT_NO_THROW(deform::check_cage(good));
  const auto message = [](const Cage& c) {
    try {
      deform::check_cage(c);
    } catch (const TopologyError& e) {
      return std::string(e.what());
    }
    return std::string("no TopologyError");
  };
  Cage open = good;
  open.faces.conservativeResize(open.faces.rows() - 1, 3);
  EXPECT_NE(message(open).find("not closed"), std::string::npos) << message(open);
  Cage doubled = good;
  doubled.faces.conservativeResize(doubled.faces.rows() + 1, 3);
  doubled.faces.row(doubled.faces.rows() - 1) = good.faces.row(0);
  EXPECT_NE(message(doubled).find("not manifold"), std::string::npos) << message(doubled);
  Cage flipped = good;
  std::swap(flipped.faces(0, 1), flipped.faces(0, 2));
  EXPECT_NE(message(flipped).find("not consistently oriented"), std::string::npos) << message(flipped);
  Cage degenerate = good;
  degenerate.faces(0, 1) = degenerate.faces(0, 0);
  EXPECT_NE(message(degenerate).find("face 0"), std::string::npos) << message(degenerate);
  // cage_coordinates validates first.
  EXPECT_THROW((void)deform::cage_coordinates(cesium_man().positions, open), TopologyError);
  Cage tiny = good;
  tiny.faces.resize(2, 3);
  EXPECT_THROW(deform::check_cage(tiny), InvalidInputError);
}

TEST(CageCoordinates, OptionsOutOfRangeAreRefused) {
  deform::CageOptions o;
  o.resolution = 3;
  EXPECT_THROW((void)deform::cage_coordinates(cesium_man().positions, man_cage(), o), InvalidInputError);
  o.resolution = 16;
  o.tolerance = 0;
  EXPECT_THROW((void)deform::cage_coordinates(cesium_man().positions, man_cage(), o), InvalidInputError);
}

// The .npy format itself is io's (tests/io/npy_test.cpp); here what makes a file coordinates.
TEST(CageCoordinates, CachedCoordinatesRoundTripAndAreChecked) {
  TempDir dir;
  const fs::path file = dir.path() / "c.npy";
  const Eigen::MatrixXd& c = man_coordinates();
  deform::save_cage_coordinates(file, c);
  EXPECT_EQ(deform::load_cage_coordinates(file, c.rows(), c.cols()), c);
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

  const auto error = [&](const fs::path& p, Eigen::Index rows, Eigen::Index cols) {
    try {
      (void)deform::load_cage_coordinates(p, rows, cols);
    } catch (const FileError& e) {
      return std::string(e.what());
    }
    return std::string("no FileError");
  };
  EXPECT_NE(error(file, c.rows() + 1, c.cols()).find("holds 3273x42 coordinates; the mesh and cage need 3274x42"),
            std::string::npos);
  std::string bad_row = bytes;
  const double two = 2;
  bad_row.replace(bytes.size() - static_cast<std::size_t>(c.size()) * 8, 8, reinterpret_cast<const char*>(&two), 8);
  const fs::path not_coordinates = dir.path() / "r.npy";
  std::ofstream(not_coordinates, std::ios::binary) << bad_row;
  EXPECT_NE(error(not_coordinates, c.rows(), c.cols()).find("row 0"), std::string::npos);
  EXPECT_NE(error(dir.path() / "missing.npy", 1, 1).find("cannot read the coordinates"), std::string::npos);
}

// The OBJ lines themselves are io's (tests/io/obj_reader_test.cpp); here the cage's numbering.
TEST(CageCoordinates, CageObjKeepsTheFilesNumberingAndNamesBadLines) {
  TempDir dir;
  const fs::path file = dir.path() / "cage.obj";
  std::ofstream(file) << "# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                         "f 1 3 2\nf 1/1 2/2 4/4\nf -4 -1 -2\nf 2//1 3//1 4//1\n";
  const Cage cage = deform::read_cage_obj(file);
  EXPECT_EQ(cage.vertices.rows(), 4);
  ASSERT_EQ(cage.faces.rows(), 4);
  EXPECT_EQ(cage.faces.row(2), Eigen::RowVector3i(0, 3, 2));
  EXPECT_NO_THROW(deform::check_cage(cage));
  std::ofstream(file) << "v 0 0 0\nv 1 0 0\nv 0 1 0 1\nf 1 2 3 4 5\n";
  try {
    (void)deform::read_cage_obj(file);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("cage " + file.string() + ":4:"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)deform::read_cage_obj(dir.path() / "missing.obj"), FileError);
}

/// Writes `cage` as an OBJ.
void write_obj(const fs::path& path, const Cage& cage) {
  std::ofstream out(path);
  out.precision(17);
  for (Eigen::Index v = 0; v < cage.vertices.rows(); ++v)
    out << "v " << cage.vertices(v, 0) << " " << cage.vertices(v, 1) << " " << cage.vertices(v, 2) << "\n";
  for (Eigen::Index f = 0; f < cage.faces.rows(); ++f)
    out << "f " << cage.faces(f, 0) + 1 << " " << cage.faces(f, 1) + 1 << " " << cage.faces(f, 2) + 1 << "\n";
}

anim::RiggedModel man_model() {
  anim::RiggedModel m;
  m.meshes.push_back(cesium_man());
  m.meshes[0].skin = {};
  return m;
}

TEST(CageSpec, MotorHandlesCacheTheCoordinatesAndDeformedCagesMatchKeys) {
  TempDir dir;
  write_obj(dir.path() / "cage.obj", man_cage());
  const Cage cage = man_cage();
  const double top = cage.vertices.col(1).maxCoeff();
  const std::string handles = R"([{"box": [-100, )" + std::to_string(top - 1e-6) + R"(, -100, 100, 100, 100]}])";
  const std::string text = R"({"method": "cage", "space": "mesh", "cage": "cage.obj", "resolution": 24,
      "coordinates": "cache/c.npy", "handles": )" +
                           handles + R"(, "keys": [{"rotate": [0, 0, 1, 30]}]})";
  fs::create_directories(dir.path() / "cache");
  const deform::DeformSpec spec = deform::parse_spec(text, (dir.path() / "spec.json").string());
  EXPECT_EQ(spec.method(), deform::DeformMethod::cage);
  EXPECT_EQ(std::get<deform::CageSpec>(spec.fields).cage, dir.path() / "cage.obj");
  const anim::RiggedModel model = man_model();
  const deform::BoundDeformer first(spec, model);
  ASSERT_TRUE(fs::exists(dir.path() / "cache" / "c.npy"));
  ASSERT_NE(first.method().cage(), nullptr);
  EXPECT_EQ(first.control_handles().at(0).size(), 15u);  // the top side of 3 × 5 vertices
  const mesh::RowMatrixXf<3> a = first.apply(first.keys());
  const deform::BoundDeformer cached(spec, model);  // loads the cache
  EXPECT_EQ(cached.apply(cached.keys()), a);
  EXPECT_GT((a - cesium_man().positions).cwiseAbs().maxCoeff(), 0.01);

  // Classic with the cage moved by the same key, from a deformed cage file or from handles.
  Cage posed = cage;
  const Eigen::Matrix<double, 3, 4> m = cga::PointMap<double>(first.keys()[0]).affine_matrix();
  for (Eigen::Index v = 0; v < cage.vertices.rows(); ++v)
    if (cage.vertices(v, 1) > top - 1e-6)
      posed.vertices.row(v) = (m.leftCols<3>() * cage.vertices.row(v).transpose() + m.col(3)).transpose();
  write_obj(dir.path() / "posed.obj", posed);
  const deform::BoundDeformer from_file(
      deform::parse_spec(R"({"method": "cage", "space": "mesh", "variant": "classic", "cage": "cage.obj",
          "coordinates": "cache/c.npy", "deformed_cage": "posed.obj"})",
                         (dir.path() / "spec.json").string()),
      model);
  EXPECT_TRUE(from_file.keys().empty());
  // What a viewer draws: the cage where the keys put it, and each edge of a closed genus-0 cage once.
  const std::vector<Eigen::Vector3d> drawn = first.control_points(first.keys()),
                                     posed_drawn = from_file.control_points({});
  ASSERT_EQ(drawn.size(), static_cast<std::size_t>(cage.vertices.rows()));
  ASSERT_EQ(posed_drawn.size(), drawn.size());
  for (std::size_t v = 0; v < drawn.size(); ++v) {
    EXPECT_LT((drawn[v] - posed.vertices.row(static_cast<Eigen::Index>(v)).transpose()).norm(), 1e-12) << v;
    EXPECT_EQ(posed_drawn[v], posed.vertices.row(static_cast<Eigen::Index>(v)).transpose()) << v;
  }
  EXPECT_EQ(static_cast<Eigen::Index>(first.control_edges().size()), cage.vertices.rows() + cage.faces.rows() - 2);
  std::set<std::array<int, 2>> edges(first.control_edges().begin(), first.control_edges().end());
  EXPECT_EQ(edges.size(), first.control_edges().size());
  std::string classic = text;
  classic.replace(classic.find(R"("method": "cage")"), 16, R"("method": "cage", "variant": "classic")");
  const deform::BoundDeformer from_keys(deform::parse_spec(classic, (dir.path() / "spec.json").string()), model);
  EXPECT_LT((from_file.apply(from_file.keys()) - from_keys.apply(from_keys.keys())).cwiseAbs().maxCoeff(), 1e-5);

  // A cache of another shape is refused, naming the field.
  deform::save_cage_coordinates(dir.path() / "cache" / "c.npy", Eigen::MatrixXd::Ones(3, 1));
  try {
    const deform::BoundDeformer stale(spec, model);
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("spec.coordinates: "), std::string::npos) << e.what();
  }
}

TEST(CageSpec, BadFieldsNameTheField) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"method": "cage", "handles": [[0]], "keys": [{}]})", "spec.cage"},
      {R"({"method": "cage", "cage": 3, "handles": [[0]], "keys": [{}]})", "spec.cage"},
      {R"({"method": "cage", "cage": "c.obj", "resolution": 2, "handles": [[0]], "keys": [{}]})", "spec.resolution"},
      {R"({"method": "cage", "cage": "c.obj", "resolution": 1.5, "handles": [[0]], "keys": [{}]})", "spec.resolution"},
      {R"({"method": "cage", "cage": "c.obj", "max_weights": 0, "handles": [[0]], "keys": [{}]})", "spec.max_weights"},
      {R"({"method": "cage", "cage": "c.obj", "coordinates": "", "handles": [[0]], "keys": [{}]})", "spec.coordinates"},
      {R"({"method": "cage", "cage": "c.obj", "deformed_cage": "d.obj", "handles": [[0]], "keys": [{}]})",
       "spec.deformed_cage"},
      {R"({"method": "cage", "variant": "classic", "cage": "c.obj", "deformed_cage": "d.obj", "keys": []})",
       "spec.keys"},
      {R"({"method": "cage", "cage": "c.obj", "lattice": {}, "handles": [[0]], "keys": [{}]})", "spec.lattice"},
      {R"({"method": "cage", "cage": "c.obj", "weights": "cotangent", "handles": [[0]], "keys": [{}]})",
       "spec.weights"},
      {R"({"method": "harmonic", "cage": "c.obj", "handles": [[0]], "keys": [{}]})", "spec.cage"},
      {R"({"method": "ffd", "resolution": 8, "handles": [[[0, 0, 0]]], "keys": [{}]})", "spec.resolution"},
  };
  for (const auto& [text, field] : cases) {
    try {
      (void)deform::parse_spec(text, "s.json");
      ADD_FAILURE() << text;
    } catch (const InvalidInputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(std::string(field) + ":", 0), 0u) << text << " -> " << e.what();
    }
  }
}

}  // namespace
