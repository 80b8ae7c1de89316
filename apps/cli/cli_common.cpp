#include "cli_common.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <numbers>
#include <sstream>
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
  if (j < 0)
    throw InvalidInputError("unknown joint '" + name + "' (joints: " + anim::name_list(skeleton.names()) + ")");
  return j;
}

std::vector<std::string> clip_names(const anim::RiggedModel& model) {
  std::vector<std::string> out;
  for (const anim::Clip& c : model.clips) out.push_back(c.name);
  return out;
}

std::string blend_name(BlendMode mode) {
  for (const auto& [name, value] : kBlendModes)
    if (value == mode) return name;
  return "?";
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

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what) {
  std::vector<double> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = text.find(',', pos);
    const std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    // strtod, not stod: stod throws on ERANGE, which glibc also sets for denormals (5e-324) and
    // for values that underflow to 0; only an overflow (to infinity) is refused below.
    char* end = nullptr;
    errno = 0;
    const double v = item.empty() || std::isspace(static_cast<unsigned char>(item.front())) != 0
                         ? 0.0
                         : std::strtod(item.c_str(), &end);
    if (end == nullptr || end == item.c_str() || *end != '\0')
      throw InvalidInputError(what + ": '" + item + "' is not a number");
    if (!std::isfinite(v)) throw InvalidInputError(what + ": '" + item + "' is not finite");
    out.push_back(v);
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
  if (out.size() != count)
    throw InvalidInputError(what + ": expected " + std::to_string(count) + " comma-separated numbers, got '" + text +
                            "'");
  return out;
}

anim::JointEdit parse_edit(const anim::Skeleton& skeleton, const std::string& text, double max_translation) {
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
    const Eigen::Vector3d axis(v[0], v[1], v[2]);
    // Any length is a direction: scaled first, so 1e308 does not overflow nor 1e-320 vanish.
    const double largest = axis.cwiseAbs().maxCoeff();
    if (!(largest > 0)) throw InvalidInputError("rotate: the axis is the zero vector");
    e.axis = (axis / largest).normalized();
    e.angle = std::fmod(v[3], 360.0) * std::numbers::pi / 180.0;  // exact: whole turns change nothing
  } else if (kind == "translate") {
    const auto v = parse_numbers(args, 3, "translate");
    e.translation = Eigen::Vector3d(v[0], v[1], v[2]);
    if (!(e.translation.norm() <= max_translation))
      throw InvalidInputError("translate: " + args + " moves the joint more than " + number(max_translation) + " (" +
                              number(kMaxReach) + " times the model's size): no geometric sense for this model");
  } else if (kind == "scale") {
    e.scale = parse_numbers(args, 1, "scale")[0];
    if (!(e.scale > 0))
      throw InvalidInputError("scale: must be > 0 (a CGA dilator has a positive factor), got " + args);
    if (!(e.scale <= kMaxReach && e.scale >= 1 / kMaxReach))
      throw InvalidInputError("scale: " + args + " is outside [1e-6, 1e6]: no geometric sense for a joint");
  } else {
    throw InvalidInputError("'" + kind + "': the edit must be rotate, translate or scale");
  }
  return e;
}

double max_translation(const anim::RiggedModel& model) {
  const auto rest = posed_positions(model, anim::rest_pose(model.skeleton), SkinningMode::matrix);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = -lo;
  for (const auto& p : rest)
    if (p.rows() > 0) {
      lo = lo.cwiseMin(p.colwise().minCoeff().transpose());
      hi = hi.cwiseMax(p.colwise().maxCoeff().transpose());
    }
  const double size = (hi.array() >= lo.array()).all() ? static_cast<double>((hi - lo).norm()) : 0.0;
  return kMaxReach * std::max(size, 1.0);
}

int clip_index(const anim::RiggedModel& model, const std::string& anim) {
  const int by_name = model.find_clip(anim);
  if (by_name >= 0) return by_name;
  try {
    std::size_t used = 0;
    const int i = std::stoi(anim, &used);
    if (used == anim.size() && i >= 0 && i < static_cast<int>(model.clips.size())) return i;
  } catch (const std::exception&) {
  }
  throw InvalidInputError("no animation '" + anim + "' (the model has " + std::to_string(model.clips.size()) +
                          (model.clips.empty() ? "" : ": " + anim::name_list(clip_names(model)) + ", or an index") +
                          ")");
}

void PoseChoice::add_to(CLI::App& sub) {
  auto* a = sub.add_option("--anim", anim,
                           anim_help +
                               " (name or index; default: the bind pose, as in every command; --time alone "
                               "picks the first clip)");
  time_option = sub.add_option("--time", time, "seconds into the animation (default 0 with --anim)");
  sub.add_option("--blend", blend, "key blending: format, linear or log")
      ->transform(CLI::CheckedTransformer(kBlendModes, CLI::ignore_case));
  sub.add_option("--set", sets, "JOINT:rotate=AX,AY,AZ,DEG | JOINT:translate=X,Y,Z | JOINT:scale=S (repeatable)");
  sub.add_flag("--bind-pose", bind, "the bind pose (the default; excludes --anim and --time)")
      ->excludes(a)
      ->excludes(const_cast<CLI::Option*>(time_option));
}

PoseChoice::Chosen PoseChoice::choose(const anim::RiggedModel& model) const {
  const bool timed = time_option != nullptr && time_option->count() > 0;
  if (timed && (!std::isfinite(time) || time < 0)) throw InvalidInputError("--time must be a finite number >= 0");
  Chosen out;
  int clip = -1;
  if (!anim.empty()) {
    clip = clip_index(model, anim);
  } else if (timed) {
    if (model.clips.empty())
      out.warnings.push_back("--time " + number(time) + ": the model has no animation; the bind pose is used");
    else
      clip = 0;
  }
  if (clip < 0) {
    out.pose = anim::rest_pose(model.skeleton);
    out.report = {{"kind", "bind"}};
    out.text = "bind pose";
  } else {
    const anim::Clip& c = model.clips[static_cast<std::size_t>(clip)];
    if (time > c.duration)
      out.warnings.push_back("--time " + number(time) + " is past the end of clip '" + c.name + "' (" +
                             number(c.duration) + " s): its last pose is used");
    out.pose = anim::sample(model.skeleton, c, time, blend);
    out.report = {{"kind", "clip"}, {"clip", c.name}, {"index", clip}, {"time", time}, {"blend", blend_name(blend)}};
    out.text = "clip '" + c.name + "' (" + std::to_string(clip) + ") at t = " + number(time) + " s, " +
               blend_name(blend) + " blending";
  }
  std::vector<anim::JointEdit> edits;
  const double reach = sets.empty() ? INFINITY : max_translation(model);
  for (const std::string& s : sets) edits.push_back(parse_edit(model.skeleton, s, reach));
  anim::apply_edits(out.pose, edits);
  if (!sets.empty()) {
    out.report["edits"] = sets;
    out.text += " + " + std::to_string(sets.size()) + (sets.size() == 1 ? " edit" : " edits");
  }
  return out;
}

void add_force(CLI::App& sub, bool& force) {
  sub.add_flag("--force", force, "write the output even over an input file");
}

void check_outputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs, bool force) {
  namespace fs = std::filesystem;
  const auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::equivalent(a, b, ec) && !ec) return true;
    ec.clear();
    const fs::path ca = fs::weakly_canonical(a, ec);
    if (ec) return false;
    const fs::path cb = fs::weakly_canonical(b, ec);
    return !ec && ca == cb;
  };
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k)
      if (same(outputs[i], outputs[k]))
        throw InvalidInputError("-o: '" + outputs[k] + "' and '" + outputs[i] + "' are the same file");
    if (force) continue;
    for (const std::string& in : inputs)
      if (same(outputs[i], in))
        throw InvalidInputError("-o '" + outputs[i] + "' is the input file '" + in +
                                "': refusing to overwrite it (--force to do so)");
  }
}

void check_extension(const std::string& output, const std::vector<std::string>& allowed, const std::string& command) {
  std::string ext = std::filesystem::path(output).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (std::find(allowed.begin(), allowed.end(), ext) != allowed.end()) return;
  std::string list;
  for (std::size_t i = 0; i < allowed.size(); ++i)
    list += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + allowed[i];
  throw InvalidInputError("-o '" + output + "': " + command + " writes " + list + " files (the extension chooses)");
}

void check_no_empty_values(const CLI::App& app) {
  for (const CLI::Option* o : app.get_options()) {
    if (o->get_type_size_max() == 0 || o->get_expected_max() == 0 || o->count() == 0) continue;  // a flag, or not given
    for (const std::string& r : o->results())
      if (r.empty())
        throw InvalidInputError((o->get_name().empty() ? std::string("an option") : o->get_name()) +
                                ": the value is empty");
  }
  for (const CLI::App* sub : app.get_subcommands()) check_no_empty_values(*sub);
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
