#include "cgamesh/io/text_values.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <sstream>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/number_text.hpp"

namespace cgamesh::io {

using anim::BlendMode;
using anim::SkinningMode;

const std::map<std::string, anim::BlendMode> kBlendModes{
    {"format", BlendMode::format}, {"linear", BlendMode::linear}, {"log", BlendMode::log}};
const std::map<std::string, anim::BlendMode> kKeyframeBlendModes = [] {
  auto out = kBlendModes;
  out.erase("format");
  return out;
}();
const std::map<std::string, anim::SkinningMode> kSkinningModes{{"cga", SkinningMode::cga},
                                                               {"versor", SkinningMode::versor},
                                                               {"matrix", SkinningMode::matrix},
                                                               {"dqs", SkinningMode::dqs}};
const std::map<std::string, surgery::RestPosition> kRestPositions{{"exact", surgery::RestPosition::exact},
                                                                  {"parametric", surgery::RestPosition::parametric}};
const std::map<std::string, surgery::Predicates> kPredicates{{"cga", surgery::Predicates::cga},
                                                             {"euclidean", surgery::Predicates::euclidean}};

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

std::string skinning_name(SkinningMode mode) {
  for (const auto& [name, value] : kSkinningModes)
    if (value == mode) return name;
  return "?";
}

std::string number(double x) { return number_text(x); }

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

anim::MorphSetting parse_morph_setting(const std::string& text) {
  const std::size_t eq = text.rfind('=');
  if (eq == std::string::npos || eq == 0)
    throw InvalidInputError("'" + text + "': expected TARGET=WEIGHT (a morph target's name and a number)");
  const double w = parse_numbers(text.substr(eq + 1), 1, "morph weight of '" + text.substr(0, eq) + "'")[0];
  if (!(std::abs(w) <= std::numeric_limits<float>::max()))
    throw InvalidInputError("morph weight of '" + text.substr(0, eq) + "': " + text.substr(eq + 1) +
                            " is no finite float");
  return {text.substr(0, eq), static_cast<float>(w)};
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

namespace {

/// Every mesh skinned in `pose`; with `frame` the normals too (one pass per mesh) and what the
/// mode approximated.
PosedFrame posed(const anim::RiggedModel& model, const anim::Pose& pose, SkinningMode mode, bool frame) {
  const auto gv = anim::global_versors(model.skeleton, pose);
  const auto gm = anim::global_matrices(model.skeleton, pose);
  PosedFrame out;
  bool approximated = false;
  for (const mesh::Mesh& m : model.meshes) {
    const std::span<const float> weights = anim::morph_weights(pose, m);
    anim::skin_into(m, anim::make_palette(m, gv, gm, mode, weights), out.positions.emplace_back(),
                    frame ? &out.normals.emplace_back() : nullptr);
    if (frame && (mode == SkinningMode::versor || mode == SkinningMode::dqs) && !anim::maps_by_similarities(m, gm)) {
      approximated = true;
      out.displacement = std::max(out.displacement, anim::exact_displacement(m, gm, out.positions.back(), weights));
    }
  }
  if (approximated) {
    std::ostringstream text;
    text << skinning_name(mode) << " skinning approximates the joints that scale non-uniformly or shear: in this pose "
         << "vertices lie up to " << out.displacement << " model units from the exact skinning (cga, matrix)";
    out.warnings.push_back(text.str());
  }
  return out;
}

}  // namespace

std::vector<mesh::RowMatrixXf<3>> posed_positions(const anim::RiggedModel& model, const anim::Pose& pose,
                                                  SkinningMode mode) {
  return posed(model, pose, mode, false).positions;
}

PosedFrame posed_frame(const anim::RiggedModel& model, const anim::Pose& pose, SkinningMode mode) {
  return posed(model, pose, mode, true);
}

}  // namespace cgamesh::io
