#include "cgamesh/deform/spec.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "cgamesh/cga/versors.hpp"
#include "cgamesh/errors.hpp"
#include "deform_method.hpp"

namespace cgamesh::deform {

using detail::bad;
using detail::Json;

namespace {

/// The fields every method shares.
const std::vector<std::string> kSharedFields{"method", "mesh", "space", "handles", "keys"};

/// Refuses a field that is neither shared nor the method's own, naming the method when another
/// method takes it.
void check_fields(const Json& j, DeformMethod method) {
  const detail::DeformMethodEntry& own = detail::deform_methods()[static_cast<std::size_t>(method)];
  std::vector<std::string> known = kSharedFields;
  known.insert(known.end(), own.fields.begin(), own.fields.end());
  for (const auto& [name, value] : j.items()) {
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::vector<std::string> takers;
    for (const detail::DeformMethodEntry& m : detail::deform_methods())
      if (std::find(m.fields.begin(), m.fields.end(), name) != m.fields.end()) takers.emplace_back(m.name);
    if (!takers.empty()) {
      std::string list = takers.front();
      for (std::size_t t = 1; t < takers.size(); ++t) list += (t + 1 < takers.size() ? ", " : " and ") + takers[t];
      bad(name, std::string("not a field of the ") + own.name + " method (" + list +
                    (takers.size() == 1 ? " takes it)" : " take it)"));
    }
    detail::only_fields(j, known, "");
  }
}

}  // namespace

cga::Versor<double> KeyTransform::versor() const {
  if (!(scale > 0) || !std::isfinite(scale)) throw InvalidInputError("key: the scale must be a finite number > 0");
  const cga::Rotor<double> r = cga::rotor(axis, degrees * std::numbers::pi / 180.0);
  return cga::project<cga::mask::versor>(cga::translator(Eigen::Vector3d(center + translate)) *
                                         cga::similarity(Eigen::Vector3d::Zero().eval(), r, scale) *
                                         cga::translator(Eigen::Vector3d(-center)));
}

const std::map<std::string, DeformMethod> kDeformMethods = [] {
  std::map<std::string, DeformMethod> out;
  for (std::size_t m = 0; m < detail::deform_methods().size(); ++m)
    out.emplace(detail::deform_methods()[m].name, static_cast<DeformMethod>(m));
  return out;
}();

const char* method_name(DeformMethod method) noexcept {
  const auto m = static_cast<std::size_t>(method);
  return m < detail::deform_methods().size() ? detail::deform_methods()[m].name : "?";
}

DeformSpec parse_spec(std::string_view text, const std::string& source) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw InvalidInputError("spec " + source + " is not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw InvalidInputError("spec " + source + ": expected a JSON object");
  if (!j.contains("method")) bad("method", "missing (spline, harmonic, ffd, cage or arap)");
  const DeformMethod method = detail::choice<DeformMethod>(j, "method", kDeformMethods, DeformMethod::spline);
  check_fields(j, method);
  DeformSpec s;
  s.mesh = detail::integer(j, "mesh", 0);
  if (s.mesh < 0) bad("mesh", "expected an index >= 0");
  if (j.contains("space"))
    s.space = detail::choice<DeformSpace>(j, "space", {{"mesh", DeformSpace::mesh}, {"world", DeformSpace::world}},
                                          DeformSpace::mesh);
  detail::deform_methods()[static_cast<std::size_t>(method)].parse(j, s, std::filesystem::path(source).parent_path());
  return s;
}

DeformSpec read_spec(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw FileError("cannot read the spec " + path.string() + ": is a directory");
  std::ifstream in(path);
  if (!in) throw FileError("cannot read the spec " + path.string());
  std::stringstream text;
  text << in.rdbuf();
  return parse_spec(text.str(), path.string());
}

}  // namespace cgamesh::deform
