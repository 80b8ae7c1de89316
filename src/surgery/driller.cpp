#include "driller.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/errors.hpp"

#include "convex_triangulation.hpp"
#include "polygon_triangulation.hpp"

namespace cgamesh::surgery::detail {
namespace {

using mesh::VertexSource;

/// Signed angle from u to v about n, in (−π, π].
double angle_about(const Eigen::Vector3d& n, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(n.dot(u.cross(v)), u.dot(v));
}

void require_finite(const Eigen::Vector3d& p, const char* what) {
  if (!p.allFinite()) throw InvalidInputError(std::string("drill: the ") + what + " is not finite");
}

}  // namespace

Cylinder make_cylinder(const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius,
                       const DrillOptions& options) {
  require_finite(tip, "tip");
  require_finite(base, "base");
  if (!(radius > 0) || !std::isfinite(radius)) throw InvalidInputError("drill: the radius must be a finite number > 0");
  if (!((tip - base).norm() > 0)) throw InvalidInputError("drill: the tip and the base are the same point");
  if (options.min_rim_points < 3 || options.min_rim_points > kMaxRimPoints)
    throw InvalidInputError("drill: min_rim_points must be in [3, " + std::to_string(kMaxRimPoints) + "], got " +
                            std::to_string(options.min_rim_points));
  if (options.max_refinements < 0 || options.max_refinements > kMaxRefinements)
    throw InvalidInputError("drill: max_refinements must be in [0, " + std::to_string(kMaxRefinements) + "], got " +
                            std::to_string(options.max_refinements));
  if (options.max_region_faces < 1)
    throw InvalidInputError("drill: max_region_faces must be >= 1, got " + std::to_string(options.max_region_faces));
  if (!(options.snap >= 0) || !std::isfinite(options.snap)) throw InvalidInputError("drill: snap must be >= 0");
  Cylinder c;
  c.base = base;
  c.axis = (tip - base).normalized();
  c.length = (tip - base).norm();
  c.radius = radius;
  c.sphere = cga::make_vector<double>(0, 0, 0, -0.5 * radius * radius, 1);
  c.plane = cga::make_vector<double>(c.axis.x(), c.axis.y(), c.axis.z(), 0, 0);
  c.predicates = options.predicates;
  c.e1 = any_perpendicular(c.axis);
  c.e2 = c.axis.cross(c.e1);
  return c;
}

Driller::Driller(const mesh::Mesh& mesh, const mesh::RowMatrixXf<3>& placed, const MeshIndex& index,
                 const Cylinder& cylinder, const DrillOptions& options)
    : mesh_(mesh),
      placed_(placed),
      index_(index),
      c_(cylinder),
      options_(options),
      nv_(static_cast<int>(mesh.vertex_count())),
      next_weld_(nv_) {
  tolerance_ = options.snap * index.bvh.diagonal();
  s_tolerance_ = tolerance_ * (2 * c_.radius + tolerance_);
}

void Driller::run(const std::vector<int>& candidates, LocalEdit& edit, DrillStats& out) {
  reserve_region(candidates.size());
  Pass pass = analyse(slots_of(candidates));
  if (pass.affected.empty()) return;
  std::vector<Rim> rims = find_rims(pass);
  const Refinement refinement = refine_while_coarse(pass, rims);
  const std::string name = "mesh '" + mesh_.name + "'";
  warn_if_coarse(pass, rims, refinement, name, out.warnings);
  Walls walls;
  if (options_.wall) walls = wall(pass, rims, name, out);
  emit(pass, walls, edit, out);
  out.refinements += refinement.rounds;
  out.faces_affected += static_cast<int>(pass.affected.size());
  out.wall_triangles += walls.size();
  out.rims += static_cast<int>(rims.size());
}

// ---- the steps of run ----

/// Room for the region of `candidates` faces, so that its maps are not rehashed while it is
/// pulled in (on a million-face mesh, growing them was a fifth of the drill). The search adds a
/// ring of neighbours; a mesh has about half as many vertices and 3/2 as many edges as faces,
/// the intersection points and the region's border more.
void Driller::reserve_region(std::size_t candidates) {
  const std::size_t faces = candidates + candidates / 4 + 64;
  faces_.reserve(faces);
  vertices_.reserve(faces);
  local_of_old_.reserve(faces * 2 / 3);
  slot_of_old_.reserve(faces);
  half_edges_.reserve(3 * faces);
  cuts_.reserve(2 * faces);
  cut_of_edge_.reserve(2 * faces);
  crossing_of_edge_.reserve(faces / 4);
}

std::vector<int> Driller::slots_of(const std::vector<int>& faces) {
  std::vector<int> slots;
  slots.reserve(faces.size());
  for (const int f : faces) slots.push_back(slot_of(f));
  return slots;
}

/// Step 2 is the search; steps 3 and 5 keep what is left of each face the drill meets.
Pass Driller::analyse(const std::vector<int>& seeds) {
  Pass pass;
  pass.affected = search(seeds);
  for (int s : pass.affected) keep(s, pass);
  return pass;
}

std::vector<Rim> Driller::find_rims(const Pass& pass) const {
  // Welded id -> the first chord leaving it and whether a second one does (a pinch).
  FlatMap<std::pair<int, bool>> from;
  FlatMap<int> to;  // welded id -> the first chord arriving
  from.reserve(pass.chords.size());
  to.reserve(pass.chords.size());
  for (std::size_t c = 0; c < pass.chords.size(); ++c) {
    const auto [leaving, added] =
        from.try_emplace(static_cast<std::uint64_t>(weld(pass.chords[c].p)), {static_cast<int>(c), false});
    if (!added) leaving->second = true;
    to.try_emplace(static_cast<std::uint64_t>(weld(pass.chords[c].e)), static_cast<int>(c));
  }
  std::vector<char> used(pass.chords.size(), 0);
  std::vector<Rim> rims;
  for (std::size_t c0 = 0; c0 < pass.chords.size(); ++c0) {
    if (used[c0] != 0) continue;
    // Back to the start of a chain (or once around a loop).
    auto start = static_cast<int>(c0);
    for (std::size_t steps = 0; steps < pass.chords.size(); ++steps) {
      const int* arriving = to.find(static_cast<std::uint64_t>(weld(pass.chords[static_cast<std::size_t>(start)].p)));
      if (arriving == nullptr || used[static_cast<std::size_t>(*arriving)] != 0 || *arriving == static_cast<int>(c0))
        break;
      start = *arriving;
    }
    Rim rim;
    for (int c = start;;) {
      used[static_cast<std::size_t>(c)] = 1;
      rim.chords.push_back(c);
      const auto* leaving = from.find(static_cast<std::uint64_t>(weld(pass.chords[static_cast<std::size_t>(c)].e)));
      if (leaving == nullptr) break;
      if (leaving->first == start) {
        rim.closed =
            !from.find(static_cast<std::uint64_t>(weld(pass.chords[static_cast<std::size_t>(start)].p)))->second;
        break;
      }
      if (used[static_cast<std::size_t>(leaving->first)] != 0) break;
      c = leaving->first;
    }
    rims.push_back(std::move(rim));
  }
  return rims;
}

Refinement Driller::refine_while_coarse(Pass& pass, std::vector<Rim>& rims) {
  Refinement done;
  while (too_coarse(pass, rims) && done.rounds < options_.max_refinements) {
    // Only the faces the rim crosses are split: those wholly inside go anyway. A round splits
    // each 1 -> 4 and some neighbours 1 -> 2.
    const std::vector<int> red = rim_faces(pass);
    if (faces_.size() + 6 * red.size() > static_cast<std::size_t>(options_.max_region_faces)) {
      done.over_budget = true;
      break;
    }
    refine(red);
    ++done.rounds;
    pass = analyse(alive_faces());
    rims = find_rims(pass);
  }
  return done;
}

void Driller::warn_if_coarse(const Pass& pass, const std::vector<Rim>& rims, const Refinement& refinement,
                             const std::string& name, std::vector<std::string>& warnings) const {
  if (refinement.over_budget)
    warnings.push_back(name + ": refinement stopped after " + std::to_string(refinement.rounds) +
                       " rounds: another would take the drilled region past max_region_faces = " +
                       std::to_string(options_.max_region_faces));
  if (pass.disks_inside > 0)
    warnings.push_back(name + ": the drill lies inside a face even after " + std::to_string(refinement.rounds) +
                       " refinements; no hole there");
  else if (too_coarse(pass, rims))
    warnings.push_back(name + ": a rim of the hole is still coarse (fewer than " +
                       std::to_string(options_.min_rim_points) + " points, or a chord over a long arc) after " +
                       std::to_string(refinement.rounds) + " refinements");
}

/// Stitches each entry rim to the exit rim that follows it along the axis with a tube (see
/// zipper) where no surface lies between them, and walls a last entry rim on the drill's boundary
/// up to the tip as a blind hole where the material goes on past the tip. A tube anywhere else
/// would leave the body (through a sheet, out of a back the drill did not reach).
Walls Driller::wall(const Pass& pass, const std::vector<Rim>& rims, const std::string& name, DrillStats& out) {
  std::vector<OpenRim> open;
  const std::vector<Loop> loops = closed_loops(pass, rims, open);
  const std::vector<AxisHit> hits = loops.empty() ? std::vector<AxisHit>{} : axis_hits();
  Walls walls;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const Loop& a = loops[i];
    std::string reason;
    if (a.winding < 0) {
      reason =
          "an exit with no entry before it along the drill (the base's disk cuts the surface, or the surfaces "
          "face alike)";
    } else if (i + 1 < loops.size() && loops[i + 1].winding < 0) {
      reason = between(hits, a, loops[i + 1]);
      if (reason.empty()) {
        zipper(a.points, loops[i + 1].points, walls.tube);
        ++out.walls;
        ++i;
        continue;
      }
    } else if (i + 1 < loops.size()) {
      reason = "another entry follows it along the drill";
    } else if (!on_boundary_to_tip(a)) {
      reason = "no exit follows it along the drill";
    } else {
      reason = blind_reason(hits, a);
      if (reason.empty() && !blind(a.points, walls)) reason = "the rim crosses itself seen along the drill";
      if (reason.empty()) {
        ++out.walls;
        continue;
      }
    }
    open.push_back({a.points, reason});
  }
  out.open_rims += static_cast<int>(open.size());
  for (const OpenRim& rim : open) out.warnings.push_back(name + ": " + describe(rim) + " left open: " + rim.reason);
  return walls;
}

void Driller::emit(const Pass& pass, const Walls& walls, LocalEdit& edit, DrillStats& out) const {
  const std::vector<char> affected = remove_changed_faces(pass, edit);
  std::vector<int> ids(vertices_.size(), -1);
  reserve_output(pass, walls, edit);
  emit_split_faces(affected, edit, ids);
  emit_kept_polygons(pass, edit, ids);
  emit_walls(walls, edit);
  for (std::size_t x = 0; x < ids.size(); ++x) out.intersection_points += ids[x] >= 0 && vertices_[x].crossing ? 1 : 0;
}

// ---- analyse ----

std::vector<int> Driller::search(const std::vector<int>& seeds) {
  ++pass_;
  std::vector<int> affected;
  std::vector<int> queue;
  for (int s : seeds) {
    Face& f = faces_[static_cast<std::size_t>(s)];
    if (f.alive && f.visited != pass_ && (f.visited = pass_, meets(s))) queue.push_back(s);
  }
  while (!queue.empty()) {
    const int s = queue.back();
    queue.pop_back();
    affected.push_back(s);
    for (int k = 0; k < 3; ++k) {
      const int g = neighbor(s, k);
      if (g < 0) continue;
      Face& f = faces_[static_cast<std::size_t>(g)];
      if (f.visited == pass_) continue;
      f.visited = pass_;
      if (meets(g)) queue.push_back(g);
    }
  }
  return affected;
}

bool Driller::meets(int slot) {
  for (int k = 0; k < 3; ++k)
    if (cut_of(slot, k).any_inside) return true;
  return axis_through(faces_[static_cast<std::size_t>(slot)]);
}

/// Whether the axis segment [B, A] passes through face f (a disk lying inside the face meets no
/// edge of it).
bool Driller::axis_through(const Face& f) const {
  std::array<Eigen::Vector3d, 3> d;
  for (std::size_t k = 0; k < 3; ++k) {
    const Vertex& v = vertex(f.v[k]);
    d[k] = v.placed - c_.base - v.h * c_.axis;
  }
  const double o0 = c_.axis.dot(d[0].cross(d[1])), o1 = c_.axis.dot(d[1].cross(d[2])),
               o2 = c_.axis.dot(d[2].cross(d[0]));
  if (!((o0 > 0 && o1 > 0 && o2 > 0) || (o0 < 0 && o1 < 0 && o2 < 0))) return false;
  // ... between the end disks (the projection is not degenerate, so the face is not parallel
  // to the axis).
  const Eigen::Vector3d p0 = vertex(f.v[0]).placed, n = (vertex(f.v[1]).placed - p0).cross(vertex(f.v[2]).placed - p0);
  const double h = n.dot(p0 - c_.base) / n.dot(c_.axis);
  return h > 0 && h < c_.length;
}

/// Walking the boundary of the face, each run outside the drill from the point where it leaves
/// the circle to where it enters it again, closed by the chord back, is a convex polygon (a
/// triangle minus a convex disk).
void Driller::keep(int slot, Pass& pass) {
  const Triangle corners = faces_[static_cast<std::size_t>(slot)].v;
  const FaceBoundary b = boundary(slot);
  const int m = b.size;
  const auto first = static_cast<int>(std::find(b.inside.begin(), b.inside.begin() + m, true) - b.inside.begin());
  if (first == m) {  // nothing of the boundary is inside: the disk lies inside the face
    ++pass.disks_inside;
    add_polygon(pass, slot, corners);
    return;
  }
  std::array<int, 15> run{};
  for (int i = 0; i < m; ++i) {
    const int at = (first + i) % m, before = (at + m - 1) % m;
    if (!(b.inside[static_cast<std::size_t>(before)] && !b.inside[static_cast<std::size_t>(at)])) continue;
    int n = 0;
    for (int j = at;; j = (j + 1) % m) {
      run[static_cast<std::size_t>(n++)] = b.point[static_cast<std::size_t>(j)];
      if (b.inside[static_cast<std::size_t>(j)]) break;
    }
    if (n < 3) continue;  // a chord along an edge: nothing kept
    keep_run(slot, {run.data(), static_cast<std::size_t>(n)}, pass);
  }
}

FaceBoundary Driller::boundary(int slot) {
  const Triangle v = faces_[static_cast<std::size_t>(slot)].v;
  FaceBoundary b;
  int& m = b.size;
  for (int k = 0; k < 3; ++k) {
    const int from = v[static_cast<std::size_t>(k)], to = v[static_cast<std::size_t>((k + 1) % 3)];
    const EdgeCut e = cut_of(slot, k);
    const bool forward = canonical(from, to).first == from;
    b.point[static_cast<std::size_t>(m)] = from;
    for (int r = 0; r <= e.roots; ++r) {
      const int j = forward ? r : e.roots - r;  // sub-segment in canonical order
      b.inside[static_cast<std::size_t>(m)] = e.inside[static_cast<std::size_t>(j)];
      if (r < e.roots) b.point[static_cast<std::size_t>(++m)] = crossing(from, to, e, forward ? r : e.roots - 1 - r);
    }
    ++m;
  }
  return b;
}

/// `run` goes from where the boundary leaves the drill to where it enters it again; the chord
/// back closes it.
void Driller::keep_run(int slot, std::span<const int> run, Pass& pass) {
  add_polygon(pass, slot, run);
  const Chord chord{run.back(), run.front()};
  pass.chords.push_back(chord);
  // Only a chord between two points of the cylinder replaces an arc of it; one with an end in an
  // end disk's plane follows the line that plane cuts from the face.
  const bool on_cylinder = vertex(chord.p).s == 0 && vertex(chord.e).s == 0;
  if (on_cylinder && arc(chord, run) > 4 * std::numbers::pi / options_.min_rim_points) ++pass.coarse_arcs;
}

void Driller::add_polygon(Pass& pass, int slot, std::span<const int> corners) {
  pass.polygons.push_back({slot, static_cast<int>(pass.corners.size()), static_cast<int>(corners.size())});
  pass.corners.insert(pass.corners.end(), corners.begin(), corners.end());
}

/// The arc of the circle a chord replaces: on the far side of the chord from its polygon.
double Driller::arc(const Chord& chord, std::span<const int> polygon) const {
  const Eigen::Vector3d p = projected(chord.p), e = projected(chord.e);
  const double phi = std::abs(angle_about(c_.axis, p, e));
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int x : polygon) centroid += projected(x);
  centroid /= static_cast<double>(polygon.size());
  const double axis_side = c_.axis.dot((e - p).cross(-p)), polygon_side = c_.axis.dot((e - p).cross(centroid - p));
  return axis_side * polygon_side > 0 ? 2 * std::numbers::pi - phi : phi;
}

// ---- the cylinder against an edge ----

/// The points are the roots of the quadratic (the point (1 − α) a + α b is on the cylinder
/// exactly, projection being affine) and the crossings of the end disks' planes; each part of
/// the edge between them is in the drill or not.
int Driller::edge_cut(int x, int y) {
  const auto [a, b] = canonical(x, y);
  const std::uint64_t key = edge_key(weld(a), weld(b));
  if (const int* known = cut_of_edge_.find(key)) return *known;
  const Vertex &va = vertex(a), &vb = vertex(b);
  const EdgeQuadratic f = quadratic(va, vb);
  const double edge_length = (vb.placed - va.placed).norm();
  EdgeCut e;
  cylinder_roots(va, vb, f, e);
  plane_crossings(va, vb, edge_length, e);
  merge_points(edge_length, e);
  for (int k = 0; k < e.roots; ++k) e.weld[static_cast<std::size_t>(k)] = next_weld_++;
  classify(va, vb, f, e);
  drop_non_bounding(e);
  cut_of_edge_.try_emplace(key, static_cast<int>(cuts_.size()));
  cuts_.push_back(e);
  return static_cast<int>(cuts_.size()) - 1;
}

EdgeQuadratic Driller::quadratic(const Vertex& a, const Vertex& b) const {
  const double K = projected_length2(a, b);
  return {K, b.s - a.s - K, a.s};
}

void Driller::cylinder_roots(const Vertex& a, const Vertex& b, const EdgeQuadratic& f, EdgeCut& e) const {
  const double sa = a.s, sb = b.s, length = std::sqrt(f.K), disc = f.discriminant(), q = f.q();
  std::array<double, 2> t{f.K > 0 ? q / f.K : HUGE_VAL, q != 0 ? f.N / q : HUGE_VAL};
  if (t[0] > t[1]) std::swap(t[0], t[1]);
  if ((sa < 0) != (sb < 0) && sa != 0 && sb != 0) {
    // One end inside, one outside: exactly one root in (0, 1), the one nearer to it.
    const auto off = [](double r) { return std::max(-r, r - 1); };
    e.alpha[0] = std::clamp(off(t[0]) < off(t[1]) ? t[0] : t[1], 0.0, 1.0);
    e.roots = 1;
  } else if (sa >= 0 && sb >= 0 && disc > 0 && (t[1] - t[0]) * length > tolerance_) {
    // Both ends outside or on: two roots, one (an end on the cylinder), or a touch (a double
    // root: no hole). Roots within the tolerance of an end or of each other are dropped.
    for (double r : t)
      if (r * length > tolerance_ && (1 - r) * length > tolerance_) e.alpha[static_cast<std::size_t>(e.roots++)] = r;
  }
}

/// The planes h = 0 and h = |AB| (h is affine along the edge): the drill is finite and takes
/// only what lies between them.
void Driller::plane_crossings(const Vertex& a, const Vertex& b, double edge_length, EdgeCut& e) const {
  const double ha = a.h, hb = b.h;
  for (const double level : {0.0, c_.length})
    if ((ha - level) * (hb - level) < 0) {
      const double r = (ha - level) / (ha - hb);
      if (r * edge_length > tolerance_ && (1 - r) * edge_length > tolerance_) {
        e.level[static_cast<std::size_t>(e.roots)] = level;
        e.alpha[static_cast<std::size_t>(e.roots++)] = r;
      }
    }
}

void Driller::merge_points(double edge_length, EdgeCut& e) const {
  for (int k = 1; k < e.roots; ++k)  // insertion sort of at most four
    for (int j = k; j > 0 && e.alpha[static_cast<std::size_t>(j)] < e.alpha[static_cast<std::size_t>(j - 1)]; --j) {
      std::swap(e.alpha[static_cast<std::size_t>(j)], e.alpha[static_cast<std::size_t>(j - 1)]);
      std::swap(e.level[static_cast<std::size_t>(j)], e.level[static_cast<std::size_t>(j - 1)]);
    }
  int distinct = 0;
  for (int k = 0; k < e.roots; ++k)
    if (distinct == 0 ||
        (e.alpha[static_cast<std::size_t>(k)] - e.alpha[static_cast<std::size_t>(distinct - 1)]) * edge_length >
            tolerance_) {
      e.level[static_cast<std::size_t>(distinct)] = e.level[static_cast<std::size_t>(k)];
      e.alpha[static_cast<std::size_t>(distinct++)] = e.alpha[static_cast<std::size_t>(k)];
    }
  e.roots = distinct;
}

/// A sub-segment is inside the cylinder when an end is strictly inside, or between two points on
/// it (a chord) when the middle is deeper than the tolerance; and it must lie between the end disks.
void Driller::classify(const Vertex& a, const Vertex& b, const EdgeQuadratic& f, EdgeCut& e) const {
  std::array<double, 6> at{}, sv{};  // the edge's ends and its points, and ρ² − r² there
  sv[0] = a.s;
  for (int k = 0; k < e.roots; ++k) {
    const auto i = static_cast<std::size_t>(k + 1);
    at[i] = e.alpha[static_cast<std::size_t>(k)];
    const double v = f(at[i]);
    sv[i] = std::abs(v) <= s_tolerance_ ? 0.0 : v;
  }
  at[static_cast<std::size_t>(e.roots + 1)] = 1;
  sv[static_cast<std::size_t>(e.roots + 1)] = b.s;
  for (std::size_t k = 0; k <= static_cast<std::size_t>(e.roots); ++k) {
    const double mid = 0.5 * (at[k] + at[k + 1]), h = (1 - mid) * a.h + mid * b.h;
    const bool radial = sv[k] < 0 || sv[k + 1] < 0 || (sv[k] == 0 && sv[k + 1] == 0 && f(mid) < -s_tolerance_);
    const bool in = radial && h > 0 && h < c_.length;
    e.inside[k] = in;
    e.any_inside = e.any_inside || in;
  }
}

/// Such a point (an end disk's plane crossed beside the cylinder) bounds nothing: it goes, or the
/// face across the edge, not affected, would get a T-junction.
void Driller::drop_non_bounding(EdgeCut& e) {
  int bounding = 0;
  for (int k = 0; k < e.roots; ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (!e.inside[i] && !e.inside[i + 1]) continue;
    const auto j = static_cast<std::size_t>(bounding++);
    e.alpha[j] = e.alpha[i];
    e.level[j] = e.level[i];
    e.weld[j] = e.weld[i];
    e.inside[j + 1] = e.inside[i + 1];
  }
  e.roots = bounding;
}

/// The cut of edge k of face `slot`; valid until the next new cut.
const EdgeCut& Driller::cut_of(int slot, int k) {
  Face& f = faces_[static_cast<std::size_t>(slot)];
  int& c = f.cut[static_cast<std::size_t>(k)];
  if (c < 0) c = edge_cut(f.v[static_cast<std::size_t>(k)], f.v[static_cast<std::size_t>((k + 1) % 3)]);
  return cuts_[static_cast<std::size_t>(c)];
}

/// The vertex at root k of edge (x, y), cut as `e`, on this side of a seam.
int Driller::crossing(int x, int y, const EdgeCut& e, int k) {
  const auto [a, b] = canonical(x, y);
  int& id = (*crossing_of_edge_.try_emplace(edge_key(a, b), std::array<int, 4>{-1, -1, -1, -1})
                  .first)[static_cast<std::size_t>(k)];
  if (id < 0) {
    const double t = own_alpha(vertex(a), vertex(b), e, k);
    Vertex v;
    v.source = blend(a, b, t);
    v.placed = (1 - t) * vertex(a).placed + t * vertex(b).placed;
    v.weld = e.weld[static_cast<std::size_t>(k)];
    v.crossing = true;
    id = add_vertex(v);
  }
  return id;
}

/// Parameter of point k of cut `e` on this copy of the edge (a, b): the cut's own where the
/// copies of a seam are placed alike; where they are not (a seam whose copies have different
/// influences, so the posed surface has a crack there), the same boundary crossed on this copy,
/// so that every point lies on the drill's boundary. The decisions (which parts are inside) stay
/// the cut's, so both sides of the seam agree.
double Driller::own_alpha(const Vertex& a, const Vertex& b, const EdgeCut& e, int k) const {
  const double t = e.alpha[static_cast<std::size_t>(k)], level = e.level[static_cast<std::size_t>(k)];
  if (level >= 0) return a.h != b.h ? std::clamp((a.h - level) / (a.h - b.h), 0.0, 1.0) : t;
  const EdgeQuadratic f = quadratic(a, b);
  if (!(f.K > 0) || f.discriminant() < 0) return t;
  const double q = f.q();
  double best = t, gap = INFINITY;
  for (const double r : {q / f.K, q != 0 ? f.N / q : t})
    if (r >= 0 && r <= 1 && std::abs(r - t) < gap) {
      best = r;
      gap = std::abs(r - t);
    }
  return best;
}

/// |P(a) − P(b)|², eq. (18): −2 X_a·X_b − (X_a·Π − X_b·Π)².
double Driller::projected_length2(const Vertex& a, const Vertex& b) const {
  const double dh = a.h - b.h;
  if (c_.predicates == Predicates::cga) return std::max(0.0, -2 * cga::scalar_product(a.point, b.point) - dh * dh);
  const Eigen::Vector3d d = a.placed - b.placed;
  return std::max(0.0, d.squaredNorm() - dh * dh);
}

// ---- refinement ----

bool Driller::too_coarse(const Pass& pass, const std::vector<Rim>& rims) const {
  if (pass.affected.empty()) return false;
  if (pass.disks_inside > 0 || pass.coarse_arcs > 0) return true;
  for (const Rim& rim : rims)
    if (rim_points(rim) < options_.min_rim_points) return true;
  return false;
}

/// The affected faces that keep a part (the rim crosses them, or the disk lies inside them).
std::vector<int> Driller::rim_faces(const Pass& pass) {
  std::vector<int> out;
  out.reserve(pass.polygons.size());
  for (const auto& polygon : pass.polygons) out.push_back(polygon[0]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

int Driller::rim_points(const Rim& rim) { return static_cast<int>(rim.chords.size()) + (rim.closed ? 0 : 1); }

/// The faces in `red_faces` and every face with two or more split edges are split 1 -> 4 at
/// their edge midpoints, faces with one split edge 1 -> 2.
void Driller::refine(const std::vector<int>& red_faces) {
  const RedGreen marks = red_green(red_faces);
  for (int s : marks.red) split_red(s);
  for (int s : marks.green) split_green(s, marks.split);
}

RedGreen Driller::red_green(const std::vector<int>& red_faces) {
  RedGreen out;
  std::vector<char> is_red;  // per slot
  const auto red_already = [&](int slot) {
    return static_cast<std::size_t>(slot) < is_red.size() && is_red[static_cast<std::size_t>(slot)] != 0;
  };
  std::vector<int> queue, candidates;
  const auto edge_of = [&](int slot, int k) {
    const Face& f = faces_[static_cast<std::size_t>(slot)];
    return edge_key(weld(f.v[static_cast<std::size_t>(k)]), weld(f.v[static_cast<std::size_t>((k + 1) % 3)]));
  };
  const auto make_red = [&](int slot) {
    if (red_already(slot)) return;
    is_red.resize(std::max(is_red.size(), faces_.size()), 0);
    is_red[static_cast<std::size_t>(slot)] = 1;
    out.red.push_back(slot);
    for (int k = 0; k < 3; ++k) out.split.try_emplace(edge_of(slot, k), 1);
    queue.push_back(slot);
  };
  for (int s : red_faces) make_red(s);
  const auto marked = [&](int slot) {
    int n = 0;
    for (int k = 0; k < 3; ++k) n += out.split.find(edge_of(slot, k)) != nullptr ? 1 : 0;
    return n;
  };
  while (!queue.empty()) {
    const int s = queue.back();
    queue.pop_back();
    for (int k = 0; k < 3; ++k) {
      const int g = neighbor(s, k);
      if (g < 0 || red_already(g)) continue;
      if (marked(g) >= 2)
        make_red(g);
      else
        candidates.push_back(g);
    }
  }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (int s : candidates)  // some turned red after they were found
    if (!red_already(s)) out.green.push_back(s);
  return out;
}

void Driller::split_red(int slot) {
  const Face f = faces_[static_cast<std::size_t>(slot)];
  kill(slot);
  const int a = f.v[0], b = f.v[1], c = f.v[2];
  const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
  add_face({a, ab, ca}, f.origin, false);
  add_face({ab, b, bc}, f.origin, false);
  add_face({ca, bc, c}, f.origin, false);
  add_face({ab, bc, ca}, f.origin, false);
}

void Driller::split_green(int slot, const FlatMap<char>& split) {
  const Face f = faces_[static_cast<std::size_t>(slot)];
  int k = 0;
  while (split.find(edge_key(weld(f.v[static_cast<std::size_t>(k)]),
                             weld(f.v[static_cast<std::size_t>((k + 1) % 3)]))) == nullptr)
    ++k;
  kill(slot);
  const int u = f.v[static_cast<std::size_t>(k)], w = f.v[static_cast<std::size_t>((k + 1) % 3)],
            o = f.v[static_cast<std::size_t>((k + 2) % 3)];
  const int m = midpoint(u, w);
  add_face({u, m, o}, f.origin, false);
  add_face({m, w, o}, f.origin, false);
}

/// The midpoint of edge (x, y), made once per edge and welded once per welded edge.
int Driller::midpoint(int x, int y) {
  const auto [a, b] = canonical(x, y);
  const auto [known, added] = midpoint_of_edge_.try_emplace(edge_key(a, b), static_cast<int>(vertices_.size()));
  if (!added) return *known;
  Vertex v;
  v.source = blend(a, b, 0.5);
  v.placed = 0.5 * (vertex(a).placed + vertex(b).placed);
  const auto [w, new_weld] = midpoint_weld_.try_emplace(edge_key(weld(a), weld(b)), next_weld_);
  if (new_weld) ++next_weld_;
  v.weld = *w;
  return add_vertex(v);
}

std::vector<int> Driller::alive_faces() const {
  std::vector<int> alive;
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faces_[f].alive) alive.push_back(static_cast<int>(f));
  return alive;
}

// ---- the wall ----

/// The closed rims as loops, by height; a rim that is open or does not wind about the axis
/// counts as `open`.
std::vector<Loop> Driller::closed_loops(const Pass& pass, const std::vector<Rim>& rims,
                                        std::vector<OpenRim>& open) const {
  std::vector<Loop> loops;
  for (const Rim& rim : rims) {
    Loop loop = loop_of(pass, rim);
    if (!rim.closed) {
      open.push_back({std::move(loop.points), "it ends on a boundary of the mesh"});
      continue;
    }
    // A loop around the axis winds ±2π: + where the surface faces B (an entry), − an exit.
    if (std::abs(loop.winding) < std::numbers::pi) {
      open.push_back({std::move(loop.points), "it does not go around the drill's axis"});
      continue;
    }
    loops.push_back(std::move(loop));
  }
  std::sort(loops.begin(), loops.end(), [](const Loop& x, const Loop& y) { return x.height < y.height; });
  return loops;
}

Loop Driller::loop_of(const Pass& pass, const Rim& rim) const {
  Loop loop;
  loop.low = std::numeric_limits<double>::infinity();
  loop.high = -loop.low;
  for (int c : rim.chords) {
    const Chord& chord = pass.chords[static_cast<std::size_t>(c)];
    const double h = vertex(chord.p).h;
    loop.points.push_back(chord.p);
    loop.winding += angle_about(c_.axis, projected(chord.p), projected(chord.e));
    loop.height += h;
    loop.low = std::min(loop.low, h);
    loop.high = std::max(loop.high, h);
  }
  loop.height /= static_cast<double>(loop.points.size());
  return loop;
}

std::vector<AxisHit> Driller::axis_hits() const {
  const double reach = c_.length + index_.bvh.diagonal();
  std::vector<AxisHit> hits;
  for (const mesh::SegmentHit& hit : index_.bvh.segment_hits(c_.base, c_.base + reach * c_.axis)) {
    const auto f = mesh_.faces.row(hit.face);
    const Eigen::Vector3d a = placed_.row(f(0)).cast<double>().transpose(),
                          b = placed_.row(f(1)).cast<double>().transpose(),
                          c = placed_.row(f(2)).cast<double>().transpose();
    hits.push_back({hit.t * reach, (b - a).cross(c - a).dot(c_.axis) > 0});
  }
  std::sort(hits.begin(), hits.end(), [](const AxisHit& x, const AxisHit& y) { return x.height < y.height; });
  return hits;
}

std::string Driller::between(const std::vector<AxisHit>& hits, const Loop& a, const Loop& b) const {
  const bool crossed = std::any_of(hits.begin(), hits.end(), [&](const AxisHit& h) {
    return h.height > a.high + tolerance_ && h.height < b.low - tolerance_;
  });
  return crossed ? "the surface lies across the drill's axis between it and the next exit" : "";
}

std::string Driller::blind_reason(const std::vector<AxisHit>& hits, const Loop& a) const {
  const auto next =
      std::find_if(hits.begin(), hits.end(), [&](const AxisHit& h) { return h.height > a.high + tolerance_; });
  if (next == hits.end()) return "nothing lies past it along the drill: the tip is outside the material";
  if (!next->exit) return "the surface past it along the drill faces the drill: the tip is outside the material";
  if (next->height < c_.length - tolerance_)
    return "the drill leaves the material " + std::to_string(c_.length - next->height) +
           " before its tip, where it does not cut a whole rim";
  return "";
}

std::string Driller::describe(const OpenRim& rim) const {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double depth = 0;
  for (int x : rim.points) {
    centre += vertex(x).placed;
    depth += vertex(x).h;
  }
  const auto n = static_cast<double>(std::max<std::size_t>(rim.points.size(), 1));
  centre /= n;
  std::ostringstream s;
  s << std::setprecision(4) << "the rim of " << rim.points.size() << " points around (" << centre.x() << ", "
    << centre.y() << ", " << centre.z() << "), " << depth / n << " along the drill from its base,";
  return s.str();
}

/// A rim on the drill's boundary up to the tip — on the cylinder below it, or on the tip's disk
/// (where that disk cuts the surface): the wall of a blind hole can go down from it.
bool Driller::on_boundary_to_tip(const Loop& loop) const {
  return std::all_of(loop.points.begin(), loop.points.end(), [&](int x) {
    const Vertex& v = vertex(x);
    return (v.s == 0 && v.h < c_.length) || (v.h == c_.length && v.s <= 0);
  });
}

/// Merges loop a (winding +) with loop b (winding −, walked backwards) by angle about the axis,
/// each triangle holding the reverse of one rim edge, so the surface stays closed and
/// consistently oriented.
void Driller::zipper(const std::vector<int>& a, const std::vector<int>& b, std::vector<Triangle>& tube) const {
  const auto wrap = [](double t) { return std::remainder(t, 2 * std::numbers::pi); };
  const int m = static_cast<int>(a.size()), n = static_cast<int>(b.size());
  const double a0 = angle(a[0]);
  int j0 = 0;
  for (int j = 1; j < n; ++j)
    if (std::abs(wrap(angle(b[static_cast<std::size_t>(j)]) - a0)) <
        std::abs(wrap(angle(b[static_cast<std::size_t>(j0)]) - a0)))
      j0 = j;
  const auto A = [&](int i) { return a[static_cast<std::size_t>(i % m)]; };
  const auto B = [&](int j) { return b[static_cast<std::size_t>(((j0 - j) % n + n) % n)]; };
  double ua = a0, ub = a0 + wrap(angle(B(0)) - a0);
  int i = 0, j = 0;
  while (i < m || j < n) {
    const double next_a = ua + wrap(angle(A(i + 1)) - angle(A(i)));
    const double next_b = ub + wrap(angle(B(j + 1)) - angle(B(j)));
    if (j == n || (i < m && next_a <= next_b)) {
      tube.push_back({A(i + 1), A(i), B(j)});
      ua = next_a;
      ++i;
    } else {
      tube.push_back({B(j), B(j + 1), A(i)});
      ub = next_b;
      ++j;
    }
  }
}

/// The wall of a blind hole below the entry rim `a` (winding +, in its own direction): a tube
/// straight down the cylinder to the tip's disk, each triangle pair holding the reverse of one
/// rim edge, and the disk. Rim points on the tip's disk are their own feet; a rim edge between
/// two of them borders the disk directly. A disk bounded by the circle alone is a fan about the
/// tip; one that the surface cuts (part of its boundary runs inside the circle) is triangulated
/// as a polygon in the disk's plane.
bool Driller::blind(const std::vector<int>& a, Walls& walls) {
  const Eigen::Vector3d tip = c_.base + c_.length * c_.axis;
  const std::size_t n = a.size();
  std::vector<int> q(n);
  bool cut_disk = false;
  for (std::size_t i = 0; i < n; ++i) {
    const Vertex& v = vertex(a[i]);
    cut_disk = cut_disk || v.s < 0;
    q[i] = v.h == c_.length ? a[i] : add_off_surface(a[i], tip + c_.radius * projected(a[i]).normalized());
  }
  std::vector<Triangle> bottom;
  if (!cut_disk) {
    const int centre = add_off_surface(a[0], tip);
    for (std::size_t i = 0; i < n; ++i) bottom.push_back({q[(i + 1) % n], q[i], centre});
  } else {
    // In (e1, e2), with e1 × e2 the axis, the triangles come counter-clockwise: facing up the
    // axis. The disk faces back up the hole, so each is flipped.
    std::vector<Eigen::Vector2d> points(n);
    std::vector<std::array<int, 2>> edges(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d d = projected(q[i]);
      points[i] = {d.dot(c_.e1), d.dot(c_.e2)};
      edges[i] = {static_cast<int>(i), static_cast<int>((i + 1) % n)};
    }
    try {
      for (const auto& t : triangulate_loops(points, edges))
        bottom.push_back(
            {q[static_cast<std::size_t>(t[0])], q[static_cast<std::size_t>(t[2])], q[static_cast<std::size_t>(t[1])]});
    } catch (const TopologyError&) {
      return false;  // the rim crosses itself seen along the axis
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    if (q[i] != a[i]) walls.tube.push_back({a[j], a[i], q[i]});
    if (q[j] != a[j]) walls.tube.push_back({a[j], q[i], q[j]});
  }
  walls.bottom.insert(walls.bottom.end(), bottom.begin(), bottom.end());
  return true;
}

/// A new point of a blind hole's wall at `at`, off the input surface, with the influences of the
/// rim point `above` it.
int Driller::add_off_surface(int above, const Eigen::Vector3d& at) {
  Vertex v;
  v.source = vertex(above).old >= 0 ? VertexSource::copy(vertex(above).old) : vertex(above).source;
  v.placed = at;
  v.weld = next_weld_++;
  v.off_surface = true;
  return add_vertex(v);
}

double Driller::angle(int x) const {
  const Eigen::Vector3d d = projected(x);
  return std::atan2(d.dot(c_.e2), d.dot(c_.e1));
}

// ---- output ----

/// Removes the input faces that were split or that the drill meets; returns the affected flag of
/// each face of the region.
std::vector<char> Driller::remove_changed_faces(const Pass& pass, LocalEdit& edit) const {
  std::vector<char> affected(faces_.size(), 0);
  for (int s : pass.affected) affected[static_cast<std::size_t>(s)] = 1;
  for (std::size_t s = 0; s < faces_.size(); ++s)
    if (faces_[s].original && (!faces_[s].alive || affected[s] != 0)) edit.remove_face(faces_[s].origin);
  return affected;
}

/// At most every new point of the region, and n − 2 triangles per kept n-gon.
void Driller::reserve_output(const Pass& pass, const Walls& walls, LocalEdit& edit) const {
  const std::size_t fresh =
      vertices_.size() - static_cast<std::size_t>(std::count_if(vertices_.begin(), vertices_.end(),
                                                                [](const Vertex& v) { return v.old >= 0; }));
  edit.reserve(fresh,
               faces_.size() + pass.corners.size() - 2 * pass.polygons.size() + static_cast<std::size_t>(walls.size()));
}

/// The faces refinement made that the drill does not meet.
void Driller::emit_split_faces(const std::vector<char>& affected, LocalEdit& edit, std::vector<int>& ids) const {
  for (std::size_t s = 0; s < faces_.size(); ++s) {
    const Face& f = faces_[s];
    if (f.alive && !f.original && affected[s] == 0) emit_triangle(f.v, f.origin, edit, ids);
  }
}

void Driller::emit_kept_polygons(const Pass& pass, LocalEdit& edit, std::vector<int>& ids) const {
  std::vector<Eigen::Vector3d> corners;
  std::vector<Triangle> triangles;
  for (const auto& [slot, first, count] : pass.polygons) {
    corners.clear();
    triangles.clear();
    for (int k = 0; k < count; ++k) corners.push_back(vertex(pass.corners[static_cast<std::size_t>(first + k)]).placed);
    triangulate_convex(corners, triangles);
    for (const Triangle& t : triangles)
      emit_triangle(
          {pass.corners[static_cast<std::size_t>(first + t[0])], pass.corners[static_cast<std::size_t>(first + t[1])],
           pass.corners[static_cast<std::size_t>(first + t[2])]},
          faces_[static_cast<std::size_t>(slot)].origin, edit, ids);
  }
}

/// Each wall surface has its own copies of its vertices, with its normals (area-weighted, in the
/// placed pose), so that it is not shaded with the surface's or the other's.
void Driller::emit_walls(const Walls& walls, LocalEdit& edit) const {
  for (const std::vector<Triangle>* surface : {&walls.tube, &walls.bottom}) {
    std::vector<Eigen::Vector3d> normal(vertices_.size(), Eigen::Vector3d::Zero());
    for (const Triangle& t : *surface) {
      const Eigen::Vector3d n =
          (vertex(t[1]).placed - vertex(t[0]).placed).cross(vertex(t[2]).placed - vertex(t[0]).placed);
      for (const int x : t) normal[static_cast<std::size_t>(x)] += n;
    }
    // The copies in the order of the region's vertices, not of the triangles: a disk's
    // triangulation may differ between predicates (its points are near cocircular).
    std::vector<int> copy(vertices_.size(), -1);
    for (const Triangle& t : *surface)
      for (const int x : t) copy[static_cast<std::size_t>(x)] = 0;
    for (std::size_t x = 0; x < copy.size(); ++x) {
      if (copy[x] < 0) continue;
      const Vertex& v = vertices_[x];
      copy[x] = edit.add_vertex({.source = v.old >= 0 ? VertexSource::copy(v.old) : v.source,
                                 .placed = v.placed,
                                 .normal = normal[x].normalized(),
                                 .off_surface = v.off_surface},
                                nv_);
    }
    for (const Triangle& t : *surface) {
      edit.add_face_from({copy[static_cast<std::size_t>(t[0])], copy[static_cast<std::size_t>(t[1])],
                          copy[static_cast<std::size_t>(t[2])]},
                         LocalEdit::kCutSurface);
    }
  }
}

void Driller::emit_triangle(const Triangle& t, int origin, LocalEdit& edit, std::vector<int>& ids) const {
  edit.add_face_from({extended(t[0], edit, ids), extended(t[1], edit, ids), extended(t[2], edit, ids)}, origin);
}

/// The extended id of region vertex x; `ids` holds those of the new vertices (or −1).
int Driller::extended(int x, LocalEdit& edit, std::vector<int>& ids) const {
  const Vertex& v = vertex(x);
  if (v.old >= 0) return v.old;
  int& id = ids[static_cast<std::size_t>(x)];
  if (id < 0) id = edit.add_vertex({.source = v.source, .placed = v.placed}, nv_);
  return id;
}

// ---- the region ----

/// Conformal point, height and cylinder value of a placed point (the point-versus-cylinder
/// predicate of section 4.2.3): ρ² − r² = −2 X·S − (X·Π)², distances of conformal points being
/// −2 X·Y; or the same in Euclidean terms.
void Driller::probe(Vertex& v) const {
  const Eigen::Vector3d d = v.placed - c_.base;
  if (c_.predicates == Predicates::cga) {
    v.point = cga::up<double>(d);
    v.h = cga::scalar_product(v.point, c_.plane);
    v.s = -2 * cga::scalar_product(v.point, c_.sphere) - v.h * v.h;
  } else {
    v.h = c_.axis.dot(d);
    v.s = d.squaredNorm() - v.h * v.h - c_.radius * c_.radius;
  }
  if (std::abs(v.s) <= s_tolerance_) v.s = 0;
  if (std::abs(v.h) <= tolerance_) v.h = 0;
  if (std::abs(v.h - c_.length) <= tolerance_) v.h = c_.length;
}

int Driller::add_vertex(const Vertex& v) {
  probe(vertices_.emplace_back(v));
  return static_cast<int>(vertices_.size()) - 1;
}

int Driller::local_of_old(int old) {
  const auto [local, added] =
      local_of_old_.try_emplace(static_cast<std::uint64_t>(old), static_cast<int>(vertices_.size()));
  if (!added) return *local;
  Vertex v;
  v.old = old;
  v.source = VertexSource::copy(old);
  v.placed = placed_.row(old).cast<double>().transpose();
  v.weld = index_.weld[static_cast<std::size_t>(old)];
  return add_vertex(v);
}

/// (a, b) ordered from the smaller welded id: the order both sides of a seam agree on.
std::pair<int, int> Driller::canonical(int a, int b) const {
  const int wa = weld(a), wb = weld(b);
  return wa < wb || (wa == wb && a < b) ? std::pair{a, b} : std::pair{b, a};
}

/// The projection of vertex x onto Π, from B.
Eigen::Vector3d Driller::projected(int x) const {
  const Vertex& v = vertex(x);
  return v.placed - c_.base - v.h * c_.axis;
}

/// The origin of (1 − t) a + t b in the input mesh: all the region's points lie in one input
/// face, so at most three input vertices, ordered by welded id (seam copies blend alike).
VertexSource Driller::blend(int a, int b, double t) const {
  std::array<std::pair<int, float>, 6> slots{};
  int n = 0;
  const auto add = [&](const VertexSource& s, double w) {
    for (int k = 0; k < s.count(); ++k) {
      const int v = s.vertex[static_cast<std::size_t>(k)];
      const auto weight = static_cast<float>(w * s.weight[static_cast<std::size_t>(k)]);
      auto* it = std::find_if(slots.begin(), slots.begin() + n, [&](const auto& p) { return p.first == v; });
      if (it == slots.begin() + n)
        slots[static_cast<std::size_t>(n++)] = {v, weight};
      else
        it->second += weight;
    }
  };
  add(vertex(a).source, 1 - t);
  add(vertex(b).source, t);
  if (n > 3) throw std::logic_error("drill: a new point blends more than three input vertices");
  const auto before = [&](const std::pair<int, float>& x, const std::pair<int, float>& y) {
    const int wx = index_.weld[static_cast<std::size_t>(x.first)], wy = index_.weld[static_cast<std::size_t>(y.first)];
    return wx < wy || (wx == wy && x.first < y.first);
  };
  for (int k = 1; k < n; ++k)  // insertion sort of at most three
    for (int j = k; j > 0 && before(slots[static_cast<std::size_t>(j)], slots[static_cast<std::size_t>(j - 1)]); --j)
      std::swap(slots[static_cast<std::size_t>(j)], slots[static_cast<std::size_t>(j - 1)]);
  VertexSource out;
  for (int k = 0; k < n; ++k) {
    out.vertex[static_cast<std::size_t>(k)] = slots[static_cast<std::size_t>(k)].first;
    out.weight[static_cast<std::size_t>(k)] = slots[static_cast<std::size_t>(k)].second;
  }
  return out;
}

/// The input face `f` as a face of the region (added on first use).
int Driller::slot_of(int f) {
  const auto [slot, added] = slot_of_old_.try_emplace(static_cast<std::uint64_t>(f), static_cast<int>(faces_.size()));
  if (added) add_input_face(f);
  return *slot;
}

void Driller::add_input_face(int f) {
  const Triangle v{local_of_old(mesh_.faces(f, 0)), local_of_old(mesh_.faces(f, 1)), local_of_old(mesh_.faces(f, 2))};
  add_face(v, f, true);
}

void Driller::add_face(const Triangle& v, int origin, bool original) {
  const int slot = static_cast<int>(faces_.size());
  faces_.push_back({v, origin, original});
  for (int k = 0; k < 3; ++k) {
    const auto [half_edge, added] = half_edges_.try_emplace(
        directed_key(weld(v[static_cast<std::size_t>(k)]), weld(v[static_cast<std::size_t>((k + 1) % 3)])),
        3 * slot + k);
    if (!added && *half_edge < 0) *half_edge = 3 * slot + k;
  }
}

void Driller::kill(int slot) {
  Face& f = faces_[static_cast<std::size_t>(slot)];
  f.alive = false;
  for (int k = 0; k < 3; ++k) {
    int* half_edge = half_edges_.find(
        directed_key(weld(f.v[static_cast<std::size_t>(k)]), weld(f.v[static_cast<std::size_t>((k + 1) % 3)])));
    if (half_edge != nullptr && *half_edge == 3 * slot + k) *half_edge = -1;
  }
}

/// The face across edge k of face `slot` (pulled in from the input when it is not in the region
/// yet), or −1 on a boundary or non-manifold edge.
int Driller::neighbor(int slot, int k) {
  const Face& f = faces_[static_cast<std::size_t>(slot)];
  const int u = f.v[static_cast<std::size_t>(k)], v = f.v[static_cast<std::size_t>((k + 1) % 3)];
  if (const int* half_edge = half_edges_.find(directed_key(weld(v), weld(u))); half_edge != nullptr && *half_edge >= 0)
    return *half_edge / 3;
  // Split faces are bordered by split faces only (red-green keeps the region conforming): only an
  // input face borders input faces outside the region.
  if (!f.original) return -1;
  const int g = index_.neighbor[static_cast<std::size_t>(f.origin)][static_cast<std::size_t>(k)];
  if (g < 0) return -1;
  const int added = static_cast<int>(faces_.size());
  if (!slot_of_old_.try_emplace(static_cast<std::uint64_t>(g), added).second) return -1;
  add_input_face(g);
  return added;
}

}  // namespace cgamesh::surgery::detail
