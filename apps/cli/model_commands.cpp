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
#include "cgamesh/io/mesh_writer.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "cli_common.hpp"

namespace cgamesh::cli {
namespace {

using anim::BlendMode;
using anim::SkinningMode;
using Json = nlohmann::ordered_json;
namespace fs = std::filesystem;

Json vec_json(const Eigen::Vector3f& v) { return Json::array({v.x(), v.y(), v.z()}); }

// ---- info ----
struct InfoOptions {
  std::string model;
  bool json = false;
};

void run_info(const InfoOptions& o) {
  const anim::RiggedModel model = cli::load_model(o.model, false);
  const auto rest = posed_positions(model, anim::rest_pose(model.skeleton), SkinningMode::matrix);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  Json meshes = Json::array();
  long vertices = 0, triangles = 0;
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    vertices += m.vertex_count();
    triangles += m.face_count();
    if (m.vertex_count() > 0) {
      lo = lo.cwiseMin(rest[i].colwise().minCoeff().transpose());
      hi = hi.cwiseMax(rest[i].colwise().maxCoeff().transpose());
    }
    meshes.push_back({{"name", m.name},
                      {"vertices", m.vertex_count()},
                      {"triangles", m.face_count()},
                      {"skinned", !m.skin.empty()},
                      {"joints", m.skin.palette.size()}});
  }
  Json clips = Json::array();
  for (const anim::Clip& c : model.clips) clips.push_back({{"name", c.name}, {"duration", c.duration}});
  const Json out = {{"file", o.model},
                    {"meshes", meshes},
                    {"vertices", vertices},
                    {"triangles", triangles},
                    {"joints", model.skeleton.size()},
                    {"animations", clips},
                    {"max_influences", model.source_max_influences},
                    {"bounding_box", {{"min", vec_json(lo)}, {"max", vec_json(hi)}}},
                    {"warnings", model.warnings}};
  if (o.json) {
    std::cout << out.dump(2) << "\n";
    return;
  }
  std::cout << o.model << "\n  meshes: " << model.meshes.size() << " (" << vertices << " vertices, " << triangles
            << " triangles)\n";
  for (const auto& m : meshes)
    std::cout << "    " << m["name"].get<std::string>() << ": " << m["vertices"] << " vertices, " << m["triangles"]
              << " triangles" << (m["skinned"].get<bool>() ? ", skinned to " + m["joints"].dump() + " joints" : "")
              << "\n";
  std::cout << "  joints: " << model.skeleton.size() << "\n  animations: " << model.clips.size() << "\n";
  for (const auto& c : clips)
    std::cout << "    " << c["name"].get<std::string>() << ": " << c["duration"].get<double>() << " s\n";
  std::cout << "  max influences per vertex: " << model.source_max_influences << "\n  bounding box: [" << lo.transpose()
            << "] - [" << hi.transpose() << "]\n";
  for (const auto& w : model.warnings) std::cout << "  warning: " << w << "\n";
}

// ---- pose ----
struct PoseOptions {
  std::string model, output, anim;
  double time = 0;
  BlendMode blend = BlendMode::format;
  SkinningMode skinning = SkinningMode::cga;
  std::vector<std::string> sets;
  bool bind_pose = false;
  bool json = false;
};

void run_pose(const PoseOptions& o) {
  if (!std::isfinite(o.time) || o.time < 0) throw InvalidInputError("--time must be a finite number >= 0");
  const anim::RiggedModel model = cli::load_model(o.model);
  std::vector<anim::JointEdit> edits;
  for (const std::string& s : o.sets) edits.push_back(parse_edit(model.skeleton, s));
  const int clip = o.bind_pose ? -1 : clip_index(model, o.anim);
  anim::Pose pose =
      clip < 0 ? anim::rest_pose(model.skeleton) : anim::sample(model.skeleton, model.clips[clip], o.time, o.blend);
  anim::apply_edits(pose, edits);
  const auto positions = posed_positions(model, pose, o.skinning);
  if (is_gltf_path(o.output)) {
    // The posed frame as a static glTF: world-space positions, no skin, one root node.
    anim::RiggedModel frame;
    anim::EditableSkeleton root;
    root.joints.push_back({"root", -1, {}});
    frame.skeleton = anim::Skeleton::build(root);
    for (std::size_t i = 0; i < model.meshes.size(); ++i) {
      mesh::Mesh m = model.meshes[i];
      m.positions = positions[i];
      m.normals.resize(0, 3);  // rest-pose normals do not fit the posed positions
      m.skin = {};
      m.node = -1;
      frame.meshes.push_back(std::move(m));
    }
    io::write_gltf(frame, o.output);
  } else {
    io::write_mesh(model.meshes, positions, o.output);
  }
  if (o.json) {
    Json out = {{"output", o.output},
                {"animation", clip < 0 ? Json(nullptr) : Json(model.clips[clip].name)},
                {"time", o.time},
                {"meshes", model.meshes.size()},
                {"warnings", model.warnings}};
    std::cout << out.dump(2) << "\n";
  }
}

// ---- convert ----
struct ConvertOptions {
  std::string model, output;
  bool json = false;
};

void run_convert(const ConvertOptions& o) {
  const anim::RiggedModel model = cli::load_model(o.model);
  io::write_gltf(model, o.output);
  if (o.json)
    std::cout << Json({{"output", o.output},
                       {"meshes", model.meshes.size()},
                       {"joints", model.skeleton.size()},
                       {"animations", model.clips.size()},
                       {"warnings", model.warnings}})
                     .dump(2)
              << "\n";
}

// ---- animate ----
struct AnimateOptions {
  std::string model, output, name = "generated";
  std::vector<std::string> keys;
  BlendMode blend = BlendMode::linear;
  double fps = 30;
  bool json = false;
};

void run_animate(const AnimateOptions& o) {
  anim::RiggedModel model = cli::load_model(o.model);
  std::map<double, anim::Keyframe> by_time;
  for (const std::string& k : o.keys) {
    const std::size_t colon = k.find(':');
    if (colon == std::string::npos) throw InvalidInputError("--key '" + k + "': expected TIME:JOINT:EDIT=VALUES");
    const double t = parse_numbers(k.substr(0, colon), 1, "--key time")[0];
    anim::Keyframe& kf = by_time[t];
    kf.time = t;
    kf.edits.push_back(parse_edit(model.skeleton, k.substr(colon + 1)));
  }
  std::vector<anim::Keyframe> keyframes;
  for (auto& [t, kf] : by_time) keyframes.push_back(std::move(kf));
  model.clips.push_back(
      anim::generate_clip(model.skeleton, keyframes, {.blend = o.blend, .fps = o.fps, .name = o.name}));
  io::write_gltf(model, o.output);
  if (o.json)
    std::cout << Json({{"output", o.output},
                       {"animation", o.name},
                       {"keyframes", keyframes.size()},
                       {"duration", model.clips.back().duration},
                       {"channels", model.clips.back().channels.size()},
                       {"warnings", model.warnings}})
                     .dump(2)
              << "\n";
}

}  // namespace

void add_info(CLI::App& app) {
  auto o = std::make_shared<InfoOptions>();
  CLI::App* sub =
      app.add_subcommand("info", "Meshes, joints, animations, influences, bounding box and warnings of a model");
  sub->add_option("MODEL", o->model, "model file (any format Assimp reads)")->required();
  sub->add_flag("--json", o->json, "print a machine-readable summary");
  sub->callback([o] { run_info(*o); });
}

void add_pose(CLI::App& app) {
  auto o = std::make_shared<PoseOptions>();
  CLI::App* sub =
      app.add_subcommand("pose", "Write the world-space posed geometry of all meshes (OBJ, PLY, or a static glTF)");
  sub->add_option("MODEL", o->model, "model file")->required();
  sub->add_option("-o,--output", o->output, "output file: .obj, .ply, .glb or .gltf")->required();
  sub->add_option("--anim", o->anim, "animation name or index (default: the first)");
  sub->add_option("--time", o->time, "seconds into the animation")->capture_default_str();
  sub->add_option("--blend", o->blend, "key blending: format, linear or log")
      ->transform(CLI::CheckedTransformer(kBlendModes, CLI::ignore_case));
  sub->add_option("--skinning", o->skinning, "skinning: cga, versor, matrix or dqs")
      ->transform(CLI::CheckedTransformer(kSkinningModes, CLI::ignore_case));
  sub->add_option("--set", o->sets, "JOINT:rotate=AX,AY,AZ,DEG | JOINT:translate=X,Y,Z | JOINT:scale=S (repeatable)");
  sub->add_flag("--bind-pose", o->bind_pose, "the bind pose instead of an animation");
  sub->add_flag("--json", o->json, "print a machine-readable summary");
  sub->callback([o] { run_pose(*o); });
}

void add_convert(CLI::App& app) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* sub = app.add_subcommand("convert", "Convert any readable model to a rigged glTF 2.0 (.glb or .gltf)");
  sub->add_option("MODEL", o->model, "model file")->required();
  sub->add_option("-o,--output", o->output, "output .glb or .gltf")->required();
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
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, BlendMode>{{"linear", BlendMode::linear}, {"log", BlendMode::log}}, CLI::ignore_case));
  sub->add_option("--fps", o->fps, "frames per second of the generated clip")->capture_default_str();
  sub->add_option("--name", o->name, "name of the new clip")->capture_default_str();
  sub->add_flag("--json", o->json, "print a machine-readable summary");
  sub->callback([o] { run_animate(*o); });
}

}  // namespace cgamesh::cli
