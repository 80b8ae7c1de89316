#include "cgamesh/surgery/cut.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

#include "../flat_map.hpp"
#include "polygon_triangulation.hpp"
#include "surgery_common.hpp"

namespace cgamesh::surgery {
namespace {

using mesh::RowMatrixXf;
using mesh::VertexSource;
using Triangle = std::array<int, 3>;

/// A new vertex on input edge (a, b), a < b: (1 − t) a + t b.
struct EdgePoint {
  int a, b;
  float t;
};

/// Whether every coordinate is finite: one pass over the exponent bits, with no early exit so
/// that it vectorises (Eigen's allFinite() tests a coefficient at a time).
bool all_finite(const RowMatrixXf<3>& m) {
  constexpr std::uint32_t exponent = 0x7f800000u;  // all ones: inf or NaN
  std::uint32_t non_finite = 0;
  for (const float x : std::span(m.data(), static_cast<std::size_t>(m.size())))
    non_finite |= static_cast<std::uint32_t>((std::bit_cast<std::uint32_t>(x) & exponent) == exponent);
  return non_finite == 0;
}

class Cutter {
 public:
  /// A cut of the whole mesh: every vertex is classified up front.
  Cutter(const mesh::Mesh& mesh, const RowMatrixXf<3>& placed, const cga::Vector<double>& plane,
         const CutOptions& options, const anim::SkinningPalette* palette, int cap_material)
      : Cutter(mesh, placed, plane, options, 0.0) {
    palette_ = palette;
    cap_material_ = cap_material;
    track_parents_ = mesh.face_materials.rows() > 0;  // for the pieces' face materials
    if (placed.rows() != mesh.vertex_count())
      throw InvalidInputError("cut: mesh '" + mesh.name + "' has " + std::to_string(nv_) + " vertices but " +
                              std::to_string(placed.rows()) + " placed positions");
    if (!all_finite(placed)) throw InvalidInputError("cut: the placed positions of mesh '" + mesh.name + "' hold NaN");
    classify();
  }

  /// A local cut (in place): vertices are classified as the faces near the plane ask, with the
  /// snapping tolerance `tolerance` (absolute).
  Cutter(const mesh::Mesh& mesh, const RowMatrixXf<3>& placed, const cga::Vector<double>& plane,
         const CutOptions& options, double tolerance)
      : mesh_(mesh),
        placed_(placed),
        options_(options),
        nv_(static_cast<int>(mesh.vertex_count())),
        tolerance_(tolerance) {
    const auto [n, d] = cga::plane_parameters(plane);
    normal_ = n;
    offset_ = d;
    plane_ = cga::plane(n, d);
  }

  MeshCut run() {
    const Eigen::Index nf = mesh_.face_count();
    for (auto& f : faces_) f.reserve(static_cast<std::size_t>(nf));
    // Most faces lie on one side: sort them here, leaving the others to split_face.
    const int* corner = mesh_.faces.data();
    const signed char* side = side_.data();
    for (Eigen::Index f = 0; f < nf; ++f, corner += 3) {
      const int a = corner[0], b = corner[1], c = corner[2];
      const int sa = side[a], sb = side[b], sc = side[c];
      if (sa > 0 && sb > 0 && sc > 0) {
        faces_[0].push_back({a, b, c});
        if (track_parents_) parents_[0].push_back(static_cast<int>(f));
      } else if (sa < 0 && sb < 0 && sc < 0) {
        faces_[1].push_back({a, b, c});
        if (track_parents_) parents_[1].push_back(static_cast<int>(f));
      } else {
        parent_ = static_cast<int>(f);
        split_face(f);
      }
    }
    MeshCut out;
    out.intersection_points = static_cast<int>(points_.size());
    out.faces_split = faces_split_;
    // One remap (extended vertex -> piece vertex, or -1) serves both pieces: build_piece resets
    // the entries it sets.
    std::vector<int> remap(static_cast<std::size_t>(nv_) + points_.size(), -1);
    for (int p = 0; p < 2; ++p) build_piece(p, remap, out);
    return out;
  }

  /// Separates the faces among `near` that the plane crosses or touches (in place): they are
  /// removed and re-triangulated; each vertex on the plane gets a copy for piece B where both
  /// pieces use it. `piece` gets the piece of each new face.
  void separate(const std::vector<int>& near, LocalEdit& edit, std::vector<signed char>& piece, CutStats& stats) {
    for (const int f : near) {
      const std::array<int, 3> s{side(mesh_.faces(f, 0)), side(mesh_.faces(f, 1)), side(mesh_.faces(f, 2))};
      const bool zero = s[0] == 0 || s[1] == 0 || s[2] == 0;
      const bool crossed = std::count(s.begin(), s.end(), 1) > 0 && std::count(s.begin(), s.end(), -1) > 0;
      if (!zero && !crossed) continue;
      edit.remove_face(f);
      parent_ = f;
      split_face(f);
    }
    // Old vertices on the plane that piece A keeps: piece B gets copies of them.
    FlatMap<int> shared;
    for (const Triangle& t : faces_[0])
      for (const int x : t)
        if (x < nv_ && side(x) == 0) shared.try_emplace(static_cast<std::uint64_t>(x), -1);
    FlatMap<int> id_of;
    const auto id = [&](int x, int p) {
      if (x < nv_) {
        if (p == 0 || side(x) != 0) return x;
        int* copy = shared.find(static_cast<std::uint64_t>(x));
        if (copy == nullptr) return x;
        if (*copy < 0) *copy = edit.add_vertex({.source = VertexSource::copy(x), .placed = point(x), .side = -1}, nv_);
        return *copy;
      }
      const auto [copy, added] = id_of.try_emplace(directed_key(x, p), -1);
      if (added)
        *copy = edit.add_vertex(
            {.source = source(x, p), .placed = point(x), .side = static_cast<signed char>(p == 0 ? 1 : -1)}, nv_);
      return *copy;
    };
    for (std::size_t p = 0; p < 2; ++p) {
      const int q = static_cast<int>(p);
      for (std::size_t j = 0; j < faces_[p].size(); ++j) {
        const Triangle& t = faces_[p][j];
        edit.add_face_in({id(t[0], q), id(t[1], q), id(t[2], q)}, parents_[p][j]);
        piece.push_back(static_cast<signed char>(p));
      }
    }
    stats.intersection_points += static_cast<int>(points_.size());
    stats.faces_split += faces_split_;
  }

 private:
  /// The side of every vertex, with the snapping tolerance a fraction of the bounding-box
  /// diagonal. The distances are not kept: the few crossings recompute theirs.
  void classify() {
    const double tolerance = options_.snap * bounding_diagonal(placed_);
    tolerance_ = tolerance;
    side_.resize(static_cast<std::size_t>(nv_));
    // Locals, as classified() computes them: the signed char stores could alias the members.
    signed char* side = side_.data();
    const float* x = placed_.data();
    const Eigen::Vector3d n = normal_;
    const double d = offset_;
    const cga::Vector<double> plane = plane_;
    const Predicates predicates = options_.predicates;
    for (int v = 0; v < nv_; ++v, x += 3) {
      const double s = signed_distance(Eigen::Vector3f(x[0], x[1], x[2]).cast<double>(), n, d, plane, predicates);
      side[v] = static_cast<signed char>(s > tolerance ? 1 : s < -tolerance ? -1 : 0);
    }
  }

  /// Snapped signed distance and side of vertex v, evaluated where it is asked (a local cut): a
  /// few multiply-adds, cheaper than remembering them.
  [[nodiscard]] std::pair<double, int> classified(int v) const {
    const double x =
        signed_distance(placed_.row(v).cast<double>().transpose(), normal_, offset_, plane_, options_.predicates);
    const int s = x > tolerance_ ? 1 : x < -tolerance_ ? -1 : 0;
    return {s == 0 ? 0.0 : x, s};
  }
  [[nodiscard]] double distance(int v) const { return classified(v).first; }
  [[nodiscard]] int side(int v) const {
    return side_.empty() ? classified(v).second : side_[static_cast<std::size_t>(v)];
  }
  [[nodiscard]] static int piece_of(int side) { return side > 0 ? 0 : 1; }

  /// The crossing of edge (a, b), whose ends are strictly on opposite sides, shared by both faces
  /// of the edge: t = (A·Π) / (A·Π − B·Π), the meet of the line AB with Π.
  int crossing(int a, int b) {
    if (a > b) std::swap(a, b);
    const auto [id, added] = point_of_edge_.try_emplace(edge_key(a, b), nv_ + static_cast<int>(points_.size()));
    if (added) {
      const double da = distance(a), db = distance(b);
      points_.push_back({a, b, static_cast<float>(da / (da - db))});
    }
    return *id;
  }

  void emit(int piece, int a, int b, int c) {
    faces_[static_cast<std::size_t>(piece)].push_back({a, b, c});
    if (track_parents_) parents_[static_cast<std::size_t>(piece)].push_back(parent_);
  }

  void split_face(Eigen::Index f) {
    const Triangle v{mesh_.faces(f, 0), mesh_.faces(f, 1), mesh_.faces(f, 2)};
    const std::array<int, 3> s{side(v[0]), side(v[1]), side(v[2])};
    const bool pos = s[0] > 0 || s[1] > 0 || s[2] > 0, neg = s[0] < 0 || s[1] < 0 || s[2] < 0;
    if (!pos && !neg) {  // in the plane: it bounds the side its normal faces away from
      const Eigen::Vector3d a = placed_.row(v[0]).cast<double>(), b = placed_.row(v[1]).cast<double>(),
                            c = placed_.row(v[2]).cast<double>();
      emit((b - a).cross(c - a).dot(normal_) > 0 ? 1 : 0, v[0], v[1], v[2]);
      return;
    }
    if (!(pos && neg)) {
      emit(pos ? 0 : 1, v[0], v[1], v[2]);
      return;
    }
    ++faces_split_;
    // Rotate so that corner 0 is the odd one: the vertex on the plane, or the lone vertex.
    int r = 0;
    const int zeros = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      if (zeros == 1 ? s[static_cast<std::size_t>(k)] == 0
                     : s[static_cast<std::size_t>(k1)] == s[static_cast<std::size_t>(k2)])
        r = k;
    }
    const int a = v[static_cast<std::size_t>(r)], b = v[static_cast<std::size_t>((r + 1) % 3)],
              c = v[static_cast<std::size_t>((r + 2) % 3)];
    if (zeros == 1) {  // a on the plane, b and c on opposite sides: two triangles
      const int q = crossing(b, c);
      emit(piece_of(side(b)), a, b, q);
      emit(piece_of(side(c)), a, q, c);
      return;
    }
    // a alone on its side: one triangle there, a quad on the other side split along its
    // shorter diagonal.
    const int qb = crossing(a, b), qc = crossing(a, c);
    emit(piece_of(side(a)), a, qb, qc);
    const int other = piece_of(side(b));
    if ((point(qb) - placed_.row(c).cast<double>().transpose()).squaredNorm() <=
        (point(qc) - placed_.row(b).cast<double>().transpose()).squaredNorm()) {
      emit(other, qb, b, c);
      emit(other, qb, c, qc);
    } else {
      emit(other, qb, b, qc);
      emit(other, b, c, qc);
    }
  }

  /// Placed position of an extended vertex (old, or new edge point).
  [[nodiscard]] Eigen::Vector3d point(int x) const {
    if (x < nv_) return placed_.row(x).cast<double>().transpose();
    const EdgePoint& e = points_[static_cast<std::size_t>(x - nv_)];
    return (1.0 - e.t) * placed_.row(e.a).cast<double>().transpose() +
           e.t * placed_.row(e.b).cast<double>().transpose();
  }

  [[nodiscard]] VertexSource source(int x, int piece) const {
    if (x < nv_) return VertexSource::copy(x);
    const EdgePoint& e = points_[static_cast<std::size_t>(x - nv_)];
    VertexSource s = VertexSource::edge(e.a, e.b, e.t);
    if (options_.own_side_influences) {
      const int want = piece == 0 ? 1 : -1;
      s.influence_mask = static_cast<std::uint8_t>((side(e.a) == want ? 1u : 0u) | (side(e.b) == want ? 2u : 0u));
    }
    return s;
  }

  /// `remap` (extended vertex -> piece vertex, all -1) is scratch shared by both pieces, and left so.
  void build_piece(int piece, std::vector<int>& remap, MeshCut& out) {
    const auto& faces = faces_[static_cast<std::size_t>(piece)];
    // Piece vertices in order of first use; extended[i] is the extended vertex of piece vertex i.
    mesh::Faces piece_faces(static_cast<Eigen::Index>(faces.size()), 3);
    std::vector<int> extended(remap.size());
    int* corner = piece_faces.data();
    int* const piece_vertex = remap.data();
    int* const extended_vertex = extended.data();
    int count = 0;
    for (const Triangle& t : faces)
      for (const int x : t) {
        int& r = piece_vertex[x];
        if (r < 0) {
          r = count;
          extended_vertex[count++] = x;
        }
        *corner++ = r;
      }
    extended.resize(static_cast<std::size_t>(count));
    for (const int x : extended) remap[static_cast<std::size_t>(x)] = -1;
    const int surface_vertices = static_cast<int>(extended.size());
    if (options_.cap && !faces.empty()) add_cap(piece, extended, piece_faces, out);
    RowMatrixXf<3>& placed = out.placed[static_cast<std::size_t>(piece)];
    placed.resize(static_cast<Eigen::Index>(extended.size()), 3);
    for (std::size_t i = 0; i < extended.size(); ++i) {
      const int x = extended[i];
      const auto row = static_cast<Eigen::Index>(i);
      if (x < nv_)
        std::memcpy(placed.row(row).data(), placed_.row(x).data(), 3 * sizeof(float));  // as it is
      else
        placed.row(row) = point(x).cast<float>().transpose();
    }
    std::vector<VertexSource>& sources = out.origins[static_cast<std::size_t>(piece)];
    sources.reserve(extended.size());
    for (const int x : extended) sources.push_back(x < nv_ ? VertexSource::copy(x) : source(x, piece));
    mesh::Mesh& m = out.pieces[static_cast<std::size_t>(piece)];
    m = mesh::resample(mesh_, sources, mesh::Faces(0, 3));
    m.faces = std::move(piece_faces);  // valid by construction: moved in, not checked and copied
    set_face_materials(piece, m);
    if (palette_ != nullptr) solve_rest_positions(m, *palette_, placed, sources, 0, options_.rest);
    if (static_cast<int>(sources.size()) > surface_vertices) set_cap_normals(m, surface_vertices);
  }

  /// Welded identity of an extended vertex: seam copies share it.
  int weld_id(int x) {
    if (x < nv_) return weld_(x);
    const EdgePoint& e = points_[static_cast<std::size_t>(x - nv_)];
    return *weld_of_edge_.try_emplace(edge_key(weld_(e.a), weld_(e.b)), nv_ + static_cast<int>(weld_of_edge_.size()))
                .first;
  }

  /// Triangulates the closed cross-section loops bounding this piece in the plane and appends
  /// the cap: its own copies of the loop vertices (so the cap has its own normals), appended to
  /// `extended` as further piece vertices.
  void add_cap(int piece, std::vector<int>& extended, mesh::Faces& faces, MeshCut& out) {
    const auto on_plane = [&](int x) { return x >= nv_ || side(x) == 0; };
    // Directed edges between on-plane vertices, by welded id; a boundary edge has no twin.
    std::unordered_map<std::uint64_t, int> count;
    std::unordered_map<int, int> representative;  // welded id -> piece vertex
    for (Eigen::Index f = 0; f < faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) {
        const int u = faces(f, k), v = faces(f, (k + 1) % 3);
        const int xu = extended[static_cast<std::size_t>(u)], xv = extended[static_cast<std::size_t>(v)];
        if (!on_plane(xu) || !on_plane(xv)) continue;
        const int wu = weld_id(xu), wv = weld_id(xv);
        representative.try_emplace(wu, u);
        representative.try_emplace(wv, v);
        ++count[directed_key(wu, wv)];
      }
    std::vector<std::array<int, 2>> boundary;  // welded ids
    std::unordered_map<int, int> balance;
    for (const auto& [key, n] : count) {
      const int wu = static_cast<int>(key >> 32), wv = static_cast<int>(key & 0xffffffffu);
      if (n != 1 || count.contains(directed_key(wv, wu))) continue;
      boundary.push_back({wu, wv});
      ++balance[wu];
      --balance[wv];
    }
    if (boundary.empty()) return;
    if (std::any_of(balance.begin(), balance.end(), [](const auto& b) { return b.second != 0; })) {
      out.warnings.push_back("mesh '" + mesh_.name +
                             "': the cross-section is not closed (the mesh is open there); piece " +
                             std::string(piece == 0 ? "A" : "B") + " not capped");
      return;
    }
    // 2-D coordinates in the plane, with (e_u, e_v, n) right-handed.
    const Eigen::Vector3d eu = any_perpendicular(normal_), ev = normal_.cross(eu);
    std::unordered_map<int, int> local;  // welded id -> index into pts
    std::vector<int> welded;
    std::vector<Eigen::Vector2d> pts;
    std::vector<std::array<int, 2>> edges;
    const auto local_index = [&](int w) {
      const auto [it, added] = local.try_emplace(w, static_cast<int>(pts.size()));
      if (added) {
        const Eigen::Vector3d x = point(extended[static_cast<std::size_t>(representative.at(w))]);
        pts.emplace_back(x.dot(eu), x.dot(ev));
        welded.push_back(w);
      }
      return it->second;
    };
    for (const auto& e : boundary) edges.push_back({local_index(e[0]), local_index(e[1])});
    std::vector<Triangle> tris;
    int left_out = 0;
    try {
      tris = detail::triangulate_loops_that_can_be(pts, edges, left_out);
    } catch (const TopologyError&) {
      left_out = -1;
    }
    if (left_out != 0)
      out.warnings.push_back(
          "mesh '" + mesh_.name + "': " +
          (left_out < 0 ? std::string("the cross-section loops")
                        : std::to_string(left_out) + " cross-section loop(s)") +
          " cross themselves or each other (the surface self-intersects there); not capped on piece " +
          std::string(piece == 0 ? "A" : "B"));
    if (tris.empty()) return;
    // Cap vertices: copies of the loop vertices.
    std::vector<int> cap_vertex(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const int x = extended[static_cast<std::size_t>(representative.at(welded[i]))];
      cap_vertex[i] = static_cast<int>(extended.size());
      extended.push_back(x);
    }
    // Counter-clockwise in (e_u, e_v) faces +n: right for piece B, reversed for piece A.
    const Eigen::Index first = faces.rows();
    faces.conservativeResize(first + static_cast<Eigen::Index>(tris.size()), 3);
    for (std::size_t t = 0; t < tris.size(); ++t) {
      const int a = cap_vertex[static_cast<std::size_t>(tris[t][0])],
                b = cap_vertex[static_cast<std::size_t>(tris[t][1])],
                c = cap_vertex[static_cast<std::size_t>(tris[t][2])];
      if (piece == 0)
        faces.row(first + static_cast<Eigen::Index>(t)) << a, c, b;
      else
        faces.row(first + static_cast<Eigen::Index>(t)) << a, b, c;
    }
    out.cap_triangles += static_cast<int>(tris.size());
  }

  /// The piece's faces keep the materials of the faces they lie in; its cap faces (after them)
  /// get cap_material_. Left without face_materials when every face has the mesh's material.
  void set_face_materials(int piece, mesh::Mesh& m) const {
    const auto surface = static_cast<Eigen::Index>(faces_[static_cast<std::size_t>(piece)].size());
    const bool capped = m.face_count() > surface && cap_material_ != mesh_.material;
    if (!track_parents_ && !capped) return;
    m.face_materials.setConstant(m.face_count(), cap_material_);
    const std::vector<int>& parents = parents_[static_cast<std::size_t>(piece)];
    for (Eigen::Index f = 0; f < surface; ++f)
      m.face_materials[f] = track_parents_ ? mesh_.face_material(parents[static_cast<std::size_t>(f)]) : mesh_.material;
  }

  /// Normals of the cap vertices (from `first` on): area-weighted normals of the cap faces in
  /// the rest mesh (the cut plane is flat in the placed pose, not necessarily at rest).
  static void set_cap_normals(mesh::Mesh& m, int first) {
    if (m.normals.rows() == 0) return;
    m.normals.bottomRows(m.vertex_count() - first).setZero();
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      if (m.faces(f, 0) < first) continue;
      const Eigen::Vector3f a = m.positions.row(m.faces(f, 0)), b = m.positions.row(m.faces(f, 1)),
                            c = m.positions.row(m.faces(f, 2));
      const Eigen::Vector3f n = (b - a).cross(c - a);
      for (int k = 0; k < 3; ++k) m.normals.row(m.faces(f, k)) += n.transpose();
    }
    for (Eigen::Index v = first; v < m.vertex_count(); ++v)
      if (m.normals.row(v).norm() > 0) m.normals.row(v).normalize();
  }

  const mesh::Mesh& mesh_;
  const RowMatrixXf<3>& placed_;
  const CutOptions& options_;
  const anim::SkinningPalette* palette_ = nullptr;  ///< the placement's, for exact rest positions
  const int nv_;
  Eigen::Vector3d normal_;
  double offset_ = 0;
  cga::Vector<double> plane_;
  double tolerance_ = 0;
  std::vector<signed char> side_;
  std::vector<EdgePoint> points_;
  FlatMap<int> point_of_edge_;
  std::array<std::vector<Triangle>, 2> faces_;
  /// Per face of faces_, the input face it lies in: kept for a local cut (the edit's parents)
  /// and for a mesh with face materials.
  std::array<std::vector<int>, 2> parents_;
  bool track_parents_ = true;
  int parent_ = -1;        ///< the face split_face splits
  int cap_material_ = -1;  ///< material of the cap faces
  int faces_split_ = 0;
  PositionWelder weld_{mesh_.positions};
  FlatMap<int> weld_of_edge_;
};

}  // namespace

MeshCut cut_mesh(const mesh::Mesh& mesh, const RowMatrixXf<3>& placed, const cga::Vector<double>& plane,
                 const CutOptions& options, const anim::SkinningPalette* palette, int cap_material) {
  return Cutter(mesh, placed, plane, options, palette, cap_material).run();
}

cga::Vector<double> cut_plane(const Eigen::Vector3d& normal, double d) {
  if (!normal.allFinite() || !std::isfinite(d)) throw InvalidInputError("the plane must be finite");
  // Any length is a direction: scaled first, so that 1e308 does not overflow its norm.
  const double largest = normal.cwiseAbs().maxCoeff();
  if (!(largest > 0)) throw InvalidInputError("the plane's normal NX,NY,NZ is the zero vector");
  const double offset = d / largest;
  if (!std::isfinite(offset)) throw InvalidInputError("the plane's offset D is too large for its normal");
  return cga::plane(Eigen::Vector3d(normal / largest), offset);
}

ModelCut cut(const anim::RiggedModel& model, const Placement& placement, const cga::Vector<double>& plane,
             const CutOptions& options) {
  require_placement_fits(model, placement);
  // The foot on the plane of any placed vertex lies within the model's box when the plane
  // meets it, and as far as the plane when it does not.
  for (const auto& p : placement.positions)
    if (p.rows() > 0) {
      const Eigen::Vector3d x = p.row(0).transpose().cast<double>(), n(plane[0], plane[1], plane[2]);
      if (n.squaredNorm() > 0)
        require_in_reach(placed_box(placement),
                         x - cga::scalar_product(cga::up<double>(x), plane) / n.squaredNorm() * n, "cut: the plane");
      break;
    }
  ModelCut out;
  std::vector<mesh::Material> materials = model.materials;
  const int cap_material = options.cap ? mesh::cut_surface_material_index(materials) : -1;
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    MeshCut mc =
        cut_mesh(model.meshes[i], placement.positions[i], plane, options, &placement.palettes[i], cap_material);
    out.faces_in += static_cast<int>(model.meshes[i].face_count());
    out.intersection_points += mc.intersection_points;
    out.faces_split += mc.faces_split;
    out.cap_triangles += mc.cap_triangles;
    out.new_vertices -= static_cast<int>(model.meshes[i].vertex_count());
    out.warnings.insert(out.warnings.end(), mc.warnings.begin(), mc.warnings.end());
    for (std::size_t p = 0; p < 2; ++p) {
      out.new_vertices += static_cast<int>(mc.pieces[p].vertex_count());
      if (mc.pieces[p].face_count() == 0) continue;
      out.faces_out[p] += static_cast<int>(mc.pieces[p].face_count());
      out.pieces[p].meshes.push_back(std::move(mc.pieces[p]));
      out.source_mesh[p].push_back(static_cast<int>(i));
      out.origins[p].push_back(std::move(mc.origins[p]));
      out.placed[p].push_back(std::move(mc.placed[p]));
    }
  }
  if (out.pieces[0].meshes.empty() || out.pieces[1].meshes.empty())
    throw TopologyError("cut: the plane misses the model (every face is on its " +
                        std::string(out.pieces[0].meshes.empty() ? "negative" : "positive") + " side)");
  for (anim::RiggedModel& piece : out.pieces) {
    copy_rig(model, piece);
    if (out.cap_triangles > 0) piece.materials = materials;  // with the cut-surface material
  }
  return out;
}

LiveCut cut(LiveModel& live, const cga::Vector<double>& plane, const CutOptions& options) {
  if (options.cap) throw InvalidInputError("cut: `cap` is not available in place; cut() returns two closed pieces");
  const auto [n, d] = cga::plane_parameters(plane);
  const anim::RiggedModel& model = live.model();
  LiveCut out;
  // Every edit is made before any is applied, so that a throw leaves `live` as it was.
  std::vector<LocalEdit> edits(model.meshes.size());
  std::vector<std::vector<signed char>> pieces(model.meshes.size());
  std::array<bool, 2> reached{false, false};
  out.faces_in = face_total(model);
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const MeshIndex& index = live.index().meshes[i];
    const double tolerance = options.snap * index.bvh.diagonal();
    // Twice the snapping tolerance (and a little more when it is 0): the index measures n·x − d
    // in floats, the predicates X·Π in doubles; no face touching the plane may be missed.
    std::vector<int> near;
    index.bvh.faces_near_plane(n, d, 2 * tolerance + 1e-9 * index.bvh.diagonal(), near);
    Cutter(model.meshes[i], live.placement().positions[i], plane, options, tolerance)
        .separate(near, edits[i], pieces[i], out);
    for (const signed char p : pieces[i]) reached[static_cast<std::size_t>(p)] = true;
  }
  if (!reached[0] && !reached[1])
    throw TopologyError("cut: the plane crosses no face of the model (nothing to separate)");
  if (!reached[0] || !reached[1])
    throw TopologyError(std::string("cut: the plane only touches the model (no face on its ") +
                        (reached[0] ? "negative" : "positive") + " side there)");
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    if (edits[i].removed_faces().empty()) continue;
    AppliedEdit applied = live.apply(i, edits[i], options.rest);
    out.new_vertices += static_cast<int>(applied.change.origins.size());
    out.changes.push_back(std::move(applied.change));
    out.piece_of_new_face.push_back(std::move(pieces[i]));
  }
  out.faces_out = face_total(model);
  return out;
}

anim::RiggedModel join_pieces(std::array<anim::RiggedModel, 2> pieces) {
  anim::RiggedModel out = std::move(pieces[0]);
  anim::RiggedModel& b = pieces[1];
  const int offset = b.materials.size() == out.materials.size() ? 0 : static_cast<int>(out.materials.size());
  if (offset != 0) out.materials.insert(out.materials.end(), b.materials.begin(), b.materials.end());
  for (mesh::Mesh& m : b.meshes) {
    if (m.material >= 0) m.material += offset;
    for (Eigen::Index f = 0; f < m.face_materials.rows(); ++f)
      if (m.face_materials[f] >= 0) m.face_materials[f] += offset;
    out.meshes.push_back(std::move(m));
  }
  return out;
}

}  // namespace cgamesh::surgery
