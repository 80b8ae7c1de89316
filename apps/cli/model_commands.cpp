#include "model_commands.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cgamesh/anim/keyframes.hpp"
#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/gltf_writer.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/io/mesh_writer.hpp"
#include "cgamesh/io/model_info.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "cli_common.hpp"

namespace cgamesh::cli {
namespace {

using anim::BlendMode;
using anim::SkinningMode;
namespace fs = std::filesystem;

std::ostream& operator<<(std::ostream& os, const io::InfoBox& b) {
  return os << "[" << b.min.transpose() << "] - [" << b.max.transpose() << "]";
}

// ---- info ----
struct InfoOptions {
  std::string model;
  bool json = false;
};

void run_info(const InfoOptions& o) {
  const anim::RiggedModel model = cli::load_model(o.model, false);
  const anim::Skeleton& sk = model.skeleton;
  const io::ModelInfo info = io::model_info(model);
  if (o.json) {
    std::cout << io::model_info_json(model, info, o.model) << "\n";
    return;
  }
  std::cout << o.model << " (boxes in the bind pose, world space)\n  meshes: " << model.meshes.size() << " ("
            << info.vertices << " vertices, " << info.triangles << " triangles)\n";
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    std::cout << "    " << i << " " << m.name << ": " << m.vertex_count() << " vertices, " << m.face_count()
              << " triangles"
              << (m.skin.empty() ? std::string() : ", skinned to " + std::to_string(m.skin.palette.size()) + " joints")
              << (m.morph_targets.empty() ? std::string()
                                          : ", " + std::to_string(m.morph_targets.size()) + " morph targets")
              << "\n      box " << info.meshes[i].box << "\n      mesh-space box " << info.meshes[i].box_mesh_space
              << "\n";
  }
  std::cout << "  nodes: " << sk.size() << " (" << info.skinned_joints << " skin joints)\n";
  const auto& skins = info.skins;
  std::vector<std::vector<int>> children(static_cast<std::size_t>(sk.size()));
  std::vector<int> roots;
  for (int j = 0; j < sk.size(); ++j)
    (sk.parents()[j] < 0 ? roots : children[static_cast<std::size_t>(sk.parents()[j])]).push_back(j);
  const auto print = [&](const auto& self, int j, int depth) -> void {
    std::cout << std::string(static_cast<std::size_t>(4 + 2 * depth), ' ') << sk.names()[j];
    const auto& s = skins[static_cast<std::size_t>(j)];
    for (std::size_t k = 0; k < s.size(); ++k)
      std::cout << (k == 0 ? "  [skins " : ", ") << model.meshes[static_cast<std::size_t>(s[k])].name;
    std::cout << (s.empty() ? "" : "]") << "\n";
    for (const int c : children[static_cast<std::size_t>(j)]) self(self, c, depth + 1);
  };
  for (const int r : roots) print(print, r, 0);
  std::cout << "  animations: " << model.clips.size() << "\n";
  for (std::size_t c = 0; c < model.clips.size(); ++c) {
    const long morphs = io::morph_weight_channels(model.clips[c]);
    std::cout << "    " << c << " " << model.clips[c].name << ": " << model.clips[c].duration << " s"
              << (morphs > 0 ? ", animates morph weights" : "") << "\n";
  }
  std::cout << "  max influences per vertex: " << model.source_max_influences << "\n  bounding box: " << info.box
            << "\n";
  for (const auto& w : model.warnings) std::cout << "  warning: " << w << "\n";
}

/// Loader and pose warnings: the pose's on stderr now (the loader's are there already), all in
/// --json.
std::vector<std::string> all_warnings(const anim::RiggedModel& model, const std::vector<std::string>& more) {
  for (const std::string& w : more) std::cerr << "cgamesh: warning: " << w << "\n";
  std::vector<std::string> all = model.warnings;
  all.insert(all.end(), more.begin(), more.end());
  return all;
}

// ---- pose ----
struct PoseOptions {
  std::string model, output;
  PoseChoice pose{"pose in this animation"};
  SkinningMode skinning = SkinningMode::cga;
  bool json = false, force = false;
};

void run_pose(const PoseOptions& o) {
  check_extension(o.output, io::kModelExtensions, "pose");
  check_outputs({o.output}, {o.model}, o.force);
  const anim::RiggedModel model = cli::load_model(o.model);
  const PoseChoice::Chosen chosen = o.pose.choose(model);
  const io::PosedFrame posed = posed_frame(model, chosen.pose, o.skinning);
  if (io::is_rigged_format(o.output)) {
    // The posed frame as a static glTF: world-space positions and skinned normals, no skin,
    // one root node.
    anim::RiggedModel frame;
    anim::EditableSkeleton root;
    root.joints.push_back({"root", -1, {}});
    frame.skeleton = anim::Skeleton::build(root);
    for (std::size_t i = 0; i < model.meshes.size(); ++i) {
      mesh::Mesh m = model.meshes[i];
      m.positions = posed.positions[i];
      m.normals = posed.normals[i];
      m.skin = {};
      m.node = -1;
      frame.meshes.push_back(std::move(m));
    }
    io::write_gltf(frame, o.output);
  } else {
    io::write_mesh(model.meshes, posed.positions, o.output, posed.normals);
  }
  std::vector<std::string> pose_warnings = chosen.warnings;
  pose_warnings.insert(pose_warnings.end(), posed.warnings.begin(), posed.warnings.end());
  const std::vector<std::string> warnings = all_warnings(model, pose_warnings);
  if (o.json) {
    const Json out = {{"output", o.output},
                      {"pose", chosen.report},
                      {"animation", chosen.report["kind"] == "clip" ? chosen.report["clip"] : Json(nullptr)},
                      {"time", chosen.report["kind"] == "clip" ? chosen.report["time"] : Json(nullptr)},
                      {"meshes", model.meshes.size()},
                      {"warnings", warnings}};
    std::cout << dump_json(out) << "\n";
    return;
  }
  std::cout << "pose " << o.model << " in the " << chosen.text << "\n  -> " << o.output << "\n";
}

// ---- convert ----
struct ConvertOptions {
  std::string model, output;
  bool json = false, force = false;
};

void run_convert(const ConvertOptions& o) {
  check_extension(o.output, io::kRiggedExtensions, "convert");
  check_outputs({o.output}, {o.model}, o.force);
  const anim::RiggedModel model = cli::load_model(o.model);
  io::write_gltf(model, o.output);
  if (o.json)
    std::cout << dump_json(Json({{"output", o.output},
                                 {"meshes", model.meshes.size()},
                                 {"nodes", model.skeleton.size()},
                                 {"skinned_joints", io::skinned_joint_count(model)},
                                 {"animations", model.clips.size()},
                                 {"warnings", model.warnings}}))
              << "\n";
}

// ---- animate ----
struct AnimateOptions {
  std::string model, output, name = "generated";
  std::vector<std::string> keys;
  BlendMode blend = BlendMode::linear;
  double fps = 30;
  bool json = false, force = false;
};

void run_animate(const AnimateOptions& o) {
  check_extension(o.output, io::kRiggedExtensions, "animate");
  check_outputs({o.output}, {o.model}, o.force);
  if (!(o.fps > 0) || !std::isfinite(o.fps)) throw InvalidInputError("--fps must be a finite number > 0");
  anim::RiggedModel model = cli::load_model(o.model);
  const double reach = max_translation(model);
  std::map<double, anim::Keyframe> by_time;
  for (const std::string& k : o.keys) {
    const std::size_t colon = k.find(':');
    if (colon == std::string::npos) throw InvalidInputError("--key '" + k + "': expected TIME:JOINT:EDIT=VALUES");
    const double t = parse_numbers(k.substr(0, colon), 1, "--key time")[0];
    if (t < 0) throw InvalidInputError("--key '" + k + "': the time must be >= 0");
    anim::Keyframe& kf = by_time[t];
    kf.time = t;
    kf.edits.push_back(parse_edit(model.skeleton, k.substr(colon + 1), reach));
  }
  std::vector<anim::Keyframe> keyframes;
  for (auto& [t, kf] : by_time) keyframes.push_back(std::move(kf));
  model.clips.push_back(
      anim::generate_clip(model.skeleton, keyframes, {.blend = o.blend, .fps = o.fps, .name = o.name}));
  io::write_gltf(model, o.output);
  if (o.json)
    std::cout << dump_json(Json({{"output", o.output},
                                 {"animation", o.name},
                                 {"keyframes", keyframes.size()},
                                 {"duration", model.clips.back().duration},
                                 {"channels", model.clips.back().channels.size()},
                                 {"warnings", model.warnings}}))
              << "\n";
}

}  // namespace

void add_info(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand(
      "info", "Meshes, the joint hierarchy, animations, influences, bind-pose boxes and warnings of a model");
  sub->add_option("MODEL", o->model, "model file (any format Assimp reads)")->required();
  sub->add_flag("--json", o->json, "print a machine-readable summary");
  sub->callback([o] { run_info(*o); });
}

void add_pose(CLI::App& app) {
  auto o = std::make_shared<PoseOptions>();
  CLI::App* sub = app.add_subcommand(
      "pose",
      "Write the world-space posed geometry of all meshes, with skinned normals (OBJ, PLY, or a static glTF); "
      "default: the bind pose");
  sub->add_option("MODEL", o->model, "model file")->required();
  sub->add_option("-o,--output", o->output, "output file: .obj, .ply, .glb or .gltf")->required();
  o->pose.add_to(*sub);
  sub->add_option("--skinning", o->skinning, "skinning: cga, versor, matrix or dqs")
      ->transform(CLI::CheckedTransformer(kSkinningModes, CLI::ignore_case));
  add_force(*sub, o->force);
  sub->add_flag("--json", o->json, "print a machine-readable summary");
  sub->callback([o] { run_pose(*o); });
}

void add_convert(CLI::App& app) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* sub = app.add_subcommand("convert", "Convert any readable model to a rigged glTF 2.0 (.glb or .gltf)");
  sub->add_option("MODEL", o->model, "model file")->required();
  sub->add_option("-o,--output", o->output, "output .glb or .gltf")->required();
  add_force(*sub, o->force);
  sub->add_flag("--json", o->json, "print a machine-readable summary");
  sub->callback([o] { run_convert(*o); });
}

void add_animate(CLI::App& app) {
  auto o = std::make_shared<AnimateOptions>();
  CLI::App* sub = app.add_subcommand("animate", "Generate keyframes on the fly and write them as a new clip");
  sub->add_option("MODEL", o->model, "model file")->required();
  sub->add_option("-o,--output", o->output, "output .glb or .gltf")->required();
  sub->add_option("--key", o->keys, "TIME:JOINT:rotate=AX,AY,AZ,DEG (or translate=X,Y,Z, scale=S); repeatable")
      ->required();
  sub->add_option("--blend", o->blend, "linear or log")
      ->transform(CLI::CheckedTransformer(io::kKeyframeBlendModes, CLI::ignore_case));
  sub->add_option("--fps", o->fps,
                  "frames per second of the generated clip (at most 100000 frames from the first key to the last)")
      ->capture_default_str();
  sub->add_option("--name", o->name, "name of the new clip")->capture_default_str();
  add_force(*sub, o->force);
  sub->add_flag("--json", o->json, "print a machine-readable summary");
  sub->callback([o] { run_animate(*o); });
}

}  // namespace cgamesh::cli
