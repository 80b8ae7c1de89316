// cgamesh deform MODEL --spec SPEC.json -o OUT: loads, parses, binds and applies a deformation
// spec (deform/spec.hpp; the format is documented in README.md, "Deformation specs") and writes
// the result.
#include "deform_command.hpp"

#include <chrono>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/io/model_writer.hpp"

#include "cli_common.hpp"

namespace cgamesh::cli {
namespace {

double milliseconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

struct DeformCommand {
  std::string model, spec_path, output;
  bool json = false, force = false;

  void run() {
    check_extension(output, io::kModelExtensions, "deform");
    check_outputs({output}, {model, spec_path}, force);
    const deform::DeformSpec spec = deform::read_spec(spec_path);
    const anim::RiggedModel m = cli::load_model(model);

    const auto start_bind = std::chrono::steady_clock::now();
    const deform::BoundDeformer bound(spec, m);
    const double bind_ms = milliseconds_since(start_bind);
    const auto start = std::chrono::steady_clock::now();
    mesh::RowMatrixXf<3> deformed;
    deform::ArapReport arap;
    bound.apply(bound.keys(), deformed, &arap);
    const double deform_ms = milliseconds_since(start);

    std::vector<std::string> warnings = m.warnings;
    const std::vector<std::string> more = bound.write(m, deformed, output);
    warnings.insert(warnings.end(), more.begin(), more.end());

    const bool world = bound.space() == deform::DeformSpace::world;
    Json handle_sizes = Json::array();
    for (const auto& h : bound.handles()) handle_sizes.push_back(h.size());
    Json summary = {{"output", output},
                    {"method", deform::method_name(spec.method())},
                    {"mesh", bound.mesh_index()},
                    {"vertices", bound.vertex_count()},
                    {"handle_vertices", handle_sizes},
                    {"free_vertices", bound.free_vertices().size()},
                    {"keys", bound.keys().size()},
                    {"bind_milliseconds", bind_ms},
                    {"deform_milliseconds", deform_ms},
                    {"pose", {{"kind", "bind"}, {"space", world ? "world" : "mesh"}}},
                    {"warnings", warnings}};
    if (const deform::FreeFormDeformation* ffd = bound.method().ffd()) {
      Json points = Json::array();
      for (const auto& h : bound.control_handles()) points.push_back(h.size());
      summary["control_points"] = ffd->lattice().count();
      summary["handle_control_points"] = points;
    }
    if (spec.method() == deform::DeformMethod::arap)
      summary["arap"] = {{"iterations", arap.iterations}, {"energies", arap.energies}};
    if (const deform::CageDeformation* cage = bound.method().cage()) {
      Json points = Json::array();
      for (const auto& h : bound.control_handles()) points.push_back(h.size());
      summary["cage_vertices"] = cage->cage_vertex_count();
      summary["handle_cage_vertices"] = points;
      summary["mean_coordinates_kept"] = cage->mean_weights();
    }
    const auto& ik = bound.ik();
    if (ik) summary["ik"] = {{"reached", ik->reached}, {"distance", ik->distance}, {"iterations", ik->iterations}};
    if (json) {
      std::cout << dump_json(summary) << "\n";
      return;
    }
    std::cout << "deform " << model << " (" << summary["method"].get<std::string>() << ", " << bound.keys().size()
              << " keys, " << bound.vertex_count() << " vertices, bind pose in " << (world ? "world" : "mesh")
              << " space): bind " << bind_ms << " ms, frame " << deform_ms << " ms\n  -> " << output << "\n";
    if (!bound.free_vertices().empty() && bound.method().ffd())
      std::cout << "  " << bound.free_vertices().size() << " vertices outside the lattice box stay in place\n";
    else if (!bound.free_vertices().empty())
      std::cout << "  " << bound.free_vertices().size() << " vertices in parts without a handle "
                << (spec.free_parts() == deform::FreeParts::nearest ? "move with the nearest handle" : "stay in place")
                << "\n";
    if (spec.method() == deform::DeformMethod::arap)
      std::cout << "  ARAP: " << arap.iterations << " iterations, energy " << arap.energies.front() << " -> "
                << arap.energies.back() << "\n";
    if (ik && !ik->reached) std::cout << "  warning: the IK target is out of reach (" << ik->distance << " away)\n";
  }
};

}  // namespace

void add_deform(CLI::App& app) {
  auto c = std::make_shared<DeformCommand>();
  auto* sub = app.add_subcommand(
      "deform",
      "motor-handle deformation (spline-aligned, harmonic coordinates, free-form lattice, harmonic cage or "
      "as-rigid-as-possible) from a JSON "
      "spec; acts on "
      "the bind pose "
      "in world space for a rigged model (the boxes of `info`), else in mesh space (\"space\" in the spec chooses)");
  sub->add_option("MESH", c->model, "model file (.obj, .ply, .glb, ...)")->required();
  sub->add_option("--spec", c->spec_path, "SPEC.json: method, handles, keys (see README, Deformation specs)")
      ->required();
  sub->add_option(
         "-o,--output", c->output,
         "OUT: .glb/.gltf (the model with its skin, skeleton and clips, the mesh's rest shape edited), or .obj/.ply "
         "(every mesh in the spec's space, the chosen one deformed)")
      ->required();
  add_force(*sub, c->force);
  sub->add_flag("--json", c->json, "print a machine-readable summary");
  sub->callback([c] { c->run(); });
}

}  // namespace cgamesh::cli
