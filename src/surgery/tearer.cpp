#include "tearer.hpp"

#include <algorithm>
#include <cmath>
#include <map>
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

namespace cgamesh::surgery::detail {

using mesh::RowMatrixXf;
using mesh::VertexSource;
using Triangle = std::array<int, 3>;

Tearer::Tearer(const mesh::Mesh& mesh, const RowMatrixXf<3>& placed, const anim::SkinningPalette& palette,
               const MeshIndex& index, const TearOptions& options)
    : mesh_(mesh),
      placed_(placed),
      palette_(palette),
      index_(index),
      options_(options),
      nv_(static_cast<int>(mesh.vertex_count())),
      tol_(options.snap * index.bvh.diagonal()) {}

PathPoint Tearer::entry(const mesh::SegmentHit& hit) const { return snapped(hit.face, hit.barycentric); }

std::vector<PathPoint> Tearer::trace(const std::vector<PathPoint>& entries, std::span<const Scalpel> scalpel) {
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

// @throws TopologyError when that changes nothing (no face split, no vertex added, no opening).
int Tearer::prepare(const std::vector<PathPoint>& path) {
  retriangulate(path);
  const int faces_split = static_cast<int>(edit_.removed_faces().size());
  duplicate(path);
  const bool opens =
      options_.open > 0 && std::any_of(copies_.begin(), copies_.end(), [](const auto& c) { return !c.empty(); });
  if (faces_split == 0 && edit_.new_vertices().empty() && !opens)
    throw TopologyError("tear: the path runs along edges where mesh '" + mesh_.name +
                        "' is split already (its faces there share no vertices), so the tear changes nothing; "
                        "give an opening width to move the two sides apart");
  return faces_split;
}

// ---- trace() ------------------------------------------------------------------------------------

// The dual of Sᵢ ∧ H ∧ T ∧ e∞ (section 2.3).
StepPlane Tearer::step_plane(const PathPoint& s, const Scalpel& blade, int step) {
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

// Along Π of the last step: walkers leave `start` in every direction Π allows, the shortest one
// so far moves on, and the first to arrive wins.
std::vector<PathPoint> Tearer::walk(const PathPoint& start, const PathPoint& target, int step) const {
  const StepPlane& plane = planes_.back();
  std::vector<Walker> walkers = start_walkers(start);
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

// Inside a face: both ways along Π; on an edge: into both faces it borders; at a vertex: into
// every face of its fan. Each walker's points start with `start`.
std::vector<Walker> Tearer::start_walkers(const PathPoint& start) const {
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
  return walkers;
}

void Tearer::advance(Walker& w, const PathPoint& target, const StepPlane& plane, int start_face) const {
  if (w.face == target.face) {
    arrive(w, target);
    return;
  }
  if (w.steps > 0 && w.face == start_face) {  // went round a closed section without meeting the target
    w.failed = true;
    return;
  }
  std::optional<PathPoint> exit = next_exit(w, plane);
  if (!exit) {
    w.failed = true;
    return;
  }
  exit->segment_face = w.face;
  exit->step = target.step;
  const Eigen::Vector3d from = w.points.empty() ? exit->x : w.points.back().x;
  w.length += (exit->x - from).norm();
  w.points.push_back(*exit);
  if (near(exit->x, target.x)) {
    w.done = true;
    return;
  }
  cross(w, *exit, from, plane);
}

void Tearer::arrive(Walker& w, const PathPoint& target) const {
  PathPoint t = target;
  t.segment_face = w.face;
  if (w.points.size() > 1 && near(w.points.back().x, t.x)) w.points.pop_back();
  w.points.push_back(t);
  w.done = true;
}

// Not back where it entered; at the start inside a face, the crossing `forced` names. No way on
// either when the walk has gone through more faces than the mesh has.
std::optional<PathPoint> Tearer::next_exit(Walker& w, const StepPlane& plane) const {
  std::vector<PathPoint> exits = crossings(w.face, plane);
  std::erase_if(exits, [&](const PathPoint& x) { return x.feature() == w.entry; });
  if (w.forced >= 0) {
    if (w.forced >= static_cast<int>(exits.size())) return std::nullopt;
    exits = {exits[static_cast<std::size_t>(w.forced)]};
    w.forced = -1;
  }
  if (exits.empty() || ++w.steps > static_cast<int>(mesh_.face_count())) return std::nullopt;
  return exits.front();
}

// Its corners on Π and the crossings of its edges whose ends lie strictly on opposite sides,
// at t = (A·Π) / (A·Π − B·Π).
std::vector<PathPoint> Tearer::crossings(int f, const StepPlane& p) const {
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

// `from` is the point before the exit; the walker fails where the section leaves the surface.
void Tearer::cross(Walker& w, const PathPoint& exit, const Eigen::Vector3d& from, const StepPlane& plane) const {
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

// Coming from `previous` to the vertex at corner k of face f: the face of the vertex's fan
// where Π leaves the vertex most nearly straight on, and the vertex's corner in it.
std::pair<int, int> Tearer::continue_at_vertex(int f, int k, const Eigen::Vector3d& previous,
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

// In b's segment face.
PathPoint Tearer::midpoint(const PathPoint& a, const PathPoint& b) const {
  const int f = b.segment_face;
  const std::array<double, 3> x = bary_in(a, f), y = bary_in(b, f);
  PathPoint m = snapped(f, Eigen::Vector3d(0.5 * (x[0] + y[0]), 0.5 * (x[1] + y[1]), 0.5 * (x[2] + y[2])));
  m.segment_face = f;
  m.step = b.step;
  return m;
}

// ---- prepare() ----------------------------------------------------------------------------------

void Tearer::retriangulate(const std::vector<PathPoint>& path) {
  for (const auto& [f, work] : faces_crossed(path)) split_face(path, f, work);
}

std::vector<std::pair<int, FaceWork>> Tearer::faces_crossed(const std::vector<PathPoint>& path) const {
  std::vector<std::pair<int, FaceWork>> out;
  std::unordered_map<int, std::size_t> slot;
  const auto touch = [&](int f) -> FaceWork& {
    const auto [it, added] = slot.try_emplace(f, out.size());
    if (added) out.emplace_back(f, FaceWork{});
    return out[it->second].second;
  };
  const auto add_point = [&](int f, int i) {
    FaceWork& w = touch(f);
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
  return out;
}

void Tearer::split_face(const std::vector<PathPoint>& path, int f, const FaceWork& work) {
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
  for (const int i : work.points) local_of(i);
  std::vector<std::array<int, 2>> segments;
  for (const auto& s : work.segments) segments.push_back({local_of(s[0]), local_of(s[1])});
  std::vector<Triangle> tris;
  try {
    tris = triangulate_constrained(pts, segments);
  } catch (const TopologyError&) {
    throw TopologyError("tear: the tear path crosses itself in face " + std::to_string(f) + " of mesh '" + mesh_.name +
                        "'");
  }
  edit_.remove_face(f);
  for (const Triangle& t : tris)
    edit_.add_face_in(
        {ids[static_cast<std::size_t>(t[0])], ids[static_cast<std::size_t>(t[1])], ids[static_cast<std::size_t>(t[2])]},
        f);
}

// The faces on either side of the path (connected around a vertex through edges that are not
// on the path) get their own copy of it.
void Tearer::duplicate(const std::vector<PathPoint>& path) {
  const int n = static_cast<int>(path.size());
  const PathEdges on_path = path_edges(path);
  free_fans(path);
  std::unordered_map<long long, std::vector<int>> faces_at = faces_by_key();
  copies_.assign(static_cast<std::size_t>(n), {});
  for (int i = 1; i + 1 < n; ++i) {
    const auto found = faces_at.find(point_key(path, i));
    if (found != faces_at.end()) split_point(path, i, found->second, on_path);
  }
}

Tearer::PathEdges Tearer::path_edges(const std::vector<PathPoint>& path) const {
  PathEdges out;
  for (int i = 1; i < static_cast<int>(path.size()); ++i)
    out.insert(std::minmax(point_key(path, i - 1), point_key(path, i)));
  return out;
}

// Those of the inner path points only: the two ends are not split.
void Tearer::free_fans(const std::vector<PathPoint>& path) {
  const int n = static_cast<int>(path.size());
  std::unordered_set<int> removed(edit_.removed_faces().begin(), edit_.removed_faces().end());
  for (int i = 1; i + 1 < n; ++i) {
    const PathPoint& p = path[static_cast<std::size_t>(i)];
    if (p.kind != PathPoint::Kind::vertex) continue;
    for (const int g : fan(p.face, p.corner)) {
      if (!removed.insert(g).second) continue;
      edit_.remove_face(g);
      edit_.add_face_in({corner(g, 0), corner(g, 1), corner(g, 2)}, g);
    }
  }
}

std::unordered_map<long long, std::vector<int>> Tearer::faces_by_key() const {
  std::unordered_map<long long, std::vector<int>> out;
  for (int t = 0; t < static_cast<int>(edit_.new_faces().size()); ++t)
    for (const int x : edit_.new_faces()[static_cast<std::size_t>(t)]) out[key(x)].push_back(t);
  return out;
}

// `faces` is left sorted, each face once. A point whose faces all form one group stays whole.
void Tearer::split_point(const std::vector<PathPoint>& path, int i, std::vector<int>& faces, const PathEdges& on_path) {
  const long long k = point_key(path, i);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  const std::vector<int> group = side_groups(k, faces, on_path);
  const int groups = *std::max_element(group.begin(), group.end()) + 1;
  if (groups < 2) return;
  const StepPlane& plane = planes_[static_cast<std::size_t>(path[static_cast<std::size_t>(i)].step)];
  const std::vector<int> sign = side_signs(plane, k, faces, group, groups);
  for (const auto& [gx, x] : copy_for_groups(i, k, faces, group, sign)) {
    copies_[static_cast<std::size_t>(i)].push_back({x, sign[static_cast<std::size_t>(gx.first)]});
    if (options_.own_side_influences && x >= nv_) {
      const auto k = static_cast<std::size_t>(x - nv_);
      edit_.set_source(
          k, restricted_influences(edit_.new_vertices()[k].source, plane, sign[static_cast<std::size_t>(gx.first)]));
    }
  }
}

// Union-find over the faces around the point, joined across edges off the path.
std::vector<int> Tearer::side_groups(long long k, const std::vector<int>& faces, const PathEdges& on_path) const {
  UnionFind sets(faces.size());
  std::unordered_map<long long, int> across;  // other end of an edge at the point -> a face
  for (std::size_t a = 0; a < faces.size(); ++a) {
    const Triangle& t = edit_.new_faces()[static_cast<std::size_t>(faces[a])];
    for (const int x : t) {
      const long long o = key(x);
      if (o == k || on_path.contains(std::minmax(k, o))) continue;
      const auto [it, added] = across.try_emplace(o, static_cast<int>(a));
      if (!added) sets.unite(static_cast<int>(a), it->second);
    }
  }
  std::map<int, int> group_of_root;
  std::vector<int> group(faces.size());
  for (std::size_t a = 0; a < faces.size(); ++a)
    group[a] =
        group_of_root.try_emplace(sets.find(static_cast<int>(a)), static_cast<int>(group_of_root.size())).first->second;
  return group;
}

// Where each group's faces' other vertices lie relative to Π, summed; a group on Π takes +1 if
// it is the first, else −1, and two groups always get opposite sides.
std::vector<int> Tearer::side_signs(const StepPlane& plane, long long k, const std::vector<int>& faces,
                                    const std::vector<int>& group, int groups) const {
  std::vector<double> side(static_cast<std::size_t>(groups), 0.0);
  for (std::size_t a = 0; a < faces.size(); ++a)
    for (const int x : edit_.new_faces()[static_cast<std::size_t>(faces[a])])
      if (key(x) != k) side[static_cast<std::size_t>(group[a])] += signed_offset(plane, x);
  std::vector<int> sign(side.size());
  for (std::size_t g = 0; g < side.size(); ++g) sign[g] = side[g] > 0 ? 1 : side[g] < 0 ? -1 : (g == 0 ? 1 : -1);
  if (sign.size() == 2 && sign[0] == sign[1]) sign[1] = -sign[0];
  return sign;
}

// Keyed by (group, extended id). A vertex the faces of one group alone use (a seam copy, or a
// mesh without shared vertices) is that group's already: only one that several groups share is
// copied, and the first of those groups keeps the original.
std::map<std::pair<int, int>, int> Tearer::copy_for_groups(int i, long long k, const std::vector<int>& faces,
                                                           const std::vector<int>& group,
                                                           const std::vector<int>& sign) {
  std::map<int, std::set<int>> groups_of;  // extended id -> the groups using it
  for (std::size_t a = 0; a < faces.size(); ++a)
    for (const int x : edit_.new_faces()[static_cast<std::size_t>(faces[a])])
      if (key(x) == k) groups_of[x].insert(group[a]);
  std::map<std::pair<int, int>, int> copy_of;
  for (std::size_t a = 0; a < faces.size(); ++a) {
    const int g = group[a];
    const auto face = static_cast<std::size_t>(faces[a]);
    for (std::size_t c = 0; c < 3; ++c) {
      const int x = edit_.new_faces()[face][c];
      if (key(x) != k) continue;
      const auto [it, added] = copy_of.try_emplace({g, x}, x);
      const std::set<int>& users = groups_of[x];
      if (added && users.size() > 1 && g != *users.begin()) {
        const VertexSource s =
            x < nv_ ? VertexSource::copy(x) : edit_.new_vertices()[static_cast<std::size_t>(x - nv_)].source;
        const Eigen::Vector3d y = x < nv_ ? placed_.row(x).cast<double>().transpose()
                                          : edit_.new_vertices()[static_cast<std::size_t>(x - nv_)].placed;
        it->second = edit_.add_vertex(
            {.source = s, .placed = y, .side = static_cast<signed char>(sign[static_cast<std::size_t>(g)])}, nv_);
        point_of_new_.push_back(i);
      }
      edit_.set_corner(face, c, it->second);
    }
  }
  return copy_of;
}

// ---- move_apart() -------------------------------------------------------------------------------

void Tearer::move_vertex(mesh::Mesh& m, RowMatrixXf<3>& placed, int v, const Eigen::Vector3d& shift) const {
  placed.row(v) += shift.cast<float>().transpose();
  // A blend of joints that collapses space has no rest-space direction for the shift.
  if (const auto rest = unskin(anim::blended_affine(m, palette_, v).leftCols<3>(), shift))
    m.positions.row(v) += rest->cast<float>().transpose();
}

// ---- geometry -----------------------------------------------------------------------------------

// Seam copies use their welded representative, so both sides of a seam see the same point and
// make the same decisions.
Eigen::Vector3d Tearer::position(int v) const { return placed_.row(weld(v)).cast<double>().transpose(); }

Eigen::Vector3d Tearer::at(int f, const std::array<double, 3>& b) const {
  return b[0] * position(corner(f, 0)) + b[1] * position(corner(f, 1)) + b[2] * position(corner(f, 2));
}

PathPoint Tearer::snapped(int f, const Eigen::Vector3d& bary) const {
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

PathPoint Tearer::vertex_point(int f, int k) const {
  PathPoint p;
  p.kind = PathPoint::Kind::vertex;
  p.face = f;
  p.corner = k;
  p.bary[static_cast<std::size_t>(k)] = 1;
  p.x = position(corner(f, k));
  return p;
}

PathPoint Tearer::edge_point(int f, int k, double t) const {
  PathPoint p;
  p.kind = PathPoint::Kind::edge;
  p.face = f;
  p.corner = k;
  p.bary[static_cast<std::size_t>(k)] = 1 - t;
  p.bary[static_cast<std::size_t>((k + 1) % 3)] = t;
  p.x = at(f, p.bary);
  return p;
}

// X·Π (cga) or n·x − d.
double Tearer::distance(const StepPlane& p, int v) const {
  const Eigen::Vector3d x = position(v);
  const double s =
      options_.predicates == Predicates::cga ? cga::scalar_product(cga::up<double>(x), p.pi) : p.n.dot(x) - p.d;
  return std::abs(s) <= tol_ ? 0.0 : s;
}

double Tearer::signed_offset(const StepPlane& plane, int x) const {
  const Eigen::Vector3d y = x < nv_ ? position(x) : edit_.new_vertices()[static_cast<std::size_t>(x - nv_)].placed;
  return plane.n.dot(y) - plane.d;
}

int Tearer::corner_of(int f, int welded) const {
  for (int k = 0; k < 3; ++k)
    if (weld(corner(f, k)) == welded) return k;
  return -1;
}

// Rotating across the edges leaving the vertex, then (at an open border) across the edges
// arriving at it.
std::vector<int> Tearer::fan(int f, int k) const {
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

std::array<double, 3> Tearer::bary_in(const PathPoint& p, int g) const {
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

// b₀ = 0 gives a point whose coordinates sum to 1 exactly, so CGAL sees it on the edge and
// makes no sliver.
Eigen::Vector2d Tearer::plane_coordinates(const std::array<double, 3>& b) {
  if (b[0] == 0) {
    const double v = b[2] >= 0.5 ? b[2] : 1 - b[1];
    return {1 - v, v};
  }
  return {b[1], b[2]};
}

// ---- vertices of the edit -----------------------------------------------------------------------

int Tearer::vertex_in(const std::vector<PathPoint>& path, int i, int f) {
  const PathPoint& p = path[static_cast<std::size_t>(i)];
  if (p.kind == PathPoint::Kind::vertex) return corner(f, corner_of(f, weld(corner(p.face, p.corner))));
  return new_vertex(p, i, f);
}

// Seam copies stay apart: the key holds the face's own vertex indices.
int Tearer::new_vertex(const PathPoint& p, int i, int f) {
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
    s = VertexSource::face(corner(f, 0), corner(f, 1), corner(f, 2), static_cast<float>(b[0]), static_cast<float>(b[1]),
                           static_cast<float>(b[2]));
  }
  const auto [it, added] = vertex_of_point_.try_emplace(key, -1);
  if (added) {
    it->second = edit_.add_vertex({.source = s, .placed = p.x}, nv_);
    point_of_new_.push_back(i);
  }
  return it->second;
}

long long Tearer::key(int x) const {
  return x < nv_ ? weld(x) : -1 - static_cast<long long>(point_of_new_[static_cast<std::size_t>(x - nv_)]);
}

long long Tearer::point_key(const std::vector<PathPoint>& path, int i) const {
  const PathPoint& p = path[static_cast<std::size_t>(i)];
  return p.kind == PathPoint::Kind::vertex ? weld(corner(p.face, p.corner)) : -1 - static_cast<long long>(i);
}

VertexSource Tearer::restricted_influences(VertexSource s, const StepPlane& plane, int sign) const {
  std::uint8_t mask = 0;
  for (int k = 0; k < s.count(); ++k)
    if (distance(plane, s.vertex[static_cast<std::size_t>(k)]) * sign > 0) mask |= static_cast<std::uint8_t>(1u << k);
  if (mask != 0) s.influence_mask = mask;
  return s;
}

}  // namespace cgamesh::surgery::detail
