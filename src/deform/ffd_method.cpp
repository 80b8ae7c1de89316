// The ffd method (paper section V): handles select lattice control points, one key each; the
// mesh follows its lattice coordinates (eq. 6 classic, eqs. 7-8 motor).

#include <memory>
#include <numbers>

#include <Eigen/Geometry>

#include "cgamesh/errors.hpp"
#include "control_point_method.hpp"

namespace cgamesh::deform::detail {
namespace {

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

void parse(const Json& j, DeformSpec& s, const std::filesystem::path&) {
  FfdSpec& f = s.fields.emplace<FfdSpec>();
  if (j.contains("lattice")) f.lattice = parse_lattice(j["lattice"]);
  f.variant = parse_variant(j);
  parse_handles(j, s);  // after the lattice: control points are checked against its resolution
  parse_keys(j, s);
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

class FfdMethod final : public ControlPointMethod<FreeFormDeformation> {
 public:
  using ControlPointMethod::ControlPointMethod;
  [[nodiscard]] const FreeFormDeformation* ffd() const noexcept override { return &deformer_; }
};

std::unique_ptr<BoundMethod> bind(const BindInput& in, BoundHandles& out) {
  const auto& f = std::get<FfdSpec>(in.spec.fields);
  if (f.lattice.box) {
    in.reach.point(f.lattice.box->origin, "lattice.box.origin");
    in.reach.vector(f.lattice.box->size, "lattice.box.size");
  }
  in.reach.length(f.lattice.margin * in.reach.size(), "lattice.margin");  // in diagonals
  Lattice lattice;
  lattice.resolution = f.lattice.resolution;
  lattice.basis = f.lattice.basis;
  lattice.ends = f.lattice.ends;
  try {
    lattice.box = f.lattice.box ? *f.lattice.box : bounding_lattice_box(in.rest, f.lattice.margin);
  } catch (const InvalidInputError& e) {
    bad("lattice.margin", e.what());
  }
  FfdOptions options;
  options.threads = in.options.blend.threads;
  std::optional<FreeFormDeformation> ffd;
  try {
    ffd.emplace(in.rest, lattice, options);
  } catch (const InvalidInputError& e) {
    bad("lattice", e.what());
  }
  for (std::size_t h = 0; h < in.spec.handles.size(); ++h)
    out.control_handles.push_back(
        select_control_points(in.spec.handles[h], lattice, "handles[" + std::to_string(h) + "]"));
  out.handles.resize(in.spec.handles.size());
  const auto& r = lattice.resolution;
  for (int k = 0; k < r[2]; ++k)
    for (int v = 0; v < r[1]; ++v)
      for (int u = 0; u < r[0]; ++u) {
        if (u + 1 < r[0]) out.control_edges.push_back({lattice.index(u, v, k), lattice.index(u + 1, v, k)});
        if (v + 1 < r[1]) out.control_edges.push_back({lattice.index(u, v, k), lattice.index(u, v + 1, k)});
        if (k + 1 < r[2]) out.control_edges.push_back({lattice.index(u, v, k), lattice.index(u, v, k + 1)});
      }
  check_one_key_per_handle(in.spec);
  out.keys = key_versors(in.spec);
  out.free = ffd->outside();
  return std::make_unique<FfdMethod>(std::move(*ffd), f.variant, keys_of_points(out.control_handles, lattice.count()),
                                     lattice.control_points());
}

}  // namespace

DeformMethodEntry ffd_method() { return {"ffd", {"lattice", "variant"}, parse, bind}; }

}  // namespace cgamesh::deform::detail
