#include "cgamesh/deform/ffd.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "deform/deform_fixtures.hpp"

namespace {

using cgamesh_deform_test::moved;

using namespace cgamesh;  // NOLINT(google-build-using-namespace)
using deform::BsplineEnds;
using deform::FreeFormDeformation;
using deform::Lattice;
using deform::LatticeBasis;
using Versor = cga::Versor<double>;

const Versor kIdentity(cga::basis_blade<double, cga::blade::scalar>());

/// CesiumMan's skin in mesh space (3273 vertices): a real, non-convex mesh.
const mesh::Mesh& cesium_man() {
  static const mesh::Mesh m = io::load_model(cgamesh_test::demo_model()).meshes.at(0);
  return m;
}

double diagonal(const mesh::RowMatrixXf<3>& p) {
  return static_cast<double>((p.colwise().maxCoeff() - p.colwise().minCoeff()).norm());
}

/// The lattices every test runs over: both bases, both B-spline ends, uneven resolutions.
std::vector<Lattice> lattices(const mesh::RowMatrixXf<3>& rest) {
  std::vector<Lattice> out;
  for (const auto& [basis, ends] :
       {std::pair{LatticeBasis::bernstein, BsplineEnds::linear}, std::pair{LatticeBasis::bspline, BsplineEnds::linear},
        std::pair{LatticeBasis::bspline, BsplineEnds::repeat}}) {
    Lattice l;
    l.resolution = {3, 6, 2};
    l.basis = basis;
    l.ends = ends;
    l.box = deform::bounding_lattice_box(rest, 0.01);
    out.push_back(l);
  }
  return out;
}

double max_difference(const mesh::RowMatrixXf<3>& a, const mesh::RowMatrixXf<3>& b) {
  return static_cast<double>((a - b).cwiseAbs().maxCoeff());
}

/// Mean |l / l₀ − 1| over the faces' edges.
double mean_strain(const mesh::Mesh& m, const mesh::RowMatrixXf<3>& deformed) {
  double sum = 0;
  Eigen::Index count = 0;
  for (Eigen::Index f = 0; f < m.faces.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = m.faces(f, c), b = m.faces(f, (c + 1) % 3);
      const double rest = static_cast<double>((m.positions.row(a) - m.positions.row(b)).norm());
      if (rest == 0) continue;
      sum += std::abs(static_cast<double>((deformed.row(a) - deformed.row(b)).norm()) / rest - 1);
      ++count;
    }
  return sum / static_cast<double>(count);
}

TEST(Ffd, WeightsArePartitionsOfUnityOverFewControlPoints) {
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  for (const Lattice& l : lattices(rest)) {
    const FreeFormDeformation ffd(rest, l);
    EXPECT_TRUE(ffd.outside().empty());
    for (Eigen::Index i = 0; i < rest.rows(); i += 7) {
      const auto w = ffd.weights(i);
      double sum = 0;
      for (const auto& [c, x] : w) {
        ASSERT_GE(c, 0);
        ASSERT_LT(c, l.count());
        sum += x;
      }
      EXPECT_NEAR(sum, 1.0, 1e-6);  // single-precision basis values
      // B-splines touch at most 4 points per axis (here 3 × 4 × 2), Bernstein every point.
      EXPECT_LE(w.size(), l.basis == LatticeBasis::bernstein ? 36U : 24U);
    }
  }
}

TEST(Ffd, BernsteinClassicIsEquation6) {
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  const Lattice l = lattices(rest)[0];
  const FreeFormDeformation ffd(rest, l);
  std::vector<Eigen::Vector3d> points = l.control_points();
  for (std::size_t c = 0; c < points.size(); ++c)
    points[c] += 0.05 * Eigen::Vector3d(std::sin(c), std::cos(3.0 * c), 1);
  mesh::RowMatrixXf<3> out;
  ffd.deform_points(points, out);
  for (Eigen::Index i = 0; i < rest.rows(); i += 11) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();  // p = Σ B_u B_v B_k P_{u,v,k}, eq. 6 as written
    for (const auto& [c, w] : ffd.weights(i)) p += w * points[static_cast<std::size_t>(c)];
    EXPECT_LT((p - out.row(i).transpose().cast<double>()).norm(), 1e-6 * diagonal(rest)) << i;
  }
}

TEST(Ffd, UndeformedLatticeIsTheIdentity) {
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  const double tolerance = 1e-6 * diagonal(rest);
  for (Lattice l : lattices(rest)) {
    for (const bool rotated : {false, true}) {
      if (rotated) {  // a box turned about its corner, still holding the mesh
        l.box = deform::bounding_lattice_box(rest, 0.5);
        l.box.origin -= l.box.size;
        l.box.size *= 3;
        l.box.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
      }
      const FreeFormDeformation ffd(rest, l);
      ASSERT_TRUE(ffd.outside().empty());
      mesh::RowMatrixXf<3> classic, motor;
      ffd.deform_points(l.control_points(), classic);
      ffd.deform_motors(std::vector<Versor>(static_cast<std::size_t>(l.count()), kIdentity), motor);
      EXPECT_LE(max_difference(classic, rest), tolerance);
      EXPECT_LE(max_difference(motor, rest), tolerance);
    }
  }
}

TEST(Ffd, RigidlyMovedLatticeMovesTheMeshRigidly) {
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  const double d = diagonal(rest);
  const Versor k = cga::project<cga::mask::versor>(cga::translator(Eigen::Vector3d(0.3, -0.2, 0.5)) *
                                                   cga::rotor(Eigen::Vector3d(1, 1, 0), 1.1));
  const Eigen::Matrix<double, 3, 4> m = cga::PointMap<double>(k).affine_matrix();
  const mesh::RowMatrixXf<3> expected = moved(rest, k);
  for (const Lattice& l : lattices(rest)) {
    const FreeFormDeformation ffd(rest, l);
    std::vector<Eigen::Vector3d> points = l.control_points();
    for (auto& p : points) p = m.leftCols<3>() * p + m.col(3);
    mesh::RowMatrixXf<3> classic, motor;
    ffd.deform_points(points, classic);
    ffd.deform_motors(std::vector<Versor>(static_cast<std::size_t>(l.count()), k), motor);
    EXPECT_LE(max_difference(motor, expected), 1e-5 * d);
    // Classic FFD is rigid when the basis reproduces affine maps; Blender's repeated end points
    // do not, so a rotated lattice bends the mesh near its faces.
    if (l.ends == BsplineEnds::repeat && l.basis == LatticeBasis::bspline)
      EXPECT_GT(max_difference(classic, expected), 1e-3 * d);
    else
      EXPECT_LE(max_difference(classic, expected), 1e-5 * d);
  }
}

// Seed B Fig. 7: twisting the lattice by 90° about its long axis. Classic FFD blends the rotated
// control points linearly and shrinks the cross-sections; motors blend the rotations, so the
// cross-sections stay rigid and what strain remains is the twist's shear. Measured mean edge
// strain: Bernstein 0.0376 classic / 0.0299 motor, B-spline 0.0449 / 0.0299 (both bases blend
// the layer angles linearly, so the motor twists agree).
TEST(Ffd, TwistKeepsEdgeLengthsCloserToRestWithMotors) {
  const mesh::Mesh& man = cesium_man();
  for (const LatticeBasis basis : {LatticeBasis::bernstein, LatticeBasis::bspline}) {
    Lattice l;
    l.basis = basis;
    l.box = deform::bounding_lattice_box(man.positions, 0.01);
    int axis = 0;
    l.box.size.maxCoeff(&axis);
    l.resolution = {2, 2, 2};
    l.resolution[static_cast<std::size_t>(axis)] = 4;
    const Eigen::Vector3d center = l.box.origin + 0.5 * l.box.size;
    const FreeFormDeformation ffd(man.positions, l);
    const std::vector<Eigen::Vector3d> rest_points = l.control_points();
    std::vector<Eigen::Vector3d> points;
    std::vector<Versor> motors;
    for (int k = 0; k < l.resolution[2]; ++k)
      for (int v = 0; v < l.resolution[1]; ++v)
        for (int u = 0; u < l.resolution[0]; ++u) {
          const int layer = std::array<int, 3>{u, v, k}[static_cast<std::size_t>(axis)];
          const double angle = std::numbers::pi / 2 * layer / 3;
          const Versor twist = cga::project<cga::mask::versor>(
              cga::translator(center) * cga::rotor(Eigen::Vector3d(Eigen::Vector3d::Unit(axis)), angle) *
              cga::translator(Eigen::Vector3d(-center)));
          const Eigen::Matrix<double, 3, 4> m = cga::PointMap<double>(twist).affine_matrix();
          points.push_back(m.leftCols<3>() * rest_points[static_cast<std::size_t>(l.index(u, v, k))] + m.col(3));
          motors.push_back(twist);
        }
    mesh::RowMatrixXf<3> classic, motor;
    ffd.deform_points(points, classic);
    ffd.deform_motors(motors, motor);
    const double classic_strain = mean_strain(man, classic), motor_strain = mean_strain(man, motor);
    RecordProperty(std::string(basis == LatticeBasis::bernstein ? "bernstein" : "bspline") + "_strain",
                   std::to_string(classic_strain) + " classic, " + std::to_string(motor_strain) + " motor");
    EXPECT_LT(motor_strain, 0.85 * classic_strain) << classic_strain << " classic, " << motor_strain << " motor";
  }
}

// A frame runs a single-precision kernel over blocks of vertices (rigid blends) and the double
// exp for dilating ones: both equal the per-vertex blend to float precision.
TEST(Ffd, MotorFramesEqualThePerVertexBlend) {
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  const double d = diagonal(rest);
  for (const Lattice& l : lattices(rest))
    for (const bool dilate : {false, true}) {
      const FreeFormDeformation ffd(rest, l);
      const auto motors = cgamesh_deform_test::varied_motors(static_cast<std::size_t>(l.count()), dilate);
      mesh::RowMatrixXf<3> out;
      ffd.deform_motors(motors, out);
      EXPECT_LE(max_difference(out, cgamesh_deform_test::blended_reference(ffd, rest, motors)), 2e-6 * d);
    }
}

TEST(Ffd, VerticesOutsideTheBoxStayInPlace) {
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  Lattice l;
  l.box = deform::bounding_lattice_box(rest, 0.01);
  l.box.size[1] *= 0.5;  // the lower half
  const FreeFormDeformation ffd(rest, l);
  ASSERT_FALSE(ffd.outside().empty());
  const Versor shift(cga::translator(Eigen::Vector3d(1, 2, 3)));
  mesh::RowMatrixXf<3> out;
  ffd.deform_motors(std::vector<Versor>(static_cast<std::size_t>(l.count()), shift), out);
  for (const int v : ffd.outside()) EXPECT_EQ(out.row(v), rest.row(v));
  EXPECT_TRUE(ffd.weights(ffd.outside().front()).empty());
}

TEST(Ffd, BadLatticesAndFramesThrow) {
  const mesh::RowMatrixXf<3>& rest = cesium_man().positions;
  Lattice l;
  l.box = deform::bounding_lattice_box(rest, 0.01);
  Lattice bad = l;
  bad.resolution = {1, 2, 2};
  EXPECT_THROW(FreeFormDeformation(rest, bad), InvalidInputError);
  bad = l;
  bad.box.size[2] = 0;
  EXPECT_THROW(FreeFormDeformation(rest, bad), InvalidInputError);
  bad = l;
  bad.box.rotation(0, 0) = 2;
  EXPECT_THROW(FreeFormDeformation(rest, bad), InvalidInputError);
  EXPECT_THROW((void)deform::bounding_lattice_box(mesh::RowMatrixXf<3>(0, 3), 0.01), InvalidInputError);
  EXPECT_THROW((void)deform::bounding_lattice_box(rest, -1), InvalidInputError);
  const FreeFormDeformation ffd(rest, l);
  mesh::RowMatrixXf<3> out;
  EXPECT_THROW(ffd.deform_points(std::vector<Eigen::Vector3d>(3), out), InvalidInputError);
  EXPECT_THROW(ffd.deform_motors(std::vector<Versor>(3, kIdentity), out), InvalidInputError);
}

// --- the spec ---

/// CesiumMan's skin alone, static (a spec then acts in mesh space).
anim::RiggedModel man_model() {
  anim::RiggedModel model;
  model.meshes.push_back(cesium_man());
  model.meshes[0].skin = {};
  return model;
}

std::string message_of(const std::string& text) {
  try {
    const deform::DeformSpec s = deform::parse_spec(text, "test.json");
    (void)deform::BoundDeformer(s, man_model());
  } catch (const InvalidInputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(FfdSpec, ReadsEveryField) {
  const deform::DeformSpec s = deform::parse_spec(R"({"method": "ffd", "variant": "classic",
      "lattice": {"resolution": [2, 3, 4], "basis": "bspline", "ends": "repeat",
                  "box": {"origin": [1, 2, 3], "size": [4, 5, 6], "rotate": [0, 0, 1, 90]}},
      "handles": [[[0, 0, 0], [1, 2, 3]], {"box": [0, 0, 0, 1, 1, 1]}], "keys": [{}, {"translate": [1, 0, 0]}]})",
                                                  "inline");
  EXPECT_EQ(s.method(), deform::DeformMethod::ffd);
  const auto& f = std::get<deform::FfdSpec>(s.fields);
  EXPECT_EQ(f.variant, deform::FfdVariant::classic);
  EXPECT_EQ(f.lattice.resolution, (std::array<int, 3>{2, 3, 4}));
  EXPECT_EQ(f.lattice.basis, LatticeBasis::bspline);
  EXPECT_EQ(f.lattice.ends, BsplineEnds::repeat);
  ASSERT_TRUE(f.lattice.box.has_value());
  EXPECT_EQ(f.lattice.box->origin, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(f.lattice.box->size, Eigen::Vector3d(4, 5, 6));
  EXPECT_TRUE(f.lattice.box->rotation.isApprox(
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()));
  ASSERT_EQ(s.handles.size(), 2U);
  EXPECT_EQ(s.handles[0].kind, deform::HandleSelection::Kind::lattice_points);
  EXPECT_EQ(s.handles[0].points[1], (std::array<int, 3>{1, 2, 3}));
  EXPECT_EQ(s.handles[1].kind, deform::HandleSelection::Kind::box);
  const deform::DeformSpec d = deform::parse_spec(R"({"method": "ffd", "handles": [], "keys": []})", "inline");
  const auto& g = std::get<deform::FfdSpec>(d.fields);
  EXPECT_EQ(g.variant, deform::FfdVariant::motor);
  EXPECT_EQ(g.lattice.resolution, (std::array<int, 3>{2, 2, 2}));
  EXPECT_FALSE(g.lattice.box.has_value());
  EXPECT_STREQ(deform::method_name(d.method()), "ffd");
}

TEST(FfdSpec, ErrorsNameTheField) {
  const std::string handles = R"("handles": [[[0, 0, 0]]], "keys": [{}])";
  const std::pair<std::string, const char*> cases[] = {
      {R"({"method": "ffd", "variant": "soft", )" + handles + "}", "spec.variant: "},
      {R"({"method": "ffd", "lattice": [2, 2, 2], )" + handles + "}", "spec.lattice: "},
      {R"({"method": "ffd", "lattice": {"resolution": [2, 1, 2]}, )" + handles + "}", "spec.lattice.resolution: "},
      {R"({"method": "ffd", "lattice": {"resolution": [2, 2]}, )" + handles + "}", "spec.lattice.resolution: "},
      {R"({"method": "ffd", "lattice": {"basis": "nurbs"}, )" + handles + "}", "spec.lattice.basis: "},
      {R"({"method": "ffd", "lattice": {"basis": "bspline", "ends": "open"}, )" + handles + "}", "spec.lattice.ends: "},
      {R"({"method": "ffd", "lattice": {"ends": "repeat"}, )" + handles + "}", "spec.lattice.ends: "},
      {R"({"method": "ffd", "lattice": {"margin": -0.1}, )" + handles + "}", "spec.lattice.margin: "},
      {R"({"method": "ffd", "lattice": {"margin": 0.1, "box": {"origin": [0, 0, 0], "size": [1, 1, 1]}}, )" + handles +
           "}",
       "spec.lattice.margin: "},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0, 0]}}, )" + handles + "}", "spec.lattice.box: "},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0], "size": [1, 1, 1]}}, )" + handles + "}",
       "spec.lattice.box.origin: "},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0, 0], "size": [1, 0, 1]}}, )" + handles + "}",
       "spec.lattice.box.size: "},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0, 0], "size": [1, 1, 1], "rotate": [0, 0, 0, 5]}}, )" +
           handles + "}",
       "spec.lattice.box.rotate: "},
      {R"({"method": "ffd", "lattice": {"box": {"origin": [0, 0, 0], "size": [1, 1, 1], "spin": 1}}, )" + handles + "}",
       "spec.lattice.box.spin: "},
      {R"({"method": "ffd", "lattice": {"grid": 1}, )" + handles + "}", "spec.lattice.grid: "},
      {R"({"method": "ffd", "handles": [[[0, 0, 2]]], "keys": [{}]})", "spec.handles[0]: "},
      {R"({"method": "ffd", "handles": [[0, 1]], "keys": [{}]})", "spec.handles[0]: "},
      {R"({"method": "ffd", "handles": [[]], "keys": [{}]})", "spec.handles[0]: "},
      {R"({"method": "ffd", "handles": [{"box": [1e6, 1e6, 1e6, 2e6, 2e6, 2e6]}], "keys": [{}]})", "spec.handles[0].box: "},
      {R"({"method": "ffd", "handles": [[[0, 0, 0]]], "keys": [{}, {}]})", "spec.keys: "},
      {R"({"method": "ffd", "handles": [[[0, 0, 0]]], "keys": [{"rotate": [0, 0, 0, 1]}]})", "spec.keys[0].rotate: "},
      {R"({"method": "ffd", "basis": "bspline", )" + handles + "}", "spec.basis: "},
      {R"({"method": "ffd", "weights": "cotangent", )" + handles + "}", "spec.weights: "},
      {R"({"method": "harmonic", "lattice": {}, "handles": [[0]], "keys": [{}]})", "spec.lattice: "},
      {R"({"method": "harmonic", "variant": "motor", "handles": [[0]], "keys": [{}]})", "spec.variant: "},
  };
  for (const auto& [text, field] : cases)
    EXPECT_NE(message_of(text).find(field), std::string::npos) << text << "\n" << message_of(text);
}

// The spec's keys compose per control point and reach the FreeFormDeformation it binds.
TEST(FfdSpec, BindEqualsTheDirectLattice) {
  const anim::RiggedModel model = man_model();
  for (const char* variant : {"classic", "motor"}) {
    const deform::DeformSpec s =
        deform::parse_spec(std::string(R"({"method": "ffd", "space": "mesh", "variant": ")") + variant + R"(",
            "lattice": {"resolution": [2, 3, 2], "basis": "bspline"},
            "handles": [[[0, 2, 0], [1, 2, 0]], [[1, 2, 0], [1, 2, 1]]],
            "keys": [{"translate": [0.1, 0, 0]}, {"rotate": [0, 1, 0, 30], "center": [0, 1, 0]}]})",
                           "inline");
    const deform::BoundDeformer bound(s, model);
    ASSERT_NE(bound.method().ffd(), nullptr);
    EXPECT_EQ(bound.control_handles(), (std::vector<std::vector<int>>{{4, 5}, {5, 11}}));
    EXPECT_EQ(bound.handles().size(), 2U);
    const Lattice& l = bound.method().ffd()->lattice();
    std::vector<Versor> motors(static_cast<std::size_t>(l.count()), kIdentity);
    motors[4] = bound.keys()[0];
    motors[5] = cga::project<cga::mask::versor>(bound.keys()[1] * bound.keys()[0]);
    motors[11] = bound.keys()[1];
    std::vector<Eigen::Vector3d> points = l.control_points();
    for (std::size_t c = 0; c < points.size(); ++c) {
      const Eigen::Matrix<double, 3, 4> m = cga::PointMap<double>(motors[c]).affine_matrix();
      points[c] = m.leftCols<3>() * points[c] + m.col(3);
    }
    mesh::RowMatrixXf<3> expected;
    if (std::string(variant) == "motor")
      bound.method().ffd()->deform_motors(motors, expected);
    else
      bound.method().ffd()->deform_points(points, expected);
    // What a viewer draws: the moved control points and the 1·3·2 + 2·2·2 + 2·3·1 lattice edges.
    const std::vector<Eigen::Vector3d> drawn = bound.control_points(bound.keys());
    ASSERT_EQ(drawn.size(), points.size());
    for (std::size_t c = 0; c < points.size(); ++c) EXPECT_LT((drawn[c] - points[c]).norm(), 1e-12) << c;
    ASSERT_EQ(bound.control_edges().size(), 20U);
    for (const auto& [a, b] : bound.control_edges()) {
      const int step = b - a;
      EXPECT_TRUE(step == 1 || step == 2 || step == 6) << a << " " << b;
    }
    const mesh::RowMatrixXf<3> out = bound.apply(bound.keys());
    EXPECT_LT(max_difference(out, expected), 1e-6) << variant;
    EXPECT_GT(max_difference(out, cesium_man().positions), 0.01) << variant;
    EXPECT_THROW((void)bound.apply(std::vector<Versor>(1, kIdentity)), InvalidInputError);
  }
}

}  // namespace
