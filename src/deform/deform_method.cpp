#include "deform_method.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/number_text.hpp"

namespace cgamesh::deform::detail {

// The registry: one entry per method, defined in its own file.
DeformMethodEntry spline_method();
DeformMethodEntry harmonic_method();
DeformMethodEntry ffd_method();
DeformMethodEntry cage_method();
DeformMethodEntry arap_method();

const std::array<DeformMethodEntry, 5>& deform_methods() {
  static const std::array<DeformMethodEntry, 5> methods{spline_method(), harmonic_method(), ffd_method(),
                                                        cage_method(), arap_method()};
  return methods;
}

void bad(const std::string& field, const std::string& what) {
  throw InvalidInputError("spec." + field + ": " + what);
}

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

Eigen::Vector3d vector3(const Json& j, const std::string& field) {
  const auto v = numbers(j, 3, field);
  return {v[0], v[1], v[2]};
}

std::pair<Eigen::Vector3d, double> parse_rotate(const Json& j, const std::string& field) {
  const auto v = numbers(j, 4, field);
  const Eigen::Vector3d axis(v[0], v[1], v[2]);
  if (axis.norm() == 0) bad(field, "the axis is the zero vector");
  return {axis, v[3]};
}

int integer(const Json& spec, const std::string& field, int fallback) {
  if (!spec.contains(field)) return fallback;
  if (!spec[field].is_number_integer()) bad(field, "expected an integer");
  return spec[field].get<int>();
}

std::filesystem::path file_field(const Json& j, const std::string& field, const std::filesystem::path& base) {
  if (!j[field].is_string() || j[field].get<std::string>().empty()) bad(field, "expected a file name");
  const std::filesystem::path path = j[field].get<std::string>();
  return path.is_absolute() ? path : base / path;
}

void only_fields(const Json& j, const std::vector<std::string>& names, const std::string& prefix) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  for (const auto& [name, value] : j.items())
    if (std::find(names.begin(), names.end(), name) == names.end()) bad(prefix + name, "unknown field (" + list + ")");
}

FreeParts parse_free_parts(const Json& j) {
  return choice<FreeParts>(j, "free_parts", {{"nearest", FreeParts::nearest}, {"keep", FreeParts::keep}},
                           FreeParts::nearest);
}

namespace {

/// An ffd handle's control points [[u, v, k], ...], each inside the lattice.
std::vector<std::array<int, 3>> parse_lattice_points(const Json& j, const std::array<int, 3>& resolution,
                                                     const std::string& field) {
  const std::string shape =
      std::to_string(resolution[0]) + "x" + std::to_string(resolution[1]) + "x" + std::to_string(resolution[2]);
  std::vector<std::array<int, 3>> out;
  for (const Json& p : j) {
    if (!p.is_array() || p.size() != 3 ||
        !std::all_of(p.begin(), p.end(), [](const Json& x) { return x.is_number_integer(); }))
      bad(field, "expected control points [[u, v, k], ...] (integers)");
    const std::array<long long, 3> q = {p[0].get<long long>(), p[1].get<long long>(), p[2].get<long long>()};
    for (std::size_t a = 0; a < 3; ++a)
      if (q[a] < 0 || q[a] >= resolution[a])
        bad(field, "control point [" + std::to_string(q[0]) + ", " + std::to_string(q[1]) + ", " +
                       std::to_string(q[2]) + "] is outside the " + shape + " lattice");
    out.push_back({static_cast<int>(q[0]), static_cast<int>(q[1]), static_cast<int>(q[2])});
  }
  if (out.empty()) bad(field, "selects no control point");
  return out;
}

/// A handle: vertex indices, {"sphere": [x, y, z, r]} or {"box": [x0, y0, z0, x1, y1, z1]}; for
/// the ffd method control points [[u, v, k], ...] instead of vertex indices.
HandleSelection parse_handle(const Json& j, const DeformSpec& s, const std::string& field) {
  HandleSelection h;
  const auto* ffd = std::get_if<FfdSpec>(&s.fields);
  if (ffd != nullptr && j.is_array()) {
    h.kind = HandleSelection::Kind::lattice_points;
    h.points = parse_lattice_points(j, ffd->lattice.resolution, field);
  } else if (j.is_array()) {
    for (const Json& x : j) {
      if (!x.is_number_integer() || x.get<long long>() < 0 || x.get<long long>() > std::numeric_limits<int>::max())
        bad(field, "expected vertex indices (integers >= 0)");
      h.indices.push_back(x.get<int>());
    }
    if (h.indices.empty()) bad(field, "selects no vertex");
  } else if (j.is_object() && j.size() == 1 && (j.contains("sphere") || j.contains("box"))) {
    const bool sphere = j.contains("sphere");
    h.kind = sphere ? HandleSelection::Kind::sphere : HandleSelection::Kind::box;
    const auto v = sphere ? numbers(j["sphere"], 4, field + ".sphere") : numbers(j["box"], 6, field + ".box");
    std::copy(v.begin(), v.end(), h.shape.begin());
  } else {
    bad(field, std::string("expected a list of ") +
                   (ffd != nullptr                         ? "control points [[u, v, k], ...]"
                    : s.method() == DeformMethod::cage ? "cage vertex indices"
                                                       : "vertex indices") +
                   ", {\"sphere\": [x, y, z, r]} or {\"box\": [x0, y0, z0, x1, y1, z1]}");
  }
  return h;
}

/// A key: x -> scale R (x - center) + center + translate, every part optional.
KeyTransform parse_key(const Json& j, const std::string& field) {
  if (!j.is_object()) bad(field, "expected an object with rotate, translate, scale and/or center");
  only_fields(j, {"rotate", "translate", "scale", "center"}, field + ".");
  KeyTransform k;
  if (j.contains("translate")) k.translate = vector3(j["translate"], field + ".translate");
  if (j.contains("center")) k.center = vector3(j["center"], field + ".center");
  if (j.contains("rotate")) std::tie(k.axis, k.degrees) = parse_rotate(j["rotate"], field + ".rotate");
  if (j.contains("scale")) {
    if (!j["scale"].is_number() || !(j["scale"].get<double>() > 0) || !std::isfinite(j["scale"].get<double>()))
      bad(field + ".scale", "expected a finite number > 0");
    k.scale = j["scale"].get<double>();
  }
  return k;
}

}  // namespace

void parse_handles(const Json& j, DeformSpec& s) {
  if (!j.contains("handles") || !j["handles"].is_array()) bad("handles", "missing, or not an array");
  for (std::size_t h = 0; h < j["handles"].size(); ++h)
    s.handles.push_back(parse_handle(j["handles"][h], s, "handles[" + std::to_string(h) + "]"));
}

void parse_keys(const Json& j, DeformSpec& s) {
  if (!j.contains("keys") || !j["keys"].is_array()) bad("keys", "missing, or not an array");
  for (std::size_t k = 0; k < j["keys"].size(); ++k)
    s.keys.push_back(parse_key(j["keys"][k], "keys[" + std::to_string(k) + "]"));
}

Reach::Reach(const mesh::RowMatrixXf<3>& rest) {
  if (rest.rows() == 0) return;
  lo_ = rest.colwise().minCoeff().transpose().cast<double>();
  hi_ = rest.colwise().maxCoeff().transpose().cast<double>();
  reach_ = io::kMaxReach * std::max((hi_ - lo_).norm(), 1e-30);
}

void Reach::point(const Eigen::Vector3d& p, const std::string& field) const {
  const double away = (lo_ - p).cwiseMax(p - hi_).cwiseMax(0.0).stableNorm();
  if (!(away <= reach_)) too_far(field, "lies " + number_text(away) + " from the mesh,");
}

void Reach::length(double length, const std::string& field) const {
  if (!(std::abs(length) <= reach_)) too_far(field, number_text(length) + " is");
}

void Reach::too_far(const std::string& field, const std::string& what) const {
  bad(field, what + " more than " + number_text(io::kMaxReach) + " times the mesh's size (" + number_text(size()) +
                 "): no geometric sense for this model");
}

FileNumbering::FileNumbering(const mesh::Mesh& m) {
  by_file_.reserve(static_cast<std::size_t>(m.file_index.rows()));
  for (Eigen::Index v = 0; v < m.file_index.rows(); ++v)
    if (m.file_index[v] >= 0) by_file_.emplace_back(m.file_index[v], static_cast<int>(v));
  std::sort(by_file_.begin(), by_file_.end());
}

std::vector<int> FileNumbering::vertices(const std::vector<int>& indices, const std::string& field) const {
  const int file_count = by_file_.empty() ? 0 : by_file_.back().first + 1;
  std::vector<int> out;
  for (const int f : indices) {
    if (f >= file_count) bad(field, "expected vertex indices of the file in [0, " + std::to_string(file_count) + ")");
    auto it = std::lower_bound(by_file_.begin(), by_file_.end(), std::pair{f, -1});
    if (it == by_file_.end() || it->first != f)
      bad(field, "vertex " + std::to_string(f) + " of the file is on no triangle of the loaded mesh (or was joined " +
                     "with an identical vertex)");
    for (; it != by_file_.end() && it->first == f; ++it) out.push_back(it->second);
  }
  return out;
}

std::vector<int> select(const HandleSelection& h, const mesh::RowMatrixXf<3>& positions, const std::string& field,
                        const std::string& noun, const FileNumbering* numbering) {
  const Eigen::Index count = positions.rows();
  if (h.kind == HandleSelection::Kind::indices) {
    if (numbering != nullptr) return numbering->vertices(h.indices, field);
    for (const int v : h.indices)
      if (v >= count) bad(field, "expected " + noun + " indices in [0, " + std::to_string(count) + ")");
    return h.indices;
  }
  const auto& v = h.shape;
  std::vector<int> out;
  for (Eigen::Index i = 0; i < count; ++i) {
    const Eigen::Vector3d p = positions.row(i).transpose().cast<double>();
    const bool in = h.kind == HandleSelection::Kind::sphere ? (p - Eigen::Vector3d(v[0], v[1], v[2])).norm() <= v[3]
                                                            : (p.array() >= Eigen::Array3d(v[0], v[1], v[2])).all() &&
                                                                  (p.array() <= Eigen::Array3d(v[3], v[4], v[5])).all();
    if (in) out.push_back(static_cast<int>(i));
  }
  if (out.empty()) bad(field, "selects no " + noun);
  return out;
}

std::vector<cga::Versor<double>> key_versors(const DeformSpec& s) {
  std::vector<cga::Versor<double>> out;
  for (const KeyTransform& k : s.keys) out.push_back(k.versor());
  return out;
}

void check_one_key_per_handle(const DeformSpec& s) {
  if (s.handles.size() != s.keys.size())
    bad("keys", std::to_string(s.keys.size()) + " keys for " + std::to_string(s.handles.size()) +
                    " handles (one per handle)");
}

std::vector<std::vector<int>> keys_of_points(const std::vector<std::vector<int>>& handles, Eigen::Index count) {
  std::vector<std::vector<int>> out(static_cast<std::size_t>(count));
  for (std::size_t h = 0; h < handles.size(); ++h)
    for (const int c : handles[h]) out[static_cast<std::size_t>(c)].push_back(static_cast<int>(h));
  return out;
}

}  // namespace cgamesh::deform::detail
