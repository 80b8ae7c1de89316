#include "algebra_demo.hpp"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cgamesh/cga.hpp"
#include "cgamesh/errors.hpp"

#include "cli_common.hpp"

namespace cgamesh::cli {
namespace {

using namespace cgamesh::cga;
using V3 = Vec3<double>;

struct DemoOptions {
  std::vector<double> translate{1.0, 0.5, -2.0};
  std::vector<double> axis{0.0, 1.0, 1.0};
  double angle_deg = 120.0;
  double scale = 1.5;
  std::vector<double> point{1.0, 0.0, 0.0};
  double radius = 0.5;
  int steps = 5;
  bool json = false;
};

V3 vec3(const std::vector<double>& v) { return V3(v[0], v[1], v[2]); }
nlohmann::ordered_json to_json(const V3& v) { return nlohmann::ordered_json::array({v.x(), v.y(), v.z()}); }
std::string fmt(const V3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%8.4f, %8.4f, %8.4f)", v.x(), v.y(), v.z());
  return buf;
}

void run(const DemoOptions& o) {
  if (o.steps < 1) throw InvalidInputError("--steps must be at least 1");
  const V3 t = vec3(o.translate), x = vec3(o.point);
  const Rotor<double> r = rotor(vec3(o.axis), o.angle_deg * std::numbers::pi / 180.0);
  const Versor<double> v = similarity(t, r, o.scale);
  const Eigen::Matrix4d m = to_matrix(v);
  const auto affine = [&](const V3& p) -> V3 { return m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>(); };

  // A point, a sphere and a plane through the same versor, and the matrix's answer.
  const V3 xp = down(sandwich(v, up(x)));
  const SphereParameters<double> sp = sphere_parameters(sandwich(v, sphere(x, o.radius)));
  const V3 n0(0, 0, 1);
  const auto [np, dp] = plane_parameters(sandwich(v, plane(n0, x.z())));
  const V3 n_matrix = (m.topLeftCorner<3, 3>() * n0).normalized();
  const double d_matrix = n_matrix.dot(affine(x));

  // Keyframes: identity and V, blended linearly and logarithmically (paper Fig. 1).
  const Versor<double> identity(basis_blade<double, blade::scalar>());
  nlohmann::ordered_json path = nlohmann::ordered_json::array();
  for (int i = 0; i <= o.steps; ++i) {
    const double a = static_cast<double>(i) / o.steps;
    path.push_back({{"alpha", a},
                    {"linear", to_json(down(sandwich(lerp_normalized(identity, v, a), up(x))))},
                    {"log", to_json(down(sandwich(log_blend(identity, v, a), up(x))))}});
  }

  nlohmann::ordered_json coeffs = nlohmann::ordered_json::object();
  for (std::size_t i = 0; i < Versor<double>::size; ++i)
    if (v[i] != 0.0) coeffs[std::string(blade_name(Versor<double>::blades[i]))] = v[i];

  nlohmann::ordered_json out = {
      {"versor", coeffs},
      {"point", {{"in", to_json(x)}, {"cga", to_json(xp)}, {"matrix", to_json(affine(x))}}},
      {"sphere",
       {{"cga", {{"center", to_json(sp.center)}, {"radius", sp.radius}}},
        {"matrix", {{"center", to_json(affine(x))}, {"radius", o.scale * o.radius}}}}},
      {"plane",
       {{"cga", {{"normal", to_json(np)}, {"distance", dp}}},
        {"matrix", {{"normal", to_json(n_matrix)}, {"distance", d_matrix}}}}},
      {"blend", path}};
  if (o.json) {
    std::cout << cgamesh::cli::dump_json(out) << "\n";
    return;
  }
  std::cout << "TRS versor V = T(t) R(axis, angle) D(s) in the null basis (e1, e2, e3, einf, eo):\n  ";
  for (const auto& [name, value] : coeffs.items()) std::cout << name << "=" << value.get<double>() << "  ";
  std::cout << "\n\n"
            << "point   " << fmt(x) << "  V X V^-1 -> " << fmt(xp) << "   matrix -> " << fmt(affine(x)) << "\n"
            << "sphere  r=" << o.radius << "  -> centre " << fmt(sp.center) << " r=" << sp.radius
            << "   matrix -> " << fmt(affine(x)) << " r=" << o.scale * o.radius << "\n"
            << "plane   z=" << x.z() << "  -> n " << fmt(np) << " d=" << dp << "   matrix -> n " << fmt(n_matrix)
            << " d=" << d_matrix << "\n\n"
            << "blending identity -> V, path of the point (linear renormalised | logarithmic):\n";
  for (const auto& row : path)
    std::cout << "  alpha " << std::fixed << std::setprecision(2) << row["alpha"].get<double>() << "  " << fmt(V3(row["linear"][0], row["linear"][1], row["linear"][2]))
              << "  " << fmt(V3(row["log"][0], row["log"][1], row["log"][2])) << "\n";
}

}  // namespace

void add_algebra_demo(CLI::App& app) {
  auto opts = std::make_shared<DemoOptions>();
  CLI::App* sub = app.add_subcommand("algebra-demo", "Transform a point, sphere and plane by a TRS versor; blend keyframes");
  sub->add_option("--translate", opts->translate, "translation X,Y,Z")->delimiter(',')->expected(3)->capture_default_str();
  sub->add_option("--axis", opts->axis, "rotation axis X,Y,Z")->delimiter(',')->expected(3)->capture_default_str();
  sub->add_option("--angle", opts->angle_deg, "rotation angle in degrees")->capture_default_str();
  sub->add_option("--scale", opts->scale, "uniform scale (> 0)")->capture_default_str();
  sub->add_option("--point", opts->point, "point X,Y,Z to transform")->delimiter(',')->expected(3)->capture_default_str();
  sub->add_option("--radius", opts->radius, "radius of the sphere around the point")->capture_default_str();
  sub->add_option("--steps", opts->steps, "blend steps")->capture_default_str();
  sub->add_flag("--json", opts->json, "print a machine-readable summary");
  sub->callback([opts] { run(*opts); });
}

}  // namespace cgamesh::cli
