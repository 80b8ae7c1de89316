#include "cgamesh/deform/spec.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <nlohmann/json.hpp>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/deform/harmonic_handles.hpp"
#include "cgamesh/deform/morph_transport.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/mesh/normals.hpp"
#include "cgamesh/mesh/union_find.hpp"
#include "cgamesh/mesh/weld.hpp"

namespace cgamesh::deform {
namespace {

using Json = nlohmann::json;

/// More iterations than this are a typo, not a request (each costs a solve).
constexpr int kMaxArapIterations = 100000;

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

Eigen::Vector3d vector3(const Json& j, const std::string& field) {
  const auto v = numbers(j, 3, field);
  return {v[0], v[1], v[2]};
}

/// "rotate": [ax, ay, az, degrees] as an axis (non-zero) and an angle.
std::pair<Eigen::Vector3d, double> parse_rotate(const Json& j, const std::string& field) {
  const auto v = numbers(j, 4, field);
  const Eigen::Vector3d axis(v[0], v[1], v[2]);
  if (axis.norm() == 0) bad(field, "the axis is the zero vector");
  return {axis, v[3]};
}

/// The named value of spec[field]; `prefix` names the object in messages ("lattice.").
template <class E>
E choice(const Json& spec, const std::string& field, const std::map<std::string, E>& names, E fallback,
         const std::string& prefix = "") {
  if (!spec.contains(field)) return fallback;
  const Json& j = spec[field];
  if (j.is_string()) {
    const auto it = names.find(j.get<std::string>());
    if (it != names.end()) return it->second;
  }
  std::string list;
  for (const auto& [name, value] : names) list += (list.empty() ? "" : ", ") + name;
  bad(prefix + field, "expected one of " + list);
}

int integer(const Json& spec, const std::string& field, int fallback) {
  if (!spec.contains(field)) return fallback;
  if (!spec[field].is_number_integer()) bad(field, "expected an integer");
  return spec[field].get<int>();
}

void only_fields(const Json& j, const std::vector<std::string>& names, const std::string& prefix) {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  for (const auto& [name, value] : j.items())
    if (std::find(names.begin(), names.end(), name) == names.end()) bad(prefix + name, "unknown field (" + list + ")");
}

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
  if (s.method == DeformMethod::ffd && j.is_array()) {
    h.kind = HandleSelection::Kind::lattice_points;
    h.points = parse_lattice_points(j, s.lattice.resolution, field);
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
                   (s.method == DeformMethod::ffd    ? "control points [[u, v, k], ...]"
                    : s.method == DeformMethod::cage ? "cage vertex indices"
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

/// {"resolution": [l, m, n], "basis", "ends", "box": {"origin", "size", "rotate"} or "margin"}.
LatticeSpec parse_lattice(const Json& j) {
  if (!j.is_object()) bad("lattice", "expected an object with resolution, basis, ends, box or margin");
  only_fields(j, {"resolution", "basis", "ends", "box", "margin"}, "lattice.");
  LatticeSpec l;
  if (j.contains("resolution")) {
    const Json& r = j["resolution"];
    if (!r.is_array() || r.size() != 3 || !std::all_of(r.begin(), r.end(), [](const Json& x) {
          return x.is_number_integer() && x >= 2 && x <= kMaxLatticeResolution;
        }))
      bad("lattice.resolution", "expected 3 integers in [2, " + std::to_string(kMaxLatticeResolution) + "]");
    l.resolution = {r[0].get<int>(), r[1].get<int>(), r[2].get<int>()};
  }
  l.basis =
      choice<LatticeBasis>(j, "basis", {{"bernstein", LatticeBasis::bernstein}, {"bspline", LatticeBasis::bspline}},
                           LatticeBasis::bernstein, "lattice.");
  l.ends = choice<BsplineEnds>(j, "ends", {{"linear", BsplineEnds::linear}, {"repeat", BsplineEnds::repeat}},
                               BsplineEnds::linear, "lattice.");
  if (j.contains("ends") && l.basis != LatticeBasis::bspline) bad("lattice.ends", "only the bspline basis has ends");
  if (j.contains("margin")) {
    if (j.contains("box")) bad("lattice.margin", "give a box or a margin, not both");
    const Json& m = j["margin"];
    if (!m.is_number() || !std::isfinite(m.get<double>()) || m.get<double>() < 0)
      bad("lattice.margin", "expected a finite number >= 0");
    l.margin = m.get<double>();
  }
  if (j.contains("box")) {
    const Json& b = j["box"];
    if (!b.is_object() || !b.contains("origin") || !b.contains("size"))
      bad("lattice.box", "expected {\"origin\": [x, y, z], \"size\": [sx, sy, sz]} and optionally \"rotate\"");
    only_fields(b, {"origin", "size", "rotate"}, "lattice.box.");
    LatticeBox box;
    box.origin = vector3(b["origin"], "lattice.box.origin");
    box.size = vector3(b["size"], "lattice.box.size");
    if (!(box.size.array() > 0).all()) bad("lattice.box.size", "expected 3 numbers > 0");
    if (b.contains("rotate")) {
      const auto [axis, degrees] = parse_rotate(b["rotate"], "lattice.box.rotate");
      box.rotation = Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()).toRotationMatrix();
    }
    l.box = box;
  }
  return l;
}

/// The arap method's options: "weights", "energy", "local_step", "iterations", "tolerance".
ArapOptions parse_arap(const Json& j) {
  ArapOptions a;
  a.weights = choice<LaplacianWeights>(
      j, "weights",
      {{"cotangent", LaplacianWeights::cotangent}, {"clamped_cotangent", LaplacianWeights::clamped_cotangent}},
      LaplacianWeights::cotangent);
  a.energy = choice<ArapEnergy>(j, "energy",
                                {{"spokes", ArapEnergy::spokes}, {"spokes_and_rims", ArapEnergy::spokes_and_rims}},
                                ArapEnergy::spokes_and_rims);
  a.local_step = choice<ArapLocalStep>(j, "local_step", {{"rotor", ArapLocalStep::rotor}, {"svd", ArapLocalStep::svd}},
                                       ArapLocalStep::rotor);
  if (j.contains("iterations")) {
    const Json& n = j["iterations"];
    if (!n.is_number_integer() || n.get<long long>() < 1 || n.get<long long>() > kMaxArapIterations)
      bad("iterations", "expected an integer in [1, " + std::to_string(kMaxArapIterations) + "]");
    a.iterations = n.get<int>();
  }
  if (j.contains("tolerance")) {
    const Json& t = j["tolerance"];
    if (!t.is_number() || !std::isfinite(t.get<double>()) || t.get<double>() < 0)
      bad("tolerance", "expected a finite number >= 0 (the relative energy decrease that stops the iterations)");
    a.tolerance = t.get<double>();
  }
  return a;
}

/// A file name field, relative to `base` (the spec's directory) unless absolute.
std::filesystem::path file_field(const Json& j, const std::string& field, const std::filesystem::path& base) {
  if (!j[field].is_string() || j[field].get<std::string>().empty()) bad(field, "expected a file name");
  const std::filesystem::path path = j[field].get<std::string>();
  return path.is_absolute() ? path : base / path;
}

/// The cage method's fields: "cage", "deformed_cage" (classic), "resolution", "coordinates",
/// "max_weights".
CageSpec parse_cage(const Json& j, FfdVariant variant, const std::filesystem::path& base) {
  CageSpec c;
  if (!j.contains("cage")) bad("cage", "missing (the cage OBJ)");
  c.cage = file_field(j, "cage", base);
  if (j.contains("deformed_cage")) {
    if (variant != FfdVariant::classic) bad("deformed_cage", "only the classic variant takes a deformed cage");
    c.deformed = file_field(j, "deformed_cage", base);
  }
  if (j.contains("coordinates")) c.coordinates = file_field(j, "coordinates", base);
  c.resolution = integer(j, "resolution", c.resolution);
  if (c.resolution < kMinCageResolution || c.resolution > kMaxCageResolution)
    bad("resolution", "expected an integer in [" + std::to_string(kMinCageResolution) + ", " +
                          std::to_string(kMaxCageResolution) + "]");
  c.max_weights = integer(j, "max_weights", c.max_weights);
  if (c.max_weights < 1) bad("max_weights", "expected an integer >= 1");
  return c;
}

IkChain parse_ik(const Json& ik) {
  if (!ik.is_object() || !ik.contains("joints") || !ik["joints"].is_array() || !ik.contains("target"))
    bad("ik", "expected {\"joints\": [[x, y, z], ...], \"target\": [x, y, z]}");
  IkChain chain;
  for (std::size_t i = 0; i < ik["joints"].size(); ++i)
    chain.joints.push_back(vector3(ik["joints"][i], "ik.joints[" + std::to_string(i) + "]"));
  chain.target = vector3(ik["target"], "ik.target");
  return chain;
}

/// Checks that the method and basis take the spec's number of keys.
void check_key_count(const DeformSpec& s) {
  const std::size_t n = s.ik ? s.ik->joints.size() : s.keys.size();
  if (s.method != DeformMethod::spline) {
    if (s.handles.size() != n)
      bad("keys", std::to_string(n) + " keys for " + std::to_string(s.handles.size()) + " handles (one per handle)");
    return;
  }
  if (s.handles.size() != 2) bad("handles", "the spline method takes 2 handles (lambda = 0 and lambda = 1)");
  SplineOptions options;
  options.basis = s.basis;
  options.degree = s.degree;
  std::vector<double> probe(n);
  try {
    spline_weights(options, 0.0, probe);
  } catch (const InvalidInputError& e) {
    bad(s.ik ? "ik.joints" : "keys", e.what());
  }
}

/// A mesh's vertices by the file's numbering (Mesh::file_index), sorted once per bind.
class FileNumbering {
 public:
  explicit FileNumbering(const mesh::Mesh& m) {
    by_file_.reserve(static_cast<std::size_t>(m.file_index.rows()));
    for (Eigen::Index v = 0; v < m.file_index.rows(); ++v)
      if (m.file_index[v] >= 0) by_file_.emplace_back(m.file_index[v], static_cast<int>(v));
    std::sort(by_file_.begin(), by_file_.end());
  }

  /// The vertices an index list of file vertices names: in the order given, each file vertex's
  /// copies (split at seams) in ascending order.
  [[nodiscard]] std::vector<int> vertices(const std::vector<int>& indices, const std::string& field) const {
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

 private:
  std::vector<std::pair<int, int>> by_file_;  ///< (file vertex, vertex)
};

/// The vertices a selection picks from `positions` (#V×3, in the spec's space); index lists by
/// `numbering` when given, else as indices into `positions`. `noun` names what the positions
/// are in messages.
std::vector<int> select(const HandleSelection& h, const mesh::RowMatrixXf<3>& positions, const std::string& field,
                        const std::string& noun = "vertex", const FileNumbering* numbering = nullptr) {
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

/// The control points (Lattice::index()) an ffd handle selects: by [u, v, k], or the sphere or
/// box containing their rest positions.
std::vector<int> select_control_points(const HandleSelection& h, const Lattice& lattice, const std::string& field) {
  if (h.kind == HandleSelection::Kind::indices)
    bad(field, "the ffd method selects control points ([[u, v, k], ...], a sphere or a box), not vertices");
  std::vector<int> out;
  if (h.kind == HandleSelection::Kind::lattice_points) {
    for (const auto& p : h.points) {
      for (std::size_t a = 0; a < 3; ++a)
        if (p[a] < 0 || p[a] >= lattice.resolution[a]) bad(field, "a control point is outside the lattice");
      out.push_back(lattice.index(p[0], p[1], p[2]));
    }
    return out;
  }
  const std::vector<Eigen::Vector3d> points = lattice.control_points();
  mesh::RowMatrixXf<3> rest(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t c = 0; c < points.size(); ++c)
    rest.row(static_cast<Eigen::Index>(c)) = points[c].transpose().cast<float>();
  return select(h, rest, field, "control point");
}

/// Per vertex, its connected part as the harmonic field sees it (harmonic_precompute): welded
/// positions joined by an edge of non-zero weight; numbered by their smallest welded node.
std::vector<int> parts_of(const mesh::Mesh& shape, LaplacianWeights weights) {
  std::vector<int> node = mesh::weld_by_position(shape.positions);
  const int node_count = mesh::number_classes(node);
  const Eigen::SparseMatrix<double> w = laplacian_edge_weights(shape, node, node_count, weights);
  mesh::UnionFind parts(static_cast<std::size_t>(node_count));
  for (int col = 0; col < w.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(w, col); it; ++it) parts.unite(static_cast<int>(it.row()), col);
  for (int& n : node) n = parts.find(n);
  return node;
}

/// Per free vertex, the key that moves its part: that of the handle with the vertex nearest to
/// the part's centroid (spline: handle 0 is the first key, handle 1 the last), or −1 (keep).
std::vector<int> free_part_keys(const DeformSpec& spec, const mesh::RowMatrixXf<3>& rest,
                                const std::vector<std::vector<int>>& handles, const std::vector<int>& free,
                                const std::vector<int>& part, std::size_t key_count) {
  if (spec.free_parts == FreeParts::keep) return std::vector<int>(free.size(), -1);
  std::vector<Eigen::Vector3d> sum(part.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(part.size(), 0);
  for (const int v : free) {
    sum[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])] += rest.row(v).transpose().cast<double>();
    ++count[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])];
  }
  std::vector<int> key_of_part(part.size(), -1);
  for (std::size_t p = 0; p < part.size(); ++p) {
    if (count[p] == 0) continue;
    const Eigen::Vector3d centroid = sum[p] / count[p];
    double best = INFINITY;
    for (std::size_t h = 0; h < handles.size(); ++h)
      for (const int v : handles[h]) {
        const double d = (rest.row(v).transpose().cast<double>() - centroid).squaredNorm();
        if (d < best) {
          best = d;
          const bool last = spec.method == DeformMethod::spline && h == 1;
          key_of_part[p] = last ? static_cast<int>(key_count) - 1 : static_cast<int>(h);
        }
      }
  }
  std::vector<int> out;
  for (const int v : free) out.push_back(key_of_part[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])]);
  return out;
}

/// The one rule for every point and length a spec gives, as for joint edits and tools: within
/// io::kMaxReach sizes of the deformed mesh (its box in the spec's space). Beyond, a value makes
/// no geometric sense for the model, and its arithmetic loses every digit of the model's
/// coordinates.
class Reach {
 public:
  explicit Reach(const mesh::RowMatrixXf<3>& rest) {
    if (rest.rows() == 0) return;
    lo_ = rest.colwise().minCoeff().transpose().cast<double>();
    hi_ = rest.colwise().maxCoeff().transpose().cast<double>();
    reach_ = io::kMaxReach * std::max((hi_ - lo_).norm(), 1e-30);
  }

  /// @throws InvalidInputError "spec.FIELD: ..." when `p` lies farther than the reach from the box.
  void point(const Eigen::Vector3d& p, const std::string& field) const {
    const double away = (lo_ - p).cwiseMax(p - hi_).cwiseMax(0.0).stableNorm();
    if (!(away <= reach_)) too_far(field, "lies " + io::number(away) + " from the mesh,");
  }

  /// @throws InvalidInputError "spec.FIELD: ..." when `length` exceeds the reach.
  void length(double length, const std::string& field) const {
    if (!(std::abs(length) <= reach_)) too_far(field, io::number(length) + " is");
  }

  void vector(const Eigen::Vector3d& v, const std::string& field) const { length(v.stableNorm(), field); }

  /// The diagonal of the mesh's box.
  [[nodiscard]] double size() const { return (hi_ - lo_).norm(); }

 private:
  [[noreturn]] void too_far(const std::string& field, const std::string& what) const {
    bad(field, what + " more than " + io::number(io::kMaxReach) + " times the mesh's size (" + io::number(size()) +
                   "): no geometric sense for this model");
  }

  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero(), hi_ = Eigen::Vector3d::Zero();
  double reach_ = INFINITY;
};

/// Checks every point and length of `spec` against `reach`.
void check_reach(const DeformSpec& spec, const Reach& reach) {
  for (std::size_t h = 0; h < spec.handles.size(); ++h) {
    const HandleSelection& s = spec.handles[h];
    const std::string field = "handles[" + std::to_string(h) + "]";
    const auto& v = s.shape;
    if (s.kind == HandleSelection::Kind::sphere) {
      reach.point({v[0], v[1], v[2]}, field + ".sphere");
      reach.length(v[3], field + ".sphere");
    } else if (s.kind == HandleSelection::Kind::box) {
      reach.point({v[0], v[1], v[2]}, field + ".box");
      reach.point({v[3], v[4], v[5]}, field + ".box");
    }
  }
  for (std::size_t k = 0; k < spec.keys.size(); ++k) {
    const std::string field = "keys[" + std::to_string(k) + "]";
    reach.point(spec.keys[k].center, field + ".center");
    reach.vector(spec.keys[k].translate, field + ".translate");
  }
  if (spec.ik) {
    for (std::size_t j = 0; j < spec.ik->joints.size(); ++j)
      reach.point(spec.ik->joints[j], "ik.joints[" + std::to_string(j) + "]");
    reach.point(spec.ik->target, "ik.target");
  }
  if (spec.lattice.box) {
    reach.point(spec.lattice.box->origin, "lattice.box.origin");
    reach.vector(spec.lattice.box->size, "lattice.box.size");
  }
  reach.length(spec.lattice.margin * reach.size(), "lattice.margin");  // in diagonals
}

/// Per control point (cage vertex) of `count`, the handles that select it, ascending.
std::vector<std::vector<int>> keys_of_points(const std::vector<std::vector<int>>& handles, Eigen::Index count) {
  std::vector<std::vector<int>> out(static_cast<std::size_t>(count));
  for (std::size_t h = 0; h < handles.size(); ++h)
    for (const int c : handles[h]) out[static_cast<std::size_t>(c)].push_back(static_cast<int>(h));
  return out;
}

}  // namespace

cga::Versor<double> KeyTransform::versor() const {
  if (!(scale > 0) || !std::isfinite(scale)) throw InvalidInputError("key: the scale must be a finite number > 0");
  const cga::Rotor<double> r = cga::rotor(axis, degrees * std::numbers::pi / 180.0);
  return cga::project<cga::mask::versor>(cga::translator(Eigen::Vector3d(center + translate)) *
                                         cga::similarity(Eigen::Vector3d::Zero().eval(), r, scale) *
                                         cga::translator(Eigen::Vector3d(-center)));
}

const std::map<std::string, DeformMethod> kDeformMethods{{"spline", DeformMethod::spline},
                                                        {"harmonic", DeformMethod::harmonic},
                                                        {"ffd", DeformMethod::ffd},
                                                        {"cage", DeformMethod::cage},
                                                        {"arap", DeformMethod::arap}};

const char* method_name(DeformMethod method) noexcept {
  for (const auto& [name, value] : kDeformMethods)
    if (value == method) return name.c_str();
  return "?";
}

DeformSpec parse_spec(std::string_view text, const std::string& source) {
  Json j;
  try {
    j = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw InvalidInputError("spec " + source + " is not valid JSON: " + e.what());
  }
  if (!j.is_object()) throw InvalidInputError("spec " + source + ": expected a JSON object");
  only_fields(j, {"method",     "mesh",        "space",       "weights", "handles",    "keys",       "basis",
                  "degree",     "ik",          "free_parts",  "lattice", "variant",    "cage",       "deformed_cage",
                  "resolution", "coordinates", "max_weights", "energy",  "local_step", "iterations", "tolerance"},
              "");
  DeformSpec s;
  if (!j.contains("method")) bad("method", "missing (spline, harmonic, ffd, cage or arap)");
  s.method = choice<DeformMethod>(j, "method", kDeformMethods, DeformMethod::spline);
  // Each method's own fields: a field another method reads is an error, not silently ignored.
  const bool ffd = s.method == DeformMethod::ffd, cage = s.method == DeformMethod::cage;
  for (const char* field : {"weights", "basis", "degree", "ik", "free_parts"})
    if ((ffd || cage) && j.contains(field))
      bad(field, std::string("not a field of the ") + method_name(s.method) + " method");
  if (!ffd && j.contains("lattice")) bad("lattice", "only the ffd method takes it");
  if (!ffd && !cage && j.contains("variant")) bad("variant", "only the ffd and cage methods take it");
  for (const char* field : {"cage", "deformed_cage", "resolution", "coordinates", "max_weights"})
    if (!cage && j.contains(field)) bad(field, "only the cage method takes it");
  const bool arap = s.method == DeformMethod::arap;
  for (const char* field : {"energy", "local_step", "iterations", "tolerance"})
    if (!arap && j.contains(field)) bad(field, "only the arap method takes it");
  for (const char* field : {"basis", "degree"})
    if (arap && j.contains(field)) bad(field, "not a field of the arap method");
  if (arap) s.arap = parse_arap(j);
  if (ffd && j.contains("lattice")) s.lattice = parse_lattice(j["lattice"]);
  s.variant = choice<FfdVariant>(j, "variant", {{"classic", FfdVariant::classic}, {"motor", FfdVariant::motor}},
                                 FfdVariant::motor);
  if (cage) s.cage = parse_cage(j, s.variant, std::filesystem::path(source).parent_path());
  s.mesh = integer(j, "mesh", 0);
  if (s.mesh < 0) bad("mesh", "expected an index >= 0");
  if (j.contains("space"))
    s.space = choice<DeformSpace>(j, "space", {{"mesh", DeformSpace::mesh}, {"world", DeformSpace::world}},
                                  DeformSpace::mesh);
  if (!arap)
    s.weights = choice<LaplacianWeights>(
        j, "weights", {{"mean_value", LaplacianWeights::mean_value}, {"cotangent", LaplacianWeights::cotangent}},
        LaplacianWeights::mean_value);
  s.free_parts = choice<FreeParts>(j, "free_parts", {{"nearest", FreeParts::nearest}, {"keep", FreeParts::keep}},
                                   FreeParts::nearest);
  s.basis = choice<SplineBasis>(j, "basis",
                                {{"linear", SplineBasis::linear},
                                 {"quadratic_lagrange", SplineBasis::quadratic_lagrange},
                                 {"bezier", SplineBasis::bezier},
                                 {"bspline", SplineBasis::bspline}},
                                SplineBasis::bspline);
  s.degree = integer(j, "degree", 3);
  if (s.degree < 1) bad("degree", "expected an integer >= 1");

  if (s.cage.deformed) {
    // The deformed cage is the pose: no handles or keys to combine with it.
    for (const char* field : {"handles", "keys"})
      if (j.contains(field)) bad(field, "a spec with a deformed_cage takes no handles or keys");
    return s;
  }
  if (!j.contains("handles") || !j["handles"].is_array()) bad("handles", "missing, or not an array");
  for (std::size_t h = 0; h < j["handles"].size(); ++h)
    s.handles.push_back(parse_handle(j["handles"][h], s, "handles[" + std::to_string(h) + "]"));

  if (j.contains("ik")) {
    if (s.method != DeformMethod::spline) bad("ik", "only the spline method takes an IK chain");
    s.ik = parse_ik(j["ik"]);
    if (j.contains("keys")) bad("keys", "give either keys or ik, not both");
  } else {
    if (!j.contains("keys") || !j["keys"].is_array()) bad("keys", "missing, or not an array");
    for (std::size_t k = 0; k < j["keys"].size(); ++k)
      s.keys.push_back(parse_key(j["keys"][k], "keys[" + std::to_string(k) + "]"));
  }
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

DeformSpace default_space(const anim::RiggedModel& model) noexcept {
  const bool rigged =
      std::any_of(model.meshes.begin(), model.meshes.end(), [](const mesh::Mesh& m) { return !m.skin.empty(); });
  return rigged ? DeformSpace::world : DeformSpace::mesh;
}

mesh::WorldSurface rest_surfaces(const anim::RiggedModel& model, DeformSpace space) {
  mesh::WorldSurface out;
  if (space == DeformSpace::mesh) {
    for (const mesh::Mesh& m : model.meshes) {
      out.positions.push_back(m.positions);
      out.normals.push_back(m.normals);
    }
    return out;
  }
  const anim::Pose bind = anim::rest_pose(model.skeleton);
  const auto gv = anim::global_versors(model.skeleton, bind);
  const auto gm = anim::global_matrices(model.skeleton, bind);
  for (const mesh::Mesh& m : model.meshes) {
    mesh::RowMatrixXf<3>& x = out.positions.emplace_back();
    mesh::RowMatrixXf<3>& n = out.normals.emplace_back();
    anim::skin_into(m, anim::make_palette(m, gv, gm, anim::SkinningMode::matrix), x, &n);
  }
  return out;
}

std::vector<mesh::RowMatrixXf<3>> rest_positions(const anim::RiggedModel& model, DeformSpace space) {
  return rest_surfaces(model, space).positions;
}

BoundDeformer::BoundDeformer(const DeformSpec& spec, const anim::RiggedModel& model, const SpecBindOptions& options)
    : mesh_(spec.mesh), space_(spec.space.value_or(default_space(model))) {
  if (mesh_ < 0 || mesh_ >= static_cast<int>(model.meshes.size()))
    bad("mesh", "no mesh " + std::to_string(mesh_) + " (the model has " + std::to_string(model.meshes.size()) + ")");
  const mesh::Mesh& target = model.meshes[static_cast<std::size_t>(mesh_)];
  if (space_ == DeformSpace::mesh) {
    rest_ = target.positions;
  } else {
    // The bind pose of this mesh alone, and each vertex's inverse bind map for to_mesh_space().
    const anim::Pose bind = anim::rest_pose(model.skeleton);
    const anim::SkinningPalette palette =
        anim::make_palette(target, anim::global_versors(model.skeleton, bind),
                           anim::global_matrices(model.skeleton, bind), anim::SkinningMode::matrix);
    rest_ = anim::skin(target, palette);
    to_mesh_.resize(static_cast<std::size_t>(target.vertex_count()));
    for (Eigen::Index i = 0; i < target.vertex_count(); ++i) {
      const Eigen::Matrix<double, 3, 4> m = anim::blended_affine(target, palette, i);
      Eigen::Matrix3d inverse;
      bool invertible = false;
      m.leftCols<3>().computeInverseWithCheck(inverse, invertible);
      if (!invertible)
        bad("space", "world: the bind skinning of vertex " + std::to_string(target.vertex_label(i)) +
                         " is singular, so an edit cannot be mapped back to the mesh (use \"space\": \"mesh\")");
      to_mesh_[static_cast<std::size_t>(i)] << inverse, -inverse * m.col(3);
    }
  }
  check_reach(spec, Reach(rest_));
  if (spec.method == DeformMethod::ffd) {
    bind_ffd(spec, options);
    return;
  }
  if (spec.method == DeformMethod::cage) {
    bind_cage(spec, target, options);
    return;
  }

  std::vector<int> node = mesh::weld_by_position(rest_);
  mesh::number_classes(node);
  std::vector<int> owner(static_cast<std::size_t>(rest_.rows()), -1);  // handle of each welded node
  std::optional<FileNumbering> numbering;
  if (target.file_index.rows() > 0 &&
      std::any_of(spec.handles.begin(), spec.handles.end(),
                  [](const HandleSelection& h) { return h.kind == HandleSelection::Kind::indices; }))
    numbering.emplace(target);
  for (std::size_t h = 0; h < spec.handles.size(); ++h) {
    const std::string field = "handles[" + std::to_string(h) + "]";
    handles_.push_back(select(spec.handles[h], rest_, field, "vertex", numbering ? &*numbering : nullptr));
    for (const int v : handles_.back()) {
      int& o = owner[static_cast<std::size_t>(node[static_cast<std::size_t>(v)])];
      if (o >= 0 && o != static_cast<int>(h))
        bad(field, "vertex " + std::to_string(target.vertex_label(v)) +
                       " (or a vertex at its position) is also in handles[" + std::to_string(o) +
                       "]; handles must be disjoint");
      o = static_cast<int>(h);
    }
  }

  check_key_count(spec);  // after the selections, so that a bad index is named first
  if (spec.ik) {
    try {
      ik_ = fabrik(spec.ik->joints, spec.ik->target);
    } catch (const InvalidInputError& e) {
      bad("ik", e.what());
    }
    keys_.assign(ik_->motors.begin(), ik_->motors.end());
  } else {
    for (const KeyTransform& k : spec.keys) keys_.push_back(k.versor());
  }

  // Parts without a handle vertex: the harmonic field is solved on the others.
  mesh::Mesh shape;
  shape.positions = rest_;
  shape.faces = target.faces;
  const LaplacianWeights weights = spec.method == DeformMethod::arap ? spec.arap.weights : spec.weights;
  const std::vector<int> part = parts_of(shape, weights);
  std::vector<char> handled(part.size(), 0);
  for (const auto& h : handles_)
    for (const int v : h) handled[static_cast<std::size_t>(part[static_cast<std::size_t>(v)])] = 1;
  std::vector<std::vector<int>> bound_handles = handles_;
  if (std::any_of(part.begin(), part.end(), [&](int p) { return !handled[static_cast<std::size_t>(p)]; })) {
    std::vector<int> index(part.size(), -1);  // vertex -> its index in the blended sub-mesh
    for (std::size_t v = 0; v < part.size(); ++v) {
      if (handled[static_cast<std::size_t>(part[v])]) {
        index[v] = static_cast<int>(blended_.size());
        blended_.push_back(static_cast<int>(v));
      } else {
        free_.push_back(static_cast<int>(v));
      }
    }
    for (auto& h : bound_handles)
      for (int& v : h) v = index[static_cast<std::size_t>(v)];
    mesh::Mesh sub;
    sub.positions.resize(static_cast<Eigen::Index>(blended_.size()), 3);
    for (std::size_t v = 0; v < blended_.size(); ++v)
      sub.positions.row(static_cast<Eigen::Index>(v)) = rest_.row(blended_[v]);
    std::vector<int> faces;
    for (Eigen::Index f = 0; f < shape.faces.rows(); ++f) {
      // A face joins one part, or is degenerate (no edge of the field): then it is dropped.
      const std::array<int, 3> corner = {index[static_cast<std::size_t>(shape.faces(f, 0))],
                                         index[static_cast<std::size_t>(shape.faces(f, 1))],
                                         index[static_cast<std::size_t>(shape.faces(f, 2))]};
      if (std::all_of(corner.begin(), corner.end(), [](int c) { return c >= 0; }))
        faces.insert(faces.end(), corner.begin(), corner.end());
    }
    sub.faces = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(
        faces.data(), static_cast<Eigen::Index>(faces.size() / 3), 3);
    shape = std::move(sub);
    free_key_ = free_part_keys(spec, rest_, handles_, free_, part, keys_.size());
  }

  const std::vector<cga::Versor<double>> rest_keys(keys_.size(),
                                                   cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>()));
  HarmonicOptions harmonic;
  harmonic.weights = spec.weights;
  if (spec.method == DeformMethod::arap) {
    bind_arap(spec, shape, bound_handles, options);
  } else if (spec.method == DeformMethod::spline) {
    SplineOptions spline;
    spline.harmonic = harmonic;
    spline.basis = spec.basis;
    spline.degree = spec.degree;
    blend_.emplace(bind_spline(shape, bound_handles[0], bound_handles[1], rest_keys, spline, options.blend));
  } else {
    blend_.emplace(bind_harmonic_handles(shape, bound_handles, rest_keys, harmonic, options.blend));
  }
}

void BoundDeformer::bind_arap(const DeformSpec& spec, const mesh::Mesh& shape,
                              const std::vector<std::vector<int>>& handles, const SpecBindOptions& options) {
  for (std::size_t h = 0; h < handles.size(); ++h)
    for (const int v : handles[h]) {
      arap_handles_.push_back(v);
      arap_key_.push_back(static_cast<int>(h));
    }
  arap_rest_ = shape.positions(arap_handles_, Eigen::all).cast<double>();
  ArapOptions arap = spec.arap;
  arap.threads = options.blend.threads;
  arap_.emplace(arap_precompute(shape, arap_handles_, arap));
}

void BoundDeformer::bind_ffd(const DeformSpec& spec, const SpecBindOptions& options) {
  Lattice lattice;
  lattice.resolution = spec.lattice.resolution;
  lattice.basis = spec.lattice.basis;
  lattice.ends = spec.lattice.ends;
  try {
    lattice.box = spec.lattice.box ? *spec.lattice.box : bounding_lattice_box(rest_, spec.lattice.margin);
  } catch (const InvalidInputError& e) {
    bad("lattice.margin", e.what());
  }
  FfdOptions ffd;
  ffd.threads = options.blend.threads;
  try {
    ffd_.emplace(rest_, lattice, ffd);
  } catch (const InvalidInputError& e) {
    bad("lattice", e.what());
  }
  for (std::size_t h = 0; h < spec.handles.size(); ++h)
    control_handles_.push_back(select_control_points(spec.handles[h], lattice, "handles[" + std::to_string(h) + "]"));
  handles_.resize(spec.handles.size());
  keys_of_point_ = keys_of_points(control_handles_, lattice.count());
  const auto& r = lattice.resolution;
  for (int k = 0; k < r[2]; ++k)
    for (int v = 0; v < r[1]; ++v)
      for (int u = 0; u < r[0]; ++u) {
        if (u + 1 < r[0]) control_edges_.push_back({lattice.index(u, v, k), lattice.index(u + 1, v, k)});
        if (v + 1 < r[1]) control_edges_.push_back({lattice.index(u, v, k), lattice.index(u, v + 1, k)});
        if (k + 1 < r[2]) control_edges_.push_back({lattice.index(u, v, k), lattice.index(u, v, k + 1)});
      }
  check_key_count(spec);
  for (const KeyTransform& k : spec.keys) keys_.push_back(k.versor());
  free_ = ffd_->outside();
  variant_ = spec.variant;
}

void BoundDeformer::bind_cage(const DeformSpec& spec, const mesh::Mesh& target, const SpecBindOptions& options) {
  const CageSpec& c = spec.cage;
  Cage cage = read_cage_obj(c.cage);
  Eigen::MatrixXd coordinates;
  try {
    if (c.coordinates && std::filesystem::exists(*c.coordinates)) {
      check_cage(cage);
      coordinates = load_cage_coordinates(*c.coordinates, rest_.rows(), cage.vertices.rows());
    } else {
      CageOptions solve;
      solve.resolution = c.resolution;
      solve.threads = options.blend.threads;
      solve.vertex_labels = std::span(target.file_index.data(), static_cast<std::size_t>(target.file_index.size()));
      coordinates = cage_coordinates(rest_, cage, solve);
    }
  } catch (const FileError&) {
    rethrow_with_context("spec.coordinates: ");
  } catch (const TopologyError& e) {
    bad("cage", e.what());  // a bad value of the field, as the CLI reports it (exit 2)
  } catch (const Error&) {
    rethrow_with_context("spec.cage: ");
  }
  if (c.coordinates && !std::filesystem::exists(*c.coordinates)) {
    try {
      save_cage_coordinates(*c.coordinates, coordinates);
    } catch (const Error&) {
      rethrow_with_context("spec.coordinates: ");
    }
  }
  CageSparsity sparsity;
  sparsity.max_weights = c.max_weights;
  cage_.emplace(rest_, cage, coordinates, sparsity, options.blend.threads);
  if (c.deformed) {
    const Cage posed = read_cage_obj(*c.deformed);
    if (posed.vertices.rows() != cage.vertices.rows() || posed.faces != cage.faces)
      bad("deformed_cage", "has other vertices or faces than the cage (" + std::to_string(posed.vertices.rows()) +
                               " vertices and " + std::to_string(posed.faces.rows()) + " faces for " +
                               std::to_string(cage.vertices.rows()) + " and " + std::to_string(cage.faces.rows()) +
                               ")");
    cage = posed;
  }
  for (Eigen::Index v = 0; v < cage.vertices.rows(); ++v) cage_points_.push_back(cage.vertices.row(v).transpose());
  const mesh::RowMatrixXf<3> at_rest = cage_->cage_vertices().cast<float>();
  for (std::size_t h = 0; h < spec.handles.size(); ++h)
    control_handles_.push_back(select(spec.handles[h], at_rest, "handles[" + std::to_string(h) + "]", "cage vertex"));
  handles_.resize(spec.handles.size());
  keys_of_point_ = keys_of_points(control_handles_, cage.vertices.rows());
  // A checked cage is closed and consistently oriented: each edge runs once each way.
  for (Eigen::Index f = 0; f < cage.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (cage.faces(f, k) < cage.faces(f, (k + 1) % 3))
        control_edges_.push_back({cage.faces(f, k), cage.faces(f, (k + 1) % 3)});
  check_key_count(spec);
  for (const KeyTransform& k : spec.keys) keys_.push_back(k.versor());
  variant_ = spec.variant;
}

namespace {

/// Each point under the keys (maps) of the handles that select it, composed in handle order.
std::vector<Eigen::Vector3d> moved_points(const std::vector<std::vector<int>>& keys_of_point,
                                          std::span<const cga::Versor<double>> keys,
                                          std::vector<Eigen::Vector3d> points) {
  std::vector<Eigen::Matrix<double, 3, 4>> maps;
  for (const auto& k : keys) maps.push_back(cga::PointMap<double>(k).affine_matrix());
  for (std::size_t c = 0; c < points.size(); ++c)
    for (const int h : keys_of_point[c]) {
      const Eigen::Matrix<double, 3, 4>& m = maps[static_cast<std::size_t>(h)];
      points[c] = m.leftCols<3>() * points[c] + m.col(3);
    }
  return points;
}

/// ffd and cage frames: each control point (cage vertex) under the keys of its handles, composed
/// in handle order, then the deformer's classic (points) or motor variant.
template <class Deformer>
void move_control_points(const Deformer& deformer, FfdVariant variant,
                         const std::vector<std::vector<int>>& keys_of_point, std::size_t bound_keys,
                         std::span<const cga::Versor<double>> keys, std::vector<Eigen::Vector3d> points,
                         mesh::RowMatrixXf<3>& out) {
  if (keys.size() != bound_keys)
    throw InvalidInputError(std::to_string(keys.size()) + " keys given, bound to " + std::to_string(bound_keys));
  const std::size_t count = keys_of_point.size();
  if (variant == FfdVariant::motor) {
    std::vector<cga::Versor<double>> motors(count, cga::Versor<double>(cga::basis_blade<double, cga::blade::scalar>()));
    for (std::size_t c = 0; c < count; ++c)
      for (const int h : keys_of_point[c])
        motors[c] = cga::project<cga::mask::versor>(keys[static_cast<std::size_t>(h)] * motors[c]);
    deformer.deform_motors(motors, out);
    return;
  }
  (void)similarity_logs(keys);  // the classic variant takes similarities too, so that either variant fails alike
  deformer.deform_points(moved_points(keys_of_point, keys, std::move(points)), out);
}

}  // namespace

void BoundDeformer::apply_arap(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out,
                               ArapReport* report) const {
  if (keys.size() != keys_.size())
    throw InvalidInputError("arap: " + std::to_string(keys.size()) + " keys given, bound to " +
                            std::to_string(keys_.size()));
  (void)similarity_logs(keys);  // each key a similarity, as the blend requires
  std::vector<Eigen::Matrix<double, 3, 4>> maps;
  for (const auto& k : keys) maps.push_back(cga::PointMap<double>(k).affine_matrix());
  Eigen::MatrixXd targets(arap_rest_.rows(), 3);
  for (Eigen::Index i = 0; i < targets.rows(); ++i) {
    const Eigen::Matrix<double, 3, 4>& m = maps[static_cast<std::size_t>(arap_key_[static_cast<std::size_t>(i)])];
    targets.row(i) = (m.leftCols<3>() * arap_rest_.row(i).transpose() + m.col(3)).transpose();
  }
  Eigen::MatrixXd positions;
  const ArapReport r = arap_solve(*arap_, targets, positions);
  if (report != nullptr) *report = r;
  out = positions.cast<float>();
}

std::vector<Eigen::Vector3d> BoundDeformer::control_points(std::span<const cga::Versor<double>> keys) const {
  if (keys.size() != keys_.size())
    throw InvalidInputError(std::to_string(keys.size()) + " keys given, bound to " + std::to_string(keys_.size()));
  if (ffd_) return moved_points(keys_of_point_, keys, ffd_->lattice().control_points());
  if (cage_) return moved_points(keys_of_point_, keys, cage_points_);
  return {};
}

void BoundDeformer::apply(std::span<const cga::Versor<double>> keys, mesh::RowMatrixXf<3>& out,
                          ArapReport* report) const {
  if (ffd_) {
    move_control_points(*ffd_, variant_, keys_of_point_, keys_.size(), keys, ffd_->lattice().control_points(), out);
    return;
  }
  if (cage_) {
    move_control_points(*cage_, variant_, keys_of_point_, keys_.size(), keys, cage_points_, out);
    return;
  }
  const auto deform = [&](mesh::RowMatrixXf<3>& positions) {
    if (arap_)
      apply_arap(keys, positions, report);
    else
      blend_->deform(keys, positions);
  };
  if (blended_.empty()) {
    deform(out);
    return;
  }
  mesh::RowMatrixXf<3> part;
  deform(part);
  out = rest_;
  for (std::size_t v = 0; v < blended_.size(); ++v) out.row(blended_[v]) = part.row(static_cast<Eigen::Index>(v));
  // The rest keys are identities, so a handle's motor is its key applied to the rest shape.
  std::vector<std::optional<Eigen::Matrix<float, 3, 4>>> maps(keys.size());
  for (std::size_t f = 0; f < free_.size(); ++f) {
    const int k = free_key_[f];
    if (k < 0) continue;
    auto& map = maps[static_cast<std::size_t>(k)];
    if (!map) map = cga::PointMap<double>(keys[static_cast<std::size_t>(k)]).affine_matrix().cast<float>();
    const auto v = free_[f];
    out.row(v) = (map->leftCols<3>() * rest_.row(v).transpose() + map->col(3)).transpose();
  }
}

mesh::RowMatrixXf<3> BoundDeformer::apply(std::span<const cga::Versor<double>> keys) const {
  mesh::RowMatrixXf<3> out;
  apply(keys, out);
  return out;
}

mesh::RowMatrixXf<3> BoundDeformer::to_mesh_space(const mesh::RowMatrixXf<3>& positions) const {
  if (positions.rows() != rest_.rows())
    throw InvalidInputError("to_mesh_space: " + std::to_string(positions.rows()) + " positions for " +
                            std::to_string(rest_.rows()) + " vertices");
  if (space_ == DeformSpace::mesh) return positions;
  mesh::RowMatrixXf<3> out(positions.rows(), 3);
  for (Eigen::Index i = 0; i < positions.rows(); ++i) {
    const Eigen::Matrix<double, 3, 4>& m = to_mesh_[static_cast<std::size_t>(i)];
    out.row(i) = (m.leftCols<3>() * positions.row(i).transpose().cast<double>() + m.col(3)).transpose().cast<float>();
  }
  return out;
}

anim::RiggedModel BoundDeformer::deformed_model(const anim::RiggedModel& model,
                                                const mesh::RowMatrixXf<3>& positions) const {
  anim::RiggedModel out = model;
  if (mesh_ >= static_cast<int>(out.meshes.size()) ||
      out.meshes[static_cast<std::size_t>(mesh_)].vertex_count() != rest_.rows())
    throw InvalidInputError("deformed_model: the model is not the one bound (mesh " + std::to_string(mesh_) +
                            " has another vertex count)");
  mesh::Mesh& m = out.meshes[static_cast<std::size_t>(mesh_)];
  const mesh::RowMatrixXf<3> rest = to_mesh_space(positions);
  m.normals = mesh::reshaped_normals(m, rest);
  transport_morph_targets(m, rest);
  m.positions = rest;
  return out;
}

mesh::WorldSurface BoundDeformer::deformed_surfaces(const anim::RiggedModel& model, const mesh::RowMatrixXf<3>& positions) const {
  mesh::WorldSurface out = rest_surfaces(deformed_model(model, positions), space_);
  out.positions[static_cast<std::size_t>(mesh_)] = positions;  // not through to_mesh_space and back
  return out;
}

std::vector<std::string> BoundDeformer::write(const anim::RiggedModel& model, const mesh::RowMatrixXf<3>& positions,
                                              const std::filesystem::path& out) const {
  return io::write_model(io::is_rigged_format(out) ? deformed_model(model, positions) : model, out,
                         [&] { return deformed_surfaces(model, positions); });
}

}  // namespace cgamesh::deform
