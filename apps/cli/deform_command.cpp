// cgamesh deform MESH --spec SPEC.json -o OUT: spline-aligned (paper section III, with FABRIK
// from III.C) or harmonic-coordinate (section IV) deformation. The spec format is documented in
// README.md ("Deformation specs").
#include "deform_command.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cgamesh/cga/versors.hpp"
#include "cgamesh/deform/fabrik.hpp"
#include "cgamesh/deform/harmonic_handles.hpp"
#include "cgamesh/deform/spline_deform.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/io/mesh_writer.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "cli_common.hpp"

namespace cgamesh::cli {
namespace {

using Json = nlohmann::json;
using cga::Versor;

[[noreturn]] void bad(const std::string& field, const std::string& what) {
  throw InvalidInputError("spec." + field + ": " + what);
}

/// Exactly `count` finite numbers.
std::vector<double> numbers(const Json& j, std::size_t count, const std::string& field) {
  if (!j.is_array() || j.size() != count) bad(field, "expected an array of " + std::to_string(count) + " numbers");
  std::vector<double> out;
  for (const Json& x : j) {
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      bad(field, "expected " + std::to_string(count) + " finite numbers");
    out.push_back(x.get<double>());
  }
  return out;
}

template <class E>
E choice(const Json& spec, const std::string& field, const std::map<std::string, E>& names, E fallback) {
  if (!spec.contains(field)) return fallback;
  const Json& j = spec[field];
  if (j.is_string()) {
    const auto it = names.find(j.get<std::string>());
    if (it != names.end()) return it->second;
  }
  std::string list;
  for (const auto& [name, value] : names) list += (list.empty() ? "" : ", ") + name;
  bad(field, "expected one of " + list);
}

int integer(const Json& spec, const std::string& field, int fallback) {
  if (!spec.contains(field)) return fallback;
  if (!spec[field].is_number_integer()) bad(field, "expected an integer");
  return spec[field].get<int>();
}

/// A handle: vertex indices, {"sphere": [x, y, z, r]} or {"box": [x0, y0, z0, x1, y1, z1]}.
std::vector<int> select_handle(const Json& j, const mesh::Mesh& m, const std::string& field) {
  std::vector<int> out;
  if (j.is_array()) {
    for (const Json& x : j) {
      if (!x.is_number_integer() || x.get<long long>() < 0 || x.get<long long>() >= m.vertex_count())
        bad(field, "expected vertex indices in [0, " + std::to_string(m.vertex_count()) + ")");
      out.push_back(x.get<int>());
    }
  } else if (j.is_object() && j.size() == 1 && (j.contains("sphere") || j.contains("box"))) {
    const bool sphere = j.contains("sphere");
    const auto v = sphere ? numbers(j["sphere"], 4, field + ".sphere") : numbers(j["box"], 6, field + ".box");
    for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
      const Eigen::Vector3d p = m.positions.row(i).transpose().cast<double>();
      const bool in = sphere ? (p - Eigen::Vector3d(v[0], v[1], v[2])).norm() <= v[3]
                             : (p.array() >= Eigen::Array3d(v[0], v[1], v[2])).all() &&
                                   (p.array() <= Eigen::Array3d(v[3], v[4], v[5])).all();
      if (in) out.push_back(static_cast<int>(i));
    }
  } else {
    bad(field, "expected a list of vertex indices, {\"sphere\": [x, y, z, r]} or {\"box\": [x0, y0, z0, x1, y1, z1]}");
  }
  if (out.empty()) bad(field, "selects no vertex");
  return out;
}

/// A key: x -> scale R (x - center) + center + translate, every part optional.
Versor<double> key_versor(const Json& j, const std::string& field) {
  if (!j.is_object()) bad(field, "expected an object with rotate, translate, scale and/or center");
  for (const auto& [name, value] : j.items())
    if (name != "rotate" && name != "translate" && name != "scale" && name != "center")
      bad(field + "." + name, "unknown field (rotate, translate, scale, center)");
  Eigen::Vector3d t = Eigen::Vector3d::Zero(), c = Eigen::Vector3d::Zero();
  cga::Rotor<double> r({1.0, 0.0, 0.0, 0.0});
  double s = 1.0;
  if (j.contains("translate")) {
    const auto v = numbers(j["translate"], 3, field + ".translate");
    t = {v[0], v[1], v[2]};
  }
  if (j.contains("center")) {
    const auto v = numbers(j["center"], 3, field + ".center");
    c = {v[0], v[1], v[2]};
  }
  if (j.contains("rotate")) {
    const auto v = numbers(j["rotate"], 4, field + ".rotate");
    if (Eigen::Vector3d(v[0], v[1], v[2]).norm() == 0) bad(field + ".rotate", "the axis is the zero vector");
    r = cga::rotor(Eigen::Vector3d(v[0], v[1], v[2]), v[3] * std::numbers::pi / 180.0);
  }
  if (j.contains("scale")) {
    if (!j["scale"].is_number() || !(j["scale"].get<double>() > 0) || !std::isfinite(j["scale"].get<double>()))
      bad(field + ".scale", "expected a finite number > 0");
    s = j["scale"].get<double>();
  }
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  return cga::project<cga::mask::versor>(cga::translator(Eigen::Vector3d(c + t)) * cga::similarity(origin, r, s) *
                                         cga::translator(Eigen::Vector3d(-c)));
}

Json read_spec(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw FileError("cannot read the spec " + path + ": is a directory");
  std::ifstream in(path);
  if (!in) throw FileError("cannot read the spec " + path);
  std::stringstream text;
  text << in.rdbuf();
  try {
    Json spec = Json::parse(text.str());
    if (!spec.is_object()) throw InvalidInputError("spec " + path + ": expected a JSON object");
    return spec;
  } catch (const Json::parse_error& e) {
    throw InvalidInputError("spec " + path + " is not valid JSON: " + e.what());
  }
}

double milliseconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

struct DeformCommand {
  std::string model, spec_path, output;
  bool json = false, force = false;

  void run() {
    check_extension(output, {".obj", ".ply"}, "deform");
    check_outputs({output}, {model, spec_path}, force);
    const Json spec = read_spec(spec_path);
    for (const auto& [name, value] : spec.items())
      if (name != "method" && name != "mesh" && name != "weights" && name != "handles" && name != "keys" &&
          name != "basis" && name != "degree" && name != "ik")
        bad(name, "unknown field (method, mesh, weights, handles, keys, basis, degree, ik)");
    enum class Method { spline, harmonic };
    if (!spec.contains("method")) bad("method", "missing (spline or harmonic)");
    const Method method =
        choice<Method>(spec, "method", {{"spline", Method::spline}, {"harmonic", Method::harmonic}}, Method::spline);
    deform::HarmonicOptions harmonic;
    harmonic.weights = choice<deform::LaplacianWeights>(
        spec, "weights",
        {{"mean_value", deform::LaplacianWeights::mean_value}, {"cotangent", deform::LaplacianWeights::cotangent}},
        deform::LaplacianWeights::mean_value);

    const anim::RiggedModel m = cli::load_model(model);
    const int mesh_index = integer(spec, "mesh", 0);
    if (mesh_index < 0 || mesh_index >= static_cast<int>(m.meshes.size()))
      bad("mesh", "no mesh " + std::to_string(mesh_index) + " (the model has " + std::to_string(m.meshes.size()) + ")");
    const mesh::Mesh& target = m.meshes[static_cast<std::size_t>(mesh_index)];

    if (!spec.contains("handles") || !spec["handles"].is_array()) bad("handles", "missing, or not an array");
    std::vector<std::vector<int>> handles;
    for (std::size_t h = 0; h < spec["handles"].size(); ++h)
      handles.push_back(select_handle(spec["handles"][h], target, "handles[" + std::to_string(h) + "]"));

    Json ik_summary;
    std::vector<Versor<double>> keys;
    if (spec.contains("ik")) {
      if (method != Method::spline) bad("ik", "only the spline method takes an IK chain");
      const Json& ik = spec["ik"];
      if (!ik.is_object() || !ik.contains("joints") || !ik["joints"].is_array() || !ik.contains("target"))
        bad("ik", "expected {\"joints\": [[x, y, z], ...], \"target\": [x, y, z]}");
      std::vector<Eigen::Vector3d> joints;
      for (std::size_t i = 0; i < ik["joints"].size(); ++i) {
        const auto v = numbers(ik["joints"][i], 3, "ik.joints[" + std::to_string(i) + "]");
        joints.emplace_back(v[0], v[1], v[2]);
      }
      const auto t = numbers(ik["target"], 3, "ik.target");
      const deform::FabrikResult r = deform::fabrik(joints, Eigen::Vector3d(t[0], t[1], t[2]));
      keys.assign(r.motors.begin(), r.motors.end());
      ik_summary = {{"reached", r.reached}, {"distance", r.distance}, {"iterations", r.iterations}};
      if (spec.contains("keys")) bad("keys", "give either keys or ik, not both");
    } else {
      if (!spec.contains("keys") || !spec["keys"].is_array()) bad("keys", "missing, or not an array");
      for (std::size_t k = 0; k < spec["keys"].size(); ++k)
        keys.push_back(key_versor(spec["keys"][k], "keys[" + std::to_string(k) + "]"));
    }
    const std::vector<Versor<double>> rest(keys.size(), Versor<double>(cga::basis_blade<double, cga::blade::scalar>()));

    const auto start_bind = std::chrono::steady_clock::now();
    std::unique_ptr<deform::MotorBlend> bound;
    if (method == Method::spline) {
      if (handles.size() != 2) bad("handles", "the spline method takes 2 handles (lambda = 0 and lambda = 1)");
      deform::SplineOptions options;
      options.harmonic = harmonic;
      options.basis = choice<deform::SplineBasis>(spec, "basis",
                                                  {{"linear", deform::SplineBasis::linear},
                                                   {"quadratic_lagrange", deform::SplineBasis::quadratic_lagrange},
                                                   {"bezier", deform::SplineBasis::bezier},
                                                   {"bspline", deform::SplineBasis::bspline}},
                                                  deform::SplineBasis::bspline);
      options.degree = integer(spec, "degree", 3);
      std::vector<double> probe(keys.size());
      try {
        deform::spline_weights(options, 0.0, probe);
      } catch (const InvalidInputError& e) {
        bad(spec.contains("ik") ? "ik.joints" : "keys", e.what());
      }
      bound = std::make_unique<deform::MotorBlend>(deform::bind_spline(target, handles[0], handles[1], rest, options));
    } else {
      if (handles.size() != keys.size())
        bad("keys",
            std::to_string(keys.size()) + " keys for " + std::to_string(handles.size()) + " handles (one per handle)");
      bound = std::make_unique<deform::MotorBlend>(deform::bind_harmonic_handles(target, handles, rest, harmonic));
    }
    const double bind_ms = milliseconds_since(start_bind);
    const auto start = std::chrono::steady_clock::now();
    std::vector<mesh::RowMatrixXf<3>> positions;
    for (const mesh::Mesh& each : m.meshes) positions.push_back(each.positions);
    bound->deform(keys, positions[static_cast<std::size_t>(mesh_index)]);
    const double deform_ms = milliseconds_since(start);
    const io::EncodedFile file = io::encode_mesh(m.meshes, positions, output);
    io::write_files_atomically(std::span<const io::EncodedFile>(&file, 1));

    Json handle_sizes = Json::array();
    for (const auto& h : handles) handle_sizes.push_back(h.size());
    Json summary = {{"output", output},
                    {"method", method == Method::spline ? "spline" : "harmonic"},
                    {"mesh", mesh_index},
                    {"vertices", target.vertex_count()},
                    {"handle_vertices", handle_sizes},
                    {"keys", keys.size()},
                    {"bind_milliseconds", bind_ms},
                    {"deform_milliseconds", deform_ms},
                    {"pose", {{"kind", "bind"}, {"space", "mesh"}}},
                    {"warnings", m.warnings}};
    if (!ik_summary.is_null()) summary["ik"] = ik_summary;
    if (json) {
      std::cout << dump_json(summary) << "\n";
      return;
    }
    std::cout << "deform " << model << " (" << summary["method"].get<std::string>() << ", " << keys.size() << " keys, "
              << target.vertex_count() << " vertices, bind pose in mesh space): bind " << bind_ms << " ms, frame "
              << deform_ms << " ms\n  -> " << output << "\n";
    if (!ik_summary.is_null() && !ik_summary["reached"].get<bool>())
      std::cout << "  warning: the IK target is out of reach (" << ik_summary["distance"].get<double>() << " away)\n";
  }
};

}  // namespace

void add_deform(CLI::App& app) {
  auto c = std::make_shared<DeformCommand>();
  auto* sub = app.add_subcommand(
      "deform",
      "motor-handle deformation (spline-aligned or harmonic coordinates) from a JSON spec; acts on the bind pose "
      "in mesh space (the mesh-space boxes of `info`)");
  sub->add_option("MESH", c->model, "model file (.obj, .ply, .glb, ...)")->required();
  sub->add_option("--spec", c->spec_path, "SPEC.json: method, handles, keys (see README, Deformation specs)")
      ->required();
  sub->add_option("-o,--output", c->output, "OUT: .obj or .ply, every mesh of the model, the chosen one deformed")
      ->required();
  add_force(*sub, c->force);
  sub->add_flag("--json", c->json, "print a machine-readable summary");
  sub->callback([c] { c->run(); });
}

}  // namespace cgamesh::cli
