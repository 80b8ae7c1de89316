#include "cgamesh/surgery/tear.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <span>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

#include "polygon_triangulation.hpp"
#include "surgery_common.hpp"

namespace cgamesh::surgery {
namespace {

using mesh::RowMatrixXf;
using mesh::VertexSource;
using Triangle = std::array<int, 3>;

/// A point of the tear path on the input surface.
struct PathPoint {
  enum class Kind { vertex, edge, face };
  Kind kind = Kind::face;
  int face = -1;    ///< input face its barycentric coordinates refer to
  int corner = -1;  ///< vertex: its corner in `face`; edge: the edge k (corner k to k+1)
  std::array<double, 3> bary{0, 0, 0};
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  ///< placed position
  int segment_face = -1;                        ///< the input face holding the segment from the previous point
  int step = 0;                                 ///< the scalpel step whose plane it lies on

  /// 0–2: a corner, 3–5: an edge, 6: the interior of `face`.
  [[nodiscard]] int feature() const noexcept {
    return kind == Kind::vertex ? corner : kind == Kind::edge ? 3 + corner : 6;
  }
};

/// Π of one step, as the CGA vector n + d e∞ and as (n, d).
struct StepPlane {
  cga::Vector<double> pi;
  Eigen::Vector3d n;
  double d = 0;
};

/// One direction of the search for the surface path along Π.
struct Walker {
  int face = -1;
  int entry = 6;    ///< feature of `face` the walker entered by
  int forced = -1;  ///< at the start inside a face: which of the two crossings to leave by
  std::vector<PathPoint> points;
  double length = 0;
  int steps = 0;
  bool done = false, failed = false;
};

class Tearer {
 public:
  Tearer(const mesh::Mesh& mesh, const RowMatrixXf<3>& placed, const anim::SkinningPalette& palette,
         const MeshIndex& index, const TearOptions& options)
      : mesh_(mesh),
        placed_(placed),
        palette_(palette),
        index_(index),
        options_(options),
        nv_(static_cast<int>(mesh.vertex_count())),
        tol_(options.snap * index.bvh.diagonal()) {}

  /// The entry point S of the blade: its first crossing of the surface from the handle.
  [[nodiscard]] PathPoint entry(const mesh::SegmentHit& hit) const { return snapped(hit.face, hit.barycentric); }

  /// The whole path over all steps; consecutive points share a face.
  [[nodiscard]] std::vector<PathPoint> trace(const std::vector<PathPoint>& entries, std::span<const Scalpel> scalpel) {
    std::vector<PathPoint> path{entries.front()};
    for (std::size_t i = 0; i + 1 < entries.size(); ++i) {
      if (near(path.back().x, entries[i + 1].x)) continue;  // the blade did not move on the surface
      planes_.push_back(step_plane(path.back(), scalpel[i + 1], static_cast<int>(i)));
      PathPoint target = entries[i + 1];
      target.step = static_cast<int>(planes_.size()) - 1;
      path.back().step = target.step;
      for (PathPoint& p : walk(path.back(), target, static_cast<int>(i))) path.push_back(std::move(p));
    }
    // A tear needs a vertex between its ends to open at.
    if (path.size() == 2) path.insert(path.begin() + 1, midpoint(path[0], path[1]));
    return path;
  }

  /// Re-triangulates the faces the path crosses and duplicates the path vertices (edit());
  /// returns the number of faces split.
  /// @throws TopologyError when that changes nothing.
  int prepare(const std::vector<PathPoint>& path) {
    retriangulate(path);
    const int faces_split = static_cast<int>(edit_.removed_faces.size());
    duplicate(path);
    const bool opens =
        options_.open > 0 && std::any_of(copies_.begin(), copies_.end(), [](const auto& c) { return !c.empty(); });
    if (faces_split == 0 && edit_.new_vertices.empty() && !opens)
      throw TopologyError("tear: the path runs along edges where mesh '" + mesh_.name +
                          "' is split already (its faces there share no vertices), so the tear changes nothing; "
                          "give an opening width to move the two sides apart");
    return faces_split;
  }

  [[nodiscard]] const LocalEdit& edit() const noexcept { return edit_; }

  /// Calls visit(vertex, side) for every copy of a path vertex in the edited mesh, where
  /// vertex_of maps an extended id to its vertex there (−1: not used).
  template <class VertexOf, class Visit>
  void for_each_copy(const VertexOf& vertex_of, const Visit& visit) const {
    for (const auto& point : copies_)
      for (const auto& [x, sign] : point)
        if (const int v = vertex_of(x); v >= 0) visit(v, static_cast<signed char>(sign));
  }

  /// Step 6: the copies move apart along ±n of their step's plane, by open·sin(π s/L) in all
  /// at arc length s of a path of length L; rest positions follow through the inverse of each
  /// vertex's blended skinning map (Σ w Aⱼ), so the tear is open in the placed pose.
  /// @param[in,out] m, placed  the edited mesh and its placed positions
  template <class VertexOf>
  void move_apart(const std::vector<PathPoint>& path, mesh::Mesh& m, RowMatrixXf<3>& placed,
                  const VertexOf& vertex_of) const {
    if (options_.open == 0) return;
    std::vector<double> arc(path.size(), 0.0);
    for (std::size_t i = 1; i < path.size(); ++i) arc[i] = arc[i - 1] + (path[i].x - path[i - 1].x).norm();
    const double length = arc.back();
    for (std::size_t i = 0; i < path.size(); ++i) {
      const double width = options_.open * std::sin(std::numbers::pi * arc[i] / length);
      const Eigen::Vector3d n = planes_[static_cast<std::size_t>(path[i].step)].n;
      for (const auto& [x, sign] : copies_[i])
        if (const int v = vertex_of(x); v >= 0) move_vertex(m, placed, v, 0.5 * width * sign * n);
    }
  }

 private:
  /// Moves placed vertex v by `shift`, and its rest position by the inverse of its blended
  /// skinning map.
  void move_vertex(mesh::Mesh& m, RowMatrixXf<3>& placed, int v, const Eigen::Vector3d& shift) const {
    placed.row(v) += shift.cast<float>().transpose();
    const Eigen::Matrix3d linear = anim::blended_affine(m, palette_, v).leftCols<3>();
    m.positions.row(v) += linear.colPivHouseholderQr().solve(shift).cast<float>().transpose();
  }

  // ---- geometry ----------------------------------------------------------------------------

  [[nodiscard]] int weld(int v) const { return index_.weld[static_cast<std::size_t>(v)]; }
  [[nodiscard]] int corner(int f, int k) const { return mesh_.faces(f, k % 3); }
  /// Placed position of a vertex; seam copies use their welded representative, so both sides
  /// of a seam see the same point and make the same decisions.
  [[nodiscard]] Eigen::Vector3d position(int v) const { return placed_.row(weld(v)).cast<double>().transpose(); }
  [[nodiscard]] bool near(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const { return (a - b).norm() <= tol_; }

  [[nodiscard]] Eigen::Vector3d at(int f, const std::array<double, 3>& b) const {
    return b[0] * position(corner(f, 0)) + b[1] * position(corner(f, 1)) + b[2] * position(corner(f, 2));
  }

  /// A point of face f given by barycentric coordinates, moved onto a corner or an edge within
  /// the snapping tolerance.
  [[nodiscard]] PathPoint snapped(int f, const Eigen::Vector3d& bary) const {
    PathPoint p;
    p.face = f;
    p.bary = {bary[0], bary[1], bary[2]};
    p.x = at(f, p.bary);
    for (int k = 0; k < 3; ++k)
      if (near(p.x, position(corner(f, k)))) return vertex_point(f, k);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = position(corner(f, k)), ab = position(corner(f, k + 1)) - a;
      const double t = std::clamp((p.x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      if ((a + t * ab - p.x).norm() <= tol_) return edge_point(f, k, t);
    }
    return p;
  }

  [[nodiscard]] PathPoint vertex_point(int f, int k) const {
    PathPoint p;
    p.kind = PathPoint::Kind::vertex;
    p.face = f;
    p.corner = k;
    p.bary[static_cast<std::size_t>(k)] = 1;
    p.x = position(corner(f, k));
    return p;
  }

  /// The point (1 − t) corner k + t corner k+1 of face f.
  [[nodiscard]] PathPoint edge_point(int f, int k, double t) const {
    PathPoint p;
    p.kind = PathPoint::Kind::edge;
    p.face = f;
    p.corner = k;
    p.bary[static_cast<std::size_t>(k)] = 1 - t;
    p.bary[static_cast<std::size_t>((k + 1) % 3)] = t;
    p.x = at(f, p.bary);
    return p;
  }

  /// Π through Sᵢ, the handle and the tip at tᵢ₊₁: the dual of Sᵢ ∧ H ∧ T ∧ e∞ (section 2.3).
  [[nodiscard]] static StepPlane step_plane(const PathPoint& s, const Scalpel& blade, int step) {
    const auto outer = cga::plane_through<double>(s.x, blade.handle, blade.tip);
    const cga::Vector<double> dual = cga::dual(outer);
    const double scale = (blade.handle - s.x).norm() * (blade.tip - s.x).norm();
    if (!(Eigen::Vector3d(dual[0], dual[1], dual[2]).norm() > 1e-12 * scale))
      throw InvalidInputError("tear: at step " + std::to_string(step + 1) +
                              " the blade's line passes through the entry point " + "of step " + std::to_string(step) +
                              "; the plane of the tear is undefined");
    const auto [n, d] = cga::plane_parameters(dual);
    return {cga::plane(n, d), n, d};
  }

  /// The middle of the segment from a to b, in b's segment face.
  [[nodiscard]] PathPoint midpoint(const PathPoint& a, const PathPoint& b) const {
    const int f = b.segment_face;
    const std::array<double, 3> x = bary_in(a, f), y = bary_in(b, f);
    PathPoint m = snapped(f, Eigen::Vector3d(0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1]), 0.5 * (x[2] + y[2])));
    m.segment_face = f;
    m.step = b.step;
    return m;
  }

  /// Signed distance of vertex v from Π: X·Π (cga) or n·x − d, 0 within the tolerance.
  [[nodiscard]] double distance(const StepPlane& p, int v) const {
    const Eigen::Vector3d x = position(v);
    const double s =
        options_.predicates == Predicates::cga ? cga::scalar_product(cga::up<double>(x), p.pi) : p.n.dot(x) - p.d;
    return std::abs(s) <= tol_ ? 0.0 : s;
  }

  /// Where Π meets the border of face f: its corners on Π and the crossings of its edges whose
  /// ends lie strictly on opposite sides, at t = (A·Π) / (A·Π − B·Π).
  [[nodiscard]] std::vector<PathPoint> crossings(int f, const StepPlane& p) const {
    const std::array<double, 3> d{distance(p, corner(f, 0)), distance(p, corner(f, 1)), distance(p, corner(f, 2))};
    std::vector<PathPoint> out;
    for (int k = 0; k < 3; ++k)
      if (d[static_cast<std::size_t>(k)] == 0) out.push_back(vertex_point(f, k));
    for (int k = 0; k < 3; ++k) {
      const double a = d[static_cast<std::size_t>(k)], b = d[static_cast<std::size_t>((k + 1) % 3)];
      if (a * b < 0) out.push_back(edge_point(f, k, a / (a - b)));
    }
    return out;
  }

  [[nodiscard]] int corner_of(int f, int welded) const {
    for (int k = 0; k < 3; ++k)
      if (weld(corner(f, k)) == welded) return k;
    return -1;
  }

  /// The faces around the welded vertex at corner k of face f, f first: rotating across the
  /// edges leaving the vertex, then (at an open border) across the edges arriving at it.
  [[nodiscard]] std::vector<int> fan(int f, int k) const {
    const int w = weld(corner(f, k));
    std::vector<int> out{f};
    for (const int turn : {0, 2}) {
      int cur = f, c = k;
      while (true) {
        const int g = index_.neighbor[static_cast<std::size_t>(cur)][static_cast<std::size_t>((c + turn) % 3)];
        if (g == f) return out;  // closed fan
        if (g < 0 || std::find(out.begin(), out.end(), g) != out.end()) break;
        c = corner_of(g, w);
        if (c < 0) break;
        out.push_back(g);
        cur = g;
      }
    }
    return out;
  }

  // ---- the surface path --------------------------------------------------------------------

  /// The face to continue in after the path reached the vertex at corner k of face f, coming
  /// from `previous`: the face of the vertex's fan where Π leaves the vertex most nearly
  /// straight on.
  [[nodiscard]] std::pair<int, int> continue_at_vertex(int f, int k, const Eigen::Vector3d& previous,
                                                       const StepPlane& plane) const {
    const int w = weld(corner(f, k));
    const Eigen::Vector3d v = position(corner(f, k));
    const Eigen::Vector3d back = (previous - v).normalized();
    std::pair<int, int> best{-1, -1};
    double best_dot = 2;
    for (const int g : fan(f, k)) {
      if (g == f) continue;
      const int c = corner_of(g, w);
      for (const PathPoint& x : crossings(g, plane)) {
        if (x.feature() == c || near(x.x, previous)) continue;
        const double dot = (x.x - v).normalized().dot(back);
        if (dot < best_dot) {
          best_dot = dot;
          best = {g, c};
        }
      }
    }
    return best;
  }

  void advance(Walker& w, const PathPoint& target, const StepPlane& plane, int start_face) const {
    if (w.face == target.face) {
      PathPoint t = target;
      t.segment_face = w.face;
      if (w.points.size() > 1 && near(w.points.back().x, t.x)) w.points.pop_back();
      w.points.push_back(t);
      w.done = true;
      return;
    }
    if (w.steps > 0 && w.face == start_face) {  // went round a closed section without meeting the target
      w.failed = true;
      return;
    }
    std::vector<PathPoint> exits = crossings(w.face, plane);
    std::erase_if(exits, [&](const PathPoint& x) { return x.feature() == w.entry; });
    if (w.forced >= 0) {
      if (w.forced >= static_cast<int>(exits.size())) {
        w.failed = true;
        return;
      }
      exits = {exits[static_cast<std::size_t>(w.forced)]};
      w.forced = -1;
    }
    if (exits.empty() || ++w.steps > static_cast<int>(mesh_.face_count())) {
      w.failed = true;
      return;
    }
    PathPoint exit = exits.front();
    exit.segment_face = w.face;
    exit.step = target.step;
    const Eigen::Vector3d from = w.points.empty() ? exit.x : w.points.back().x;
    w.length += (exit.x - from).norm();
    w.points.push_back(exit);
    if (near(exit.x, target.x)) {
      w.done = true;
      return;
    }
    if (exit.kind == PathPoint::Kind::edge) {
      const int g = index_.neighbor[static_cast<std::size_t>(w.face)][static_cast<std::size_t>(exit.corner)];
      if (g < 0) {  // the section leaves the surface at an open border
        w.failed = true;
        return;
      }
      w.entry = 3 + index_.edge_across(w.face, exit.corner);
      w.face = g;
      return;
    }
    const auto [g, c] = continue_at_vertex(w.face, exit.corner, from, plane);
    if (g < 0) {
      w.failed = true;
      return;
    }
    w.face = g;
    w.entry = c;
  }

  /// The shorter surface path from `start` to `target` along Π of the last step: walkers leave
  /// `start` in every direction Π allows and the shortest one to arrive wins.
  [[nodiscard]] std::vector<PathPoint> walk(const PathPoint& start, const PathPoint& target, int step) const {
    const StepPlane& plane = planes_.back();
    std::vector<Walker> walkers;
    const auto add = [&](int face, int entry, int forced) {
      Walker w;
      w.face = face;
      w.entry = entry;
      w.forced = forced;
      walkers.push_back(std::move(w));
    };
    if (start.kind == PathPoint::Kind::face) {
      add(start.face, 6, 0);
      add(start.face, 6, 1);
    } else if (start.kind == PathPoint::Kind::edge) {
      add(start.face, start.feature(), -1);
      const int g = index_.neighbor[static_cast<std::size_t>(start.face)][static_cast<std::size_t>(start.corner)];
      if (g >= 0) add(g, 3 + index_.edge_across(start.face, start.corner), -1);
    } else {
      const int w = weld(corner(start.face, start.corner));
      for (const int g : fan(start.face, start.corner)) add(g, corner_of(g, w), -1);
    }
    for (Walker& w : walkers) {
      PathPoint s = start;
      w.points.push_back(s);
    }
    while (true) {
      Walker* next = nullptr;
      for (Walker& w : walkers)
        if (!w.failed && (next == nullptr || w.length < next->length)) next = &w;
      if (next == nullptr)
        throw TopologyError("tear: no surface path along the plane of step " + std::to_string(step + 1) +
                            " joins the blade's entry points (they lie on different parts of the surface, or the " +
                            "section runs off an open border)");
      advance(*next, target, plane, start.face);
      if (next->done) {
        next->points.erase(next->points.begin());
        return std::move(next->points);
      }
    }
  }

  // ---- re-triangulation --------------------------------------------------------------------

  /// Barycentric coordinates of path point p in face g (a face sharing its support).
  [[nodiscard]] std::array<double, 3> bary_in(const PathPoint& p, int g) const {
    if (p.face == g) return p.bary;
    std::array<double, 3> out{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      if (p.bary[static_cast<std::size_t>(k)] == 0) continue;
      const int c = corner_of(g, weld(corner(p.face, k)));
      if (c < 0) throw TopologyError("tear: internal error: a path point is not on the face of its segment");
      out[static_cast<std::size_t>(c)] = p.bary[static_cast<std::size_t>(k)];
    }
    return out;
  }

  /// 2-D coordinates (b₁, b₂) of barycentric b, exact on the three edges: b₀ = 0 gives a point
  /// whose coordinates sum to 1 exactly, so CGAL sees it on the edge and makes no sliver.
  [[nodiscard]] static Eigen::Vector2d plane_coordinates(const std::array<double, 3>& b) {
    if (b[0] == 0) {
      const double v = b[2] >= 0.5 ? b[2] : 1 - b[1];
      return {1 - v, v};
    }
    return {b[1], b[2]};
  }

  /// The new vertex of path point i in face f (seam copies stay apart: the key holds the
  /// face's own vertex indices).
  int new_vertex(const PathPoint& p, int i, int f) {
    const std::array<double, 3> b = bary_in(p, f);
    std::array<int, 4> key{-1, -1, -1, i};
    VertexSource s;
    if (p.kind == PathPoint::Kind::edge) {
      int a = -1, c = -1;
      for (int k = 0; k < 3; ++k)
        if (b[static_cast<std::size_t>(k)] != 0) (a < 0 ? a : c) = k;
      int va = corner(f, a), vc = corner(f, c);
      double t = b[static_cast<std::size_t>(c)];
      if (va > vc) {
        std::swap(va, vc);
        t = 1 - t;
      }
      key = {va, vc, -1, i};
      s = VertexSource::edge(va, vc, static_cast<float>(t));
    } else {
      key = {f, -1, -2, i};
      s = VertexSource::face(corner(f, 0), corner(f, 1), corner(f, 2), static_cast<float>(b[0]),
                             static_cast<float>(b[1]), static_cast<float>(b[2]));
    }
    const auto [it, added] = vertex_of_point_.try_emplace(key, -1);
    if (added) {
      it->second = edit_.add_vertex(s, p.x, nv_);
      point_of_new_.push_back(i);
    }
    return it->second;
  }

  /// Extended id of path point i as seen from face f.
  int vertex_in(const std::vector<PathPoint>& path, int i, int f) {
    const PathPoint& p = path[static_cast<std::size_t>(i)];
    if (p.kind == PathPoint::Kind::vertex) return corner(f, corner_of(f, weld(corner(p.face, p.corner))));
    return new_vertex(p, i, f);
  }

  void retriangulate(const std::vector<PathPoint>& path) {
    struct Work {
      std::vector<int> points;
      std::vector<std::array<int, 2>> segments;
    };
    std::vector<int> order;
    std::unordered_map<int, Work> work;
    const auto touch = [&](int f) -> Work& {
      const auto [it, added] = work.try_emplace(f);
      if (added) order.push_back(f);
      return it->second;
    };
    const auto add_point = [&](int f, int i) {
      Work& w = touch(f);
      if (std::find(w.points.begin(), w.points.end(), i) == w.points.end()) w.points.push_back(i);
    };
    for (int i = 0; i < static_cast<int>(path.size()); ++i) {
      const PathPoint& p = path[static_cast<std::size_t>(i)];
      const bool vertex = p.kind == PathPoint::Kind::vertex;
      if (!vertex) {
        add_point(p.face, i);
        const int g = p.kind == PathPoint::Kind::edge
                          ? index_.neighbor[static_cast<std::size_t>(p.face)][static_cast<std::size_t>(p.corner)]
                          : -1;
        if (g >= 0) add_point(g, i);  // no T-junction in the face across the edge
      }
      // A segment between two corners runs along an existing edge: nothing to insert.
      const bool previous_vertex = i > 0 && path[static_cast<std::size_t>(i - 1)].kind == PathPoint::Kind::vertex;
      if (i == 0 || (vertex && previous_vertex)) continue;
      const int f = p.segment_face;
      if (!vertex) add_point(f, i);
      if (!previous_vertex) add_point(f, i - 1);
      touch(f).segments.push_back({i - 1, i});
    }
    for (const int f : order) {
      Work& w = work[f];
      std::vector<Eigen::Vector2d> pts{{0, 0}, {1, 0}, {0, 1}};
      std::vector<int> ids{corner(f, 0), corner(f, 1), corner(f, 2)};
      std::unordered_map<int, int> local;
      const auto local_of = [&](int i) {
        const PathPoint& p = path[static_cast<std::size_t>(i)];
        if (p.kind == PathPoint::Kind::vertex) return corner_of(f, weld(corner(p.face, p.corner)));
        const auto [it, added] = local.try_emplace(i, static_cast<int>(pts.size()));
        if (added) {
          pts.push_back(plane_coordinates(bary_in(p, f)));
          ids.push_back(vertex_in(path, i, f));
        }
        return it->second;
      };
      for (const int i : w.points) local_of(i);
      std::vector<std::array<int, 2>> segments;
      for (const auto& s : w.segments) segments.push_back({local_of(s[0]), local_of(s[1])});
      std::vector<Triangle> tris;
      try {
        tris = detail::triangulate_constrained(pts, segments);
      } catch (const TopologyError&) {
        throw TopologyError("tear: the tear path crosses itself in face " + std::to_string(f) + " of mesh '" +
                            mesh_.name + "'");
      }
      edit_.removed_faces.push_back(f);
      for (const Triangle& t : tris) {
        edit_.new_faces.push_back({ids[static_cast<std::size_t>(t[0])], ids[static_cast<std::size_t>(t[1])],
                                   ids[static_cast<std::size_t>(t[2])]});
        edit_.new_face_parent.push_back(f);
      }
    }
  }

  // ---- opening -----------------------------------------------------------------------------

  /// Identity of an extended vertex on the surface: welded id of an old vertex, −1 − i for a
  /// new vertex of path point i.
  [[nodiscard]] long long key(int x) const {
    return x < nv_ ? weld(x) : -1 - static_cast<long long>(point_of_new_[static_cast<std::size_t>(x - nv_)]);
  }
  [[nodiscard]] long long point_key(const std::vector<PathPoint>& path, int i) const {
    const PathPoint& p = path[static_cast<std::size_t>(i)];
    return p.kind == PathPoint::Kind::vertex ? weld(corner(p.face, p.corner)) : -1 - static_cast<long long>(i);
  }

  /// Every path vertex but the two ends is split in two: the faces on either side of the path
  /// (connected around it through edges that are not on the path) get their own copy.
  void duplicate(const std::vector<PathPoint>& path) {
    const int n = static_cast<int>(path.size());
    std::set<std::pair<long long, long long>> path_edges;
    for (int i = 1; i < n; ++i) path_edges.insert(std::minmax(point_key(path, i - 1), point_key(path, i)));
    // Faces around old path vertices become editable new faces too.
    std::unordered_set<int> removed(edit_.removed_faces.begin(), edit_.removed_faces.end());
    for (int i = 1; i + 1 < n; ++i) {
      const PathPoint& p = path[static_cast<std::size_t>(i)];
      if (p.kind != PathPoint::Kind::vertex) continue;
      for (const int g : fan(p.face, p.corner)) {
        if (!removed.insert(g).second) continue;
        edit_.removed_faces.push_back(g);
        edit_.new_faces.push_back({corner(g, 0), corner(g, 1), corner(g, 2)});
        edit_.new_face_parent.push_back(g);
      }
    }
    std::unordered_map<long long, std::vector<int>> faces_at;
    for (int t = 0; t < static_cast<int>(edit_.new_faces.size()); ++t)
      for (const int x : edit_.new_faces[static_cast<std::size_t>(t)]) faces_at[key(x)].push_back(t);
    copies_.assign(static_cast<std::size_t>(n), {});
    for (int i = 1; i + 1 < n; ++i) {
      const long long k = point_key(path, i);
      const auto found = faces_at.find(k);
      if (found == faces_at.end()) continue;
      std::vector<int>& faces = found->second;
      std::sort(faces.begin(), faces.end());
      faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
      // Union-find over the faces around the point, joined across edges off the path.
      UnionFind sets(faces.size());
      const auto root = [&](int a) { return sets.find(a); };
      std::unordered_map<long long, int> across;  // other end of an edge at the point -> a face
      for (std::size_t a = 0; a < faces.size(); ++a) {
        const Triangle& t = edit_.new_faces[static_cast<std::size_t>(faces[a])];
        for (const int x : t) {
          const long long o = key(x);
          if (o == k || path_edges.contains(std::minmax(k, o))) continue;
          const auto [it, added] = across.try_emplace(o, static_cast<int>(a));
          if (!added) sets.unite(static_cast<int>(a), it->second);
        }
      }
      std::map<int, int> group_of_root;
      for (std::size_t a = 0; a < faces.size(); ++a)
        group_of_root.try_emplace(root(static_cast<int>(a)), static_cast<int>(group_of_root.size()));
      if (group_of_root.size() < 2) continue;
      const StepPlane& plane = planes_[static_cast<std::size_t>(path[static_cast<std::size_t>(i)].step)];
      // Side of each group: where its faces' other vertices lie relative to Π.
      std::vector<double> side(group_of_root.size(), 0.0);
      for (std::size_t a = 0; a < faces.size(); ++a)
        for (const int x : edit_.new_faces[static_cast<std::size_t>(faces[a])])
          if (key(x) != k)
            side[static_cast<std::size_t>(group_of_root[root(static_cast<int>(a))])] += signed_offset(plane, x);
      std::vector<int> sign(side.size());
      for (std::size_t g = 0; g < side.size(); ++g) sign[g] = side[g] > 0 ? 1 : side[g] < 0 ? -1 : (g == 0 ? 1 : -1);
      if (sign.size() == 2 && sign[0] == sign[1]) sign[1] = -sign[0];
      // A vertex the faces of one group alone use (a seam copy, or a mesh without shared
      // vertices) is that group's already: only one that several groups share is copied.
      std::map<int, std::set<int>> groups_of;  // extended id -> the groups using it
      for (std::size_t a = 0; a < faces.size(); ++a)
        for (const int x : edit_.new_faces[static_cast<std::size_t>(faces[a])])
          if (key(x) == k) groups_of[x].insert(group_of_root[root(static_cast<int>(a))]);
      std::map<std::pair<int, int>, int> copy_of;  // (group, extended id) -> its copy
      for (std::size_t a = 0; a < faces.size(); ++a) {
        const int g = group_of_root[root(static_cast<int>(a))];
        for (int& x : edit_.new_faces[static_cast<std::size_t>(faces[a])]) {
          if (key(x) != k) continue;
          const auto [it, added] = copy_of.try_emplace({g, x}, x);
          const std::set<int>& users = groups_of[x];
          if (added && users.size() > 1 && g != *users.begin()) {
            const VertexSource s =
                x < nv_ ? VertexSource::copy(x) : edit_.new_vertices[static_cast<std::size_t>(x - nv_)];
            const Eigen::Vector3d y = x < nv_ ? placed_.row(x).cast<double>().transpose()
                                              : edit_.new_placed[static_cast<std::size_t>(x - nv_)];
            it->second = edit_.add_vertex(s, y, nv_, static_cast<signed char>(sign[static_cast<std::size_t>(g)]));
            point_of_new_.push_back(i);
          }
          x = it->second;
        }
      }
      for (const auto& [gx, x] : copy_of) {
        copies_[static_cast<std::size_t>(i)].push_back({x, sign[static_cast<std::size_t>(gx.first)]});
        if (options_.own_side_influences && x >= nv_)
          restrict_influences(edit_.new_vertices[static_cast<std::size_t>(x - nv_)], plane,
                              sign[static_cast<std::size_t>(gx.first)]);
      }
    }
  }

  /// Signed distance of an extended vertex from Π (no snapping).
  [[nodiscard]] double signed_offset(const StepPlane& plane, int x) const {
    const Eigen::Vector3d y = x < nv_ ? position(x) : edit_.new_placed[static_cast<std::size_t>(x - nv_)];
    return plane.n.dot(y) - plane.d;
  }

  void restrict_influences(VertexSource& s, const StepPlane& plane, int sign) const {
    std::uint8_t mask = 0;
    for (int k = 0; k < s.count(); ++k)
      if (distance(plane, s.vertex[static_cast<std::size_t>(k)]) * sign > 0) mask |= static_cast<std::uint8_t>(1u << k);
    if (mask != 0) s.influence_mask = mask;
  }

  std::vector<StepPlane> planes_;
  /// Per path point: its copies (extended id, side ±1); empty where it was not split.
  std::vector<std::vector<std::pair<int, int>>> copies_;
  const mesh::Mesh& mesh_;
  const RowMatrixXf<3>& placed_;
  const anim::SkinningPalette& palette_;
  const MeshIndex& index_;
  const TearOptions& options_;
  const int nv_;
  const double tol_;
  LocalEdit edit_;
  std::map<std::array<int, 4>, int> vertex_of_point_;
  std::vector<int> point_of_new_;  ///< per new vertex: its path point
};

/// Checks the input, finds the torn mesh (the one the blade enters first at t₀; later steps
/// must enter it too) and traces the path; then returns finish(tearer, torn mesh, path).
template <class Finish>
auto trace_tear(const anim::RiggedModel& model, const Placement& placement, const SurfaceIndex& index,
                std::span<const Scalpel> scalpel, const TearOptions& options, const Finish& finish) {
  if (scalpel.size() < 2)
    throw InvalidInputError("tear: the scalpel needs at least 2 time steps, got " + std::to_string(scalpel.size()));
  if (!(options.open >= 0) || !std::isfinite(options.open))
    throw InvalidInputError("tear: the opening width must be a finite number >= 0");
  for (std::size_t i = 0; i < scalpel.size(); ++i) {
    if (!scalpel[i].handle.allFinite() || !scalpel[i].tip.allFinite())
      throw InvalidInputError("tear: scalpel step " + std::to_string(i) + " holds NaN or infinity");
    if (scalpel[i].handle == scalpel[i].tip)
      throw InvalidInputError("tear: scalpel step " + std::to_string(i) +
                              " has handle == tip (a blade of zero length)");
  }
  const auto first_hit = [&](std::size_t m, const Scalpel& s) {
    const auto hits = index.meshes[m].bvh.segment_hits(s.handle, s.tip);
    return hits.empty() ? mesh::SegmentHit{} : hits.front();
  };
  int torn = -1;
  mesh::SegmentHit start;
  for (std::size_t m = 0; m < model.meshes.size(); ++m) {
    const mesh::SegmentHit h = first_hit(m, scalpel[0]);
    if (h.face >= 0 && (torn < 0 || h.t < start.t)) {
      start = h;
      torn = static_cast<int>(m);
    }
  }
  if (torn < 0) throw TopologyError("tear: the scalpel at step 0 does not meet the surface");
  const auto tm = static_cast<std::size_t>(torn);
  Tearer tearer(model.meshes[tm], placement.positions[tm], placement.palettes[tm], index.meshes[tm], options);
  std::vector<PathPoint> entries{tearer.entry(start)};
  for (std::size_t i = 1; i < scalpel.size(); ++i) {
    const mesh::SegmentHit h = first_hit(tm, scalpel[i]);
    if (h.face < 0)
      throw TopologyError("tear: the scalpel at step " + std::to_string(i) + " does not meet the surface of mesh '" +
                          model.meshes[tm].name + "'");
    entries.push_back(tearer.entry(h));
  }
  const std::vector<PathPoint> path = tearer.trace(entries, scalpel);
  if (path.size() < 2) throw TopologyError("tear: the scalpel does not move over the surface: nothing to tear");
  return finish(tearer, tm, path);
}

/// The statistics both forms report, but faces_out and new_vertices.
void record(TearStats& out, const anim::RiggedModel& model, const std::vector<PathPoint>& path, int faces_split) {
  for (const PathPoint& p : path) out.path.push_back(p.x);
  out.intersection_points = static_cast<int>(path.size());
  out.faces_in = face_total(model);
  out.faces_split = faces_split;
}

}  // namespace

ModelTear tear(const anim::RiggedModel& model, const Placement& placement, const SurfaceIndex& index,
               std::span<const Scalpel> scalpel, const TearOptions& options) {
  require_placement_fits(model, placement);
  require_index_fits(model, index, "tear");
  return trace_tear(
      model, placement, index, scalpel, options,
      [&](Tearer& tearer, std::size_t tm, const std::vector<PathPoint>& path) {
        ModelTear out;
        out.mesh = static_cast<int>(tm);
        record(out, model, path, tearer.prepare(path));
        EditedMesh edited =
            apply_edit(model.meshes[tm], placement.positions[tm], placement.palettes[tm], tearer.edit(), options.rest);
        const auto vertex_of = [&](int x) { return edited.vertex_of[static_cast<std::size_t>(x)]; };
        tearer.move_apart(path, edited.mesh, edited.placed, vertex_of);
        out.side.assign(static_cast<std::size_t>(edited.mesh.vertex_count()), 0);
        tearer.for_each_copy(vertex_of, [&](int v, signed char side) { out.side[static_cast<std::size_t>(v)] = side; });
        out.new_vertices = static_cast<int>(edited.mesh.vertex_count() - model.meshes[tm].vertex_count());
        // Everything but the torn mesh is copied as it is.
        copy_rig(model, out.model);
        for (std::size_t m = 0; m < model.meshes.size(); ++m)
          out.model.meshes.push_back(m == tm ? std::move(edited.mesh) : model.meshes[m]);
        out.origins = std::move(edited.origins);
        out.placed = std::move(edited.placed);
        out.faces_out = face_total(out.model);
        return out;
      });
}

LiveTear tear(LiveModel& live, std::span<const Scalpel> scalpel, const TearOptions& options) {
  return trace_tear(
      live.model(), live.placement(), live.index(), scalpel, options,
      [&](Tearer& tearer, std::size_t tm, const std::vector<PathPoint>& path) {
        LiveTear out;
        record(out, live.model(), path, tearer.prepare(path));
        AppliedEdit applied = apply_edit_in_place(live, tm, tearer.edit(), options.rest, [&](const AppliedEdit& a) {
          tearer.move_apart(path, detail::LiveAccess::mesh(live, tm), detail::LiveAccess::placed(live, tm),
                            [&](int x) { return a.vertex_of(x); });
        });
        tearer.for_each_copy([&](int x) { return applied.vertex_of(x); },
                             [&](int v, signed char side) { out.sides.emplace_back(v, side); });
        out.new_vertices = static_cast<int>(applied.change.origins.size());
        out.faces_out = face_total(live.model());
        out.change = std::move(applied.change);
        return out;
      });
}

ModelTear tear(const anim::RiggedModel& model, const Placement& placement, std::span<const Scalpel> scalpel,
               const TearOptions& options) {
  return tear(model, placement, SurfaceIndex::build(model, placement), scalpel, options);
}

}  // namespace cgamesh::surgery
