#include "surgery_commands.hpp"

#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/io/surgery_stats.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/soft/soft_operation.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"
#include "cgamesh/surgery/tear.hpp"

#include "cli_common.hpp"

namespace cgamesh::cli {
namespace {

/// The files of one result: a rigged glTF (skin, skeleton, clips), or for OBJ/PLY the surface
/// as placed (the pose the tool was used in), with its normals (surgery::placed_normals).
std::vector<io::EncodedFile> encode_result(const anim::RiggedModel& model,
                                           const std::vector<mesh::RowMatrixXf<3>>& placed, const anim::Pose& pose,
                                           const std::string& out) {
  return io::encode_model(model, out, [&] { return mesh::WorldSurface{placed, surgery::placed_normals(model, pose)}; });
}

double milliseconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// What every surgery command shares: the model, where the tool is placed, the predicates and
/// how the result is reported.
struct SurgeryCommand {
  std::string model;
  PoseChoice placement{"place the tool against this animation"};
  bool euclidean = false;
  bool json = false;
  bool force = false;
  std::string rest_position = "exact";

  /// The model loaded, placed and (for the local tools) indexed.
  struct Scene {
    anim::RiggedModel model;
    surgery::Placement placement;
    surgery::SurfaceIndex index;
    PoseChoice::Chosen pose;  ///< the pose the tool is placed against
    double milliseconds = 0;  ///< placing and indexing, not loading
  };

  /// Refuses outputs of another type or that would overwrite the input (before loading).
  void check(const std::vector<std::string>& outputs, const std::string& command) const {
    for (const std::string& o : outputs) check_extension(o, io::kModelExtensions, command);
    check_outputs(outputs, {model}, force);
  }

  [[nodiscard]] Scene load(bool with_index) const {
    Scene s;
    s.model = cli::load_model(model);
    s.pose = placement.choose(s.model);
    for (const std::string& w : s.pose.warnings) std::cerr << "cgamesh: warning: " << w << "\n";
    const auto start = std::chrono::steady_clock::now();
    s.placement = surgery::place(s.model, s.pose.pose);
    if (with_index) s.index = surgery::SurfaceIndex::build(s.model, s.placement);
    s.milliseconds = milliseconds_since(start);
    return s;
  }

  [[nodiscard]] surgery::Predicates predicates() const {
    return euclidean ? surgery::Predicates::euclidean : surgery::Predicates::cga;
  }

  [[nodiscard]] surgery::RestPosition rest() const {
    return io::value_by_name(io::kRestPositions, rest_position, "--rest");
  }

  /// Runs `operation` and returns its result; `ms` gets its time alone.
  template <class Operation>
  [[nodiscard]] static auto timed(Operation&& operation, double& ms) {
    const auto start = std::chrono::steady_clock::now();
    auto result = operation();
    ms = milliseconds_since(start);
    return result;
  }

  /// Prints the --json summary (timings and predicates first, then `fields`), or `line` and
  /// the warnings.
  void report(const Json& outputs, double ms, const Scene& scene, const Json& fields, const std::string& line,
              const std::vector<std::string>& warnings) const {
    Json summary = {{outputs.is_array() ? "outputs" : "output", outputs},
                    {"milliseconds", ms},
                    {"placement_milliseconds", scene.milliseconds},
                    {"predicates", euclidean ? "euclidean" : "cga"},
                    {"rest", rest_position},
                    {"pose", scene.pose.report}};
    for (const auto& [key, value] : fields.items()) summary[key] = value;
    // The loader's and the pose's too (already on stderr).
    std::vector<std::string> all = scene.model.warnings;
    all.insert(all.end(), scene.pose.warnings.begin(), scene.pose.warnings.end());
    all.insert(all.end(), warnings.begin(), warnings.end());
    summary["warnings"] = all;
    if (json) {
      std::cout << dump_json(summary) << "\n";
      return;
    }
    std::cout << line << "\n  placed in the " << scene.pose.text << "\n";
    for (const auto& w : warnings) std::cout << "  warning: " << w << "\n";
  }

  /// --soft and its tissue options (soft/tissue_options.hpp).
  struct Soft {
    bool on = false;
    soft::TissueOptions options;
    double stiffness = 1.0 / soft::TissueOptions{}.stretch_compliance;
    std::string gravity = "0,-9.81,0";

    void add_to(CLI::App& sub) {
      sub.add_flag("--soft", on,
                   "living tissue: the wound opens under the skin's tension (XPBD), settles, and is baked into "
                   "the output so that it stays open as the model animates");
      sub.add_option("--tension", options.pretension, "with --soft: skin pre-tension, a fraction in [0, 1)")
          ->capture_default_str();
      sub.add_option("--stiffness", stiffness, "with --soft: stretch stiffness (newtons per model unit)")
          ->capture_default_str();
      sub.add_option("--region", options.region_radius,
                     "with --soft: radius of the simulated region around the wound (model units; 0: 10 % of the "
                     "model's size)")
          ->capture_default_str();
      sub.add_option("--gravity", gravity, "with --soft: GX,GY,GZ (model units per s^2)")->capture_default_str();
    }

    /// The options given; checked.
    [[nodiscard]] soft::TissueOptions tissue() const {
      soft::TissueOptions o = options;
      if (!(stiffness > 0) || !std::isfinite(stiffness))
        throw InvalidInputError("--stiffness must be a finite number > 0");
      o.stretch_compliance = 1.0 / stiffness;
      const auto g = parse_numbers(gravity, 3, "--gravity");
      o.gravity = {g[0], g[1], g[2]};
      o.validate();
      return o;
    }

    /// The report's "soft" entry.
    [[nodiscard]] static Json json(const soft::WoundReport& r) {
      return {{"wound_vertices", r.wound_vertices},
              {"mean_opening", r.mean_opening},
              {"max_opening", r.max_opening},
              {"settled", r.settle.settled},
              {"simulated_seconds", r.settle.seconds},
              {"substeps", r.settle.substeps},
              {"milliseconds", r.milliseconds}};
    }
    [[nodiscard]] static std::string text(const soft::WoundReport& r) {
      return "\n  soft tissue: the wound opened by " + number(r.mean_opening) + " on average (at most " +
             number(r.max_opening) + ") over " + std::to_string(r.wound_vertices) + " vertices, " +
             (r.settle.settled ? "settled" : "not settled") + " after " + number(r.settle.seconds) +
             " s simulated, in " + number(r.milliseconds) + " ms";
    }
  };

  /// `operation` in place on the scene (it returns its MeshChanges), the tissue settled and
  /// baked, written to `output`; `ms` gets the time of it all.
  template <class Operation>
  soft::SoftOperation run_soft(const Scene& scene, const Soft& soft, const std::string& output, Operation&& operation,
                               double& ms) const {
    const soft::TissueOptions tissue = soft.tissue();
    surgery::LiveModel live(scene.model, scene.placement);
    soft::SoftOperation s = timed(
        [&] {
          return soft::operate_soft(live, scene.pose.pose, tissue,
                                    [&](surgery::LiveModel& l) -> std::vector<surgery::MeshChange> { return operation(l); });
        },
        ms);
    io::write_files_atomically(encode_result(s.model, s.positions, scene.pose.pose, output));
    return s;
  }

  void add_common(CLI::App& sub) {
    sub.add_option("MODEL", model, "model file")->required();
    sub.add_flag("--euclidean", euclidean, "Euclidean predicates instead of CGA (same result; for timing)");
    sub.add_option("--rest", rest_position,
                   "rest positions of new vertices: exact (re-posed at the tool's pose they lie on the tool) or "
                   "parametric (the paper's edge/face parameters on the rest mesh)")
        ->check(CLI::IsMember(io::kRestPositions))
        ->capture_default_str();
    placement.add_to(sub);
    add_force(sub, force);
    sub.add_flag("--json", json, "print a machine-readable summary");
  }
};

/// Per mesh of `model`, the placed positions, with mesh `k` replaced by `positions`.
std::vector<mesh::RowMatrixXf<3>> placed_with(const surgery::Placement& placement, int k,
                                              const mesh::RowMatrixXf<3>& positions) {
  std::vector<mesh::RowMatrixXf<3>> out = placement.positions;
  out[static_cast<std::size_t>(k)] = positions;
  return out;
}

// ---- cut ----
struct CutCommand : SurgeryCommand {
  std::string plane;
  std::vector<std::string> outputs;
  surgery::CutOptions options;
  Soft soft;

  void run() {
    check(outputs, "cut");
    const auto p = parse_numbers(plane, 4, "--plane");
    cga::Vector<double> pi;
    try {
      pi = surgery::cut_plane({p[0], p[1], p[2]}, p[3]);
    } catch (const Error&) {
      rethrow_with_context("--plane: ");
    }
    const Scene scene = load(false);
    options.predicates = predicates();
    options.rest = rest();
    double ms = 0;
    if (soft.on) {
      // The tissue lives on the model cut in place: both pieces stay in their meshes, uncapped.
      if (options.cap) throw InvalidInputError("--soft: a cut with --cap is not made in place; drop --cap");
      if (outputs.size() != 1) throw InvalidInputError("--soft writes both pieces to one file: give one -o");
      surgery::LiveCut live_cut;
      const soft::SoftOperation s = run_soft(
          scene, soft, outputs[0],
          [&](surgery::LiveModel& l) {
            live_cut = surgery::cut(l, pi, options);
            return live_cut.changes;
          },
          ms);
      Json fields = Json::parse(io::stats_json(live_cut));
      fields["faces_out"] = live_cut.faces_out;
      fields["soft"] = Soft::json(s.report);
      report(outputs, ms, scene, fields,
             "cut " + model + " in " + std::to_string(ms) + " ms: " + std::to_string(live_cut.intersection_points) +
                 " intersection points, " + std::to_string(live_cut.faces_split) + " faces split, " +
                 std::to_string(live_cut.faces_in) + " -> " + std::to_string(live_cut.faces_out) + " faces" +
                 Soft::text(s.report) + "\n  -> " + outputs[0] + " (both pieces)",
             live_cut.warnings);
      return;
    }
    const surgery::ModelCut c = timed([&] { return surgery::cut(scene.model, scene.placement, pi, options); }, ms);
    std::vector<io::EncodedFile> files;
    if (outputs.size() == 1) {
      std::vector<mesh::RowMatrixXf<3>> placed = c.placed[0];
      placed.insert(placed.end(), c.placed[1].begin(), c.placed[1].end());
      files = encode_result(surgery::join_pieces(c.pieces), placed, scene.pose.pose, outputs[0]);
    } else {
      for (std::size_t k = 0; k < 2; ++k)
        for (io::EncodedFile& f : encode_result(c.pieces[k], c.placed[k], scene.pose.pose, outputs[k]))
          files.push_back(std::move(f));
    }
    io::write_files_atomically(files);
    Json fields = Json::parse(io::stats_json(c));
    fields["faces_out"] = c.faces_out;
    report(outputs, ms, scene, fields,
           "cut " + model + " in " + std::to_string(ms) + " ms: " + std::to_string(c.intersection_points) +
               " intersection points, " + std::to_string(c.faces_split) + " faces split, " +
               std::to_string(c.faces_out[0]) + " + " + std::to_string(c.faces_out[1]) + " faces" +
               (options.cap ? ", " + std::to_string(c.cap_triangles) + " cap triangles" : "") + "\n  -> " + outputs[0] +
               (outputs.size() == 2 ? ", " + outputs[1] : std::string(" (both pieces)")),
           c.warnings);
  }
};

// ---- drill ----
struct DrillCommand : SurgeryCommand {
  std::string tip, base, output;
  double radius = 0;
  surgery::DrillOptions options;

  void run() {
    check({output}, "drill");
    const auto a = parse_numbers(tip, 3, "--tip"), b = parse_numbers(base, 3, "--base");
    const Eigen::Vector3d tip_point(a[0], a[1], a[2]), base_point(b[0], b[1], b[2]);
    const Scene scene = load(true);
    options.predicates = predicates();
    options.rest = rest();
    double ms = 0;
    if (soft.on) {
      surgery::LiveDrill live_drill;
      const soft::SoftOperation s = run_soft(
          scene, soft, output,
          [&](surgery::LiveModel& l) {
            live_drill = surgery::drill(l, tip_point, base_point, radius, options);
            return live_drill.changes;
          },
          ms);
      report_drill(live_drill, ms, scene, Soft::json(s.report), Soft::text(s.report));
      return;
    }
    const surgery::ModelDrill d = timed(
        [&] {
          return surgery::drill(scene.model, scene.placement, scene.index, tip_point, base_point, radius, options);
        },
        ms);
    if (d.model.meshes.empty()) throw TopologyError("drill: the drill removes the whole model; nothing to write");
    io::write_files_atomically(encode_result(d.model, d.placed, scene.pose.pose, output));
    report_drill(d, ms, scene, nullptr, "");
  }

  void report_drill(const surgery::DrillStats& d, double ms, const Scene& scene, const Json& soft_report,
                    const std::string& soft_text) const {
    Json fields = Json::parse(io::stats_json(d));
    if (!soft_report.is_null()) fields["soft"] = soft_report;
    report(output, ms, scene, fields,
           "drill " + model + " in " + std::to_string(ms) + " ms: " + std::to_string(d.intersection_points) +
               " intersection points, " + std::to_string(d.rims) + " rims, " + std::to_string(d.refinements) +
               " refinements, " + std::to_string(d.faces_in) + " -> " + std::to_string(d.faces_out) + " faces" +
               (options.wall ? ", " + std::to_string(d.walls) + " walls (" + std::to_string(d.wall_triangles) +
                                   " triangles), " + std::to_string(d.open_rims) + " rims left open"
                             : "") +
               soft_text + "\n  -> " + output,
           d.warnings);
  }

  Soft soft;
};

// ---- tear ----
struct TearCommand : SurgeryCommand {
  std::string output;
  std::vector<std::string> scalpels;
  surgery::TearOptions options;

  void run() {
    check({output}, "tear");
    std::vector<surgery::Scalpel> steps;
    for (const std::string& s : scalpels) {
      const auto v = parse_numbers(s, 6, "--scalpel");
      steps.push_back({{v[0], v[1], v[2]}, {v[3], v[4], v[5]}});
    }
    if (steps.size() < 2) throw InvalidInputError("--scalpel: give the blade at 2 or more time steps");
    if (!(options.open >= 0)) throw InvalidInputError("--open: the opening width must be >= 0");
    const Scene scene = load(true);
    options.predicates = predicates();
    options.rest = rest();
    double ms = 0;
    if (soft.on) {
      run_soft(scene, steps);
      return;
    }
    const surgery::ModelTear t =
        timed([&] { return surgery::tear(scene.model, scene.placement, scene.index, steps, options); }, ms);
    io::write_files_atomically(
        encode_result(t.model, placed_with(scene.placement, t.mesh, t.placed), scene.pose.pose, output));
    Json fields = Json::parse(io::stats_json(t));
    fields["mesh"] = t.mesh;
    report(output, ms, scene, fields,
           "tear " + model + " in " + std::to_string(ms) + " ms: " + std::to_string(t.intersection_points) +
               " path points over " + std::to_string(steps.size() - 1) + " steps, " + std::to_string(t.faces_split) +
               " faces split, " + std::to_string(t.faces_in) + " -> " + std::to_string(t.faces_out) + " faces\n  -> " +
               output,
           t.warnings);
  }

  /// The tear in place, then the tissue settled and baked.
  void run_soft(const Scene& scene, const std::vector<surgery::Scalpel>& steps) {
    surgery::LiveTear t;
    double ms = 0;
    const soft::SoftOperation s = SurgeryCommand::run_soft(
        scene, soft, output,
        [&](surgery::LiveModel& l) {
          t = surgery::tear(l, steps, options);
          return std::vector<surgery::MeshChange>{t.change};
        },
        ms);
    Json fields = Json::parse(io::stats_json(t));
    fields["mesh"] = t.change.mesh;
    fields["soft"] = Soft::json(s.report);
    report(output, ms, scene, fields,
           "tear " + model + " in " + std::to_string(ms) + " ms: " + std::to_string(t.intersection_points) +
               " path points over " + std::to_string(steps.size() - 1) + " steps, " + std::to_string(t.faces_split) +
               " faces split, " + std::to_string(t.faces_in) + " -> " + std::to_string(t.faces_out) + " faces" +
               Soft::text(s.report) + "\n  -> " + output,
           t.warnings);
  }

  Soft soft;
};

}  // namespace

void add_cut(CLI::App& app) {
  auto c = std::make_shared<CutCommand>();
  CLI::App* sub = app.add_subcommand("cut", "Cut a model in two with a plane (both pieces keep skin and animations)");
  c->add_common(*sub);
  sub->add_option("--plane", c->plane, "NX,NY,NZ,D: the plane n.x = d; piece A is the side n.x > d")->required();
  sub->add_option("-o,--output", c->outputs,
                  "PIECE_A PIECE_B, or one file holding both: .glb/.gltf (rigged) or .obj/.ply (as placed)")
      ->required()
      ->expected(1, 2);
  sub->add_flag("--cap", c->options.cap, "close each piece by triangulating the cross-section");
  sub->add_flag("--own-side-influences", c->options.own_side_influences,
                "new vertices take influences from their own side only");
  c->soft.add_to(*sub);
  sub->callback([c] { c->run(); });
}

void add_drill(CLI::App& app) {
  auto c = std::make_shared<DrillCommand>();
  CLI::App* sub = app.add_subcommand(
      "drill", "Drill a hole with a cylinder from BASE to TIP (the model keeps skin and animations)");
  c->add_common(*sub);
  sub->add_option("--tip", c->tip, "X,Y,Z: the tip A of the drill axis (world space, as placed)")->required();
  sub->add_option("--base", c->base, "X,Y,Z: the base B of the drill axis")->required();
  sub->add_option("--radius", c->radius, "the drill's radius")->required();
  sub->add_option("-o,--output", c->output, "OUT: .glb/.gltf (rigged) or .obj/.ply (as placed)")->required();
  sub->add_flag("--wall", c->options.wall, "line each through-hole with a tube (a closed model stays closed)");
  sub->add_option("--min-rim-points", c->options.min_rim_points, "refine until each rim has this many points")
      ->check(CLI::Range(3, surgery::kMaxRimPoints))
      ->capture_default_str();
  sub->add_option("--max-refinements", c->options.max_refinements, "at most this many rounds of 1->4 splits")
      ->check(CLI::Range(0, surgery::kMaxRefinements))
      ->capture_default_str();
  sub->add_option("--max-region-faces", c->options.max_region_faces,
                  "work budget: refinement stops before the drilled region would pass this many faces")
      ->check(CLI::Range(1, 1 << 24))
      ->capture_default_str();
  c->soft.add_to(*sub);
  sub->callback([c] { c->run(); });
}

void add_tear(CLI::App& app) {
  auto c = std::make_shared<TearCommand>();
  CLI::App* sub = app.add_subcommand(
      "tear", "Tear the surface along the path a scalpel sweeps over time steps (the model keeps skin and animations)");
  c->add_common(*sub);
  sub->add_option("--scalpel", c->scalpels,
                  "HX,HY,HZ,TX,TY,TZ: the blade (handle, tip; world space, as placed) at one time step; "
                  "repeat for t0, t1, ... (at least 2)")
      ->required();
  sub->add_option("-o,--output", c->output, "OUT: .glb/.gltf (rigged) or .obj/.ply (as placed)")->required();
  sub->add_option("--open", c->options.open, "opening width: the two sides move apart by up to this much (default 0)");
  sub->add_flag("--own-side-influences", c->options.own_side_influences,
                "each side of the tear takes influences from its own side only");
  c->soft.add_to(*sub);
  sub->callback([c] { c->run(); });
}

}  // namespace cgamesh::cli
