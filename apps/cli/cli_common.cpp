#include "cli_common.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <thread>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "exit_codes.hpp"

namespace cgamesh::cli {
namespace {

using anim::BlendMode;
using anim::SkinningMode;

int joint_index(const anim::Skeleton& skeleton, const std::string& name) {
  const int j = skeleton.find(name);
  if (j < 0) {
    std::string known;
    for (const auto& n : skeleton.names()) known += (known.empty() ? "" : ", ") + n;
    throw InvalidInputError("unknown joint '" + name + "' (joints: " + known + ")");
  }
  return j;
}

}  // namespace

const std::map<std::string, anim::BlendMode> kBlendModes{
    {"format", BlendMode::format}, {"linear", BlendMode::linear}, {"log", BlendMode::log}};
const std::map<std::string, anim::SkinningMode> kSkinningModes{{"cga", SkinningMode::cga},
                                                               {"versor", SkinningMode::versor},
                                                               {"matrix", SkinningMode::matrix},
                                                               {"dqs", SkinningMode::dqs}};

void add_load_timeout(CLI::App& app) {
  app.add_option("--load-timeout", load_timeout_seconds,
                 "seconds a model may take to load before cgamesh gives up with exit 3 (default 120)")
      ->check(CLI::PositiveNumber);
  app.fallthrough();
}

anim::RiggedModel load_model(const std::filesystem::path& path, bool print_warnings) {
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::thread watchdog([&] {
    std::unique_lock lock(mutex);
    if (finished.wait_for(lock, std::chrono::duration<double>(load_timeout_seconds), [&] { return done; })) return;
    std::cerr << "cgamesh: cannot load '" << path.string() << "': reading it took longer than " << load_timeout_seconds
              << " s (a corrupt file can make a reader loop forever); allow more with --load-timeout\n";
    std::_Exit(kExitBadInput);
  });
  const auto stop = [&] {
    {
      const std::lock_guard lock(mutex);
      done = true;
    }
    finished.notify_one();
    watchdog.join();
  };
  try {
    anim::RiggedModel model = io::load_model(path);
    stop();
    if (print_warnings)
      for (const std::string& w : model.warnings)
        std::cerr << "cgamesh: warning: " << path.string() << ": " << w << "\n";
    return model;
  } catch (...) {
    stop();
    throw;
  }
}

std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what) {
  std::vector<double> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    try {
      std::size_t used = 0;
      out.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw InvalidInputError(what + ": '" + item + "' is not a number");
    }
    if (!std::isfinite(out.back())) throw InvalidInputError(what + ": '" + item + "' is not finite");
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  if (out.size() != count)
    throw InvalidInputError(what + ": expected " + std::to_string(count) + " comma-separated numbers, got '" + text +
                            "'");
  return out;
}

anim::JointEdit parse_edit(const anim::Skeleton& skeleton, const std::string& text) {
  const std::size_t colon = text.rfind(':');
  const std::size_t eq = text.find('=', colon == std::string::npos ? 0 : colon);
  if (colon == std::string::npos || eq == std::string::npos)
    throw InvalidInputError("'" + text +
                            "': expected JOINT:rotate=AX,AY,AZ,DEG, JOINT:translate=X,Y,Z or JOINT:scale=S");
  anim::JointEdit e;
  e.joint = joint_index(skeleton, text.substr(0, colon));
  const std::string kind = text.substr(colon + 1, eq - colon - 1), args = text.substr(eq + 1);
  if (kind == "rotate") {
    const auto v = parse_numbers(args, 4, "rotate");
    e.axis = Eigen::Vector3d(v[0], v[1], v[2]);
    if (!(e.axis.norm() > 0)) throw InvalidInputError("rotate: the axis is the zero vector");
    e.angle = v[3] * std::numbers::pi / 180.0;
  } else if (kind == "translate") {
    const auto v = parse_numbers(args, 3, "translate");
    e.translation = Eigen::Vector3d(v[0], v[1], v[2]);
  } else if (kind == "scale") {
    e.scale = parse_numbers(args, 1, "scale")[0];
    if (!(e.scale > 0))
      throw InvalidInputError("scale: must be > 0 (a CGA dilator has a positive factor), got " + args);
  } else {
    throw InvalidInputError("'" + kind + "': the edit must be rotate, translate or scale");
  }
  return e;
}

int clip_index(const anim::RiggedModel& model, const std::string& anim) {
  if (anim.empty()) return model.clips.empty() ? -1 : 0;
  const int by_name = model.find_clip(anim);
  if (by_name >= 0) return by_name;
  try {
    std::size_t used = 0;
    const int i = std::stoi(anim, &used);
    if (used == anim.size() && i >= 0 && i < static_cast<int>(model.clips.size())) return i;
  } catch (const std::exception&) {
  }
  throw InvalidInputError("no animation '" + anim + "' (the model has " + std::to_string(model.clips.size()) + ")");
}

void PoseChoice::add_to(CLI::App& sub) {
  sub.add_option("--anim", anim, anim_help + " (name or index; default: bind pose)");
  time_option = sub.add_option("--time", time, "seconds into the animation (default 0 with --anim)");
  sub.add_option("--blend", blend, "key blending: format, linear or log")
      ->transform(CLI::CheckedTransformer(kBlendModes, CLI::ignore_case));
  sub.add_option("--set", sets, "JOINT:rotate=AX,AY,AZ,DEG | JOINT:translate=X,Y,Z | JOINT:scale=S (repeatable)");
}

anim::Pose PoseChoice::pose(const anim::RiggedModel& model) const {
  const bool timed = time_option != nullptr && time_option->count() > 0;
  if (timed && (!std::isfinite(time) || time < 0)) throw InvalidInputError("--time must be a finite number >= 0");
  const bool animated = !anim.empty() || timed;
  const int clip = animated ? clip_index(model, anim) : -1;
  if (animated && clip < 0) throw InvalidInputError("--anim/--time: the model has no animation");
  anim::Pose p = clip < 0 ? anim::rest_pose(model.skeleton)
                          : anim::sample(model.skeleton, model.clips[static_cast<std::size_t>(clip)], time, blend);
  std::vector<anim::JointEdit> edits;
  for (const std::string& s : sets) edits.push_back(parse_edit(model.skeleton, s));
  anim::apply_edits(p, edits);
  return p;
}

std::vector<mesh::RowMatrixXf<3>> posed_positions(const anim::RiggedModel& model, const anim::Pose& pose,
                                                  SkinningMode mode) {
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  std::vector<mesh::RowMatrixXf<3>> out;
  for (const mesh::Mesh& m : model.meshes) out.push_back(anim::skin(m, anim::make_palette(m, gv, gm, mode)));
  return out;
}

bool is_gltf_path(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".glb" || ext == ".gltf";
}

}  // namespace cgamesh::cli
