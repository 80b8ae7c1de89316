#pragma once
// Private to surgery: the steps of a tear of one mesh (Algorithm 2), declared apart from tear()
// so that tests can run them one at a time.

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/triangle_bvh.hpp"
#include "cgamesh/surgery/surface_index.hpp"
#include "cgamesh/surgery/tear.hpp"

#include "surgery_common.hpp"

namespace cgamesh::surgery::detail {

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

/// The path points and path segments that fall in one input face, before it is re-triangulated.
struct FaceWork {
  std::vector<int> points;                   ///< path point indices
  std::vector<std::array<int, 2>> segments;  ///< pairs of path point indices
};

/// Tears one mesh: traces the surface path the blade sweeps, re-triangulates the faces it
/// crosses, splits the path vertices in two and moves the two sides apart.
class Tearer {
 public:
  Tearer(const mesh::Mesh& mesh, const mesh::RowMatrixXf<3>& placed, const anim::SkinningPalette& palette,
         const MeshIndex& index, const TearOptions& options);

  /// The entry point S of the blade: its first crossing of the surface from the handle.
  [[nodiscard]] PathPoint entry(const mesh::SegmentHit& hit) const;
  /// The whole path over all steps; consecutive points share a face.
  [[nodiscard]] std::vector<PathPoint> trace(const std::vector<PathPoint>& entries, std::span<const Scalpel> scalpel);
  /// Builds edit(): the faces the path crosses re-triangulated, its vertices split; returns #faces split.
  int prepare(const std::vector<PathPoint>& path);
  /// The edit prepare() made.
  [[nodiscard]] const LocalEdit& edit() const noexcept { return edit_; }
  /// Step 6: moves the copies of the path vertices in the edited mesh apart along ±n of Π.
  template <class VertexOf>
  void move_apart(const std::vector<PathPoint>& path, mesh::Mesh& m, mesh::RowMatrixXf<3>& placed,
                  const VertexOf& vertex_of) const;
  /// Calls visit(vertex, side) for every copy of a path vertex in the edited mesh.
  template <class VertexOf, class Visit>
  void for_each_copy(const VertexOf& vertex_of, const Visit& visit) const;

 private:
  using PathEdges = std::set<std::pair<long long, long long>>;

  // ---- trace(): per scalpel step, in order --------------------------------------------------

  /// Π through the step's entry point and the blade at the next time step.
  [[nodiscard]] static StepPlane step_plane(const PathPoint& s, const Scalpel& blade, int step);
  /// The shorter surface path along Π from one entry point to the next.
  [[nodiscard]] std::vector<PathPoint> walk(const PathPoint& start, const PathPoint& target, int step) const;
  /// The walkers that leave `start` in every direction Π allows.
  [[nodiscard]] std::vector<Walker> start_walkers(const PathPoint& start) const;
  /// Moves a walker on by one face: to the target, or out of its face along Π.
  void advance(Walker& w, const PathPoint& target, const StepPlane& plane, int start_face) const;
  /// Ends a walker at the target, which lies in its face.
  void arrive(Walker& w, const PathPoint& target) const;
  /// The crossing a walker leaves its face by; none when there is no way on.
  [[nodiscard]] std::optional<PathPoint> next_exit(Walker& w, const StepPlane& plane) const;
  /// Where Π meets the border of face f: its corners on Π and the crossings of its edges.
  [[nodiscard]] std::vector<PathPoint> crossings(int f, const StepPlane& p) const;
  /// Moves a walker into the face beyond its exit: across the edge, or around the vertex.
  void cross(Walker& w, const PathPoint& exit, const Eigen::Vector3d& from, const StepPlane& plane) const;
  /// The face and corner to go on in after the path reached a vertex.
  [[nodiscard]] std::pair<int, int> continue_at_vertex(int f, int k, const Eigen::Vector3d& previous,
                                                       const StepPlane& plane) const;
  /// The middle of a path of two points, so that the tear has a vertex to open at.
  [[nodiscard]] PathPoint midpoint(const PathPoint& a, const PathPoint& b) const;

  // ---- prepare(), in order ------------------------------------------------------------------

  /// Replaces every face the path crosses by a triangulation with the path in it.
  void retriangulate(const std::vector<PathPoint>& path);
  /// The faces the path touches, in the order it first touches them, with what falls in each.
  [[nodiscard]] std::vector<std::pair<int, FaceWork>> faces_crossed(const std::vector<PathPoint>& path) const;
  /// Triangulates face f with its path points and segments as constraints.
  void split_face(const std::vector<PathPoint>& path, int f, const FaceWork& work);
  /// Splits every path vertex but the two ends into one copy per side of the path.
  void duplicate(const std::vector<PathPoint>& path);
  /// The edges between consecutive path points, as pairs of key()s.
  [[nodiscard]] PathEdges path_edges(const std::vector<PathPoint>& path) const;
  /// Makes the faces around old path vertices editable new faces too.
  void free_fans(const std::vector<PathPoint>& path);
  /// Per surface point (key()), the new faces that use it.
  [[nodiscard]] std::unordered_map<long long, std::vector<int>> faces_by_key() const;
  /// Splits path point i among the groups of `faces` (the new faces around it).
  void split_point(const std::vector<PathPoint>& path, int i, std::vector<int>& faces, const PathEdges& on_path);
  /// Per face around point k: its side group, numbered 0, 1, … in the order of the faces.
  [[nodiscard]] std::vector<int> side_groups(long long k, const std::vector<int>& faces,
                                             const PathEdges& on_path) const;
  /// Per side group: the side of Π, ±1, its faces lie on.
  [[nodiscard]] std::vector<int> side_signs(const StepPlane& plane, long long k, const std::vector<int>& faces,
                                            const std::vector<int>& group, int groups) const;
  /// Gives each side group of point i its own copy of the vertices there; returns them.
  std::map<std::pair<int, int>, int> copy_for_groups(int i, long long k, const std::vector<int>& faces,
                                                     const std::vector<int>& group, const std::vector<int>& sign);

  // ---- move_apart() -------------------------------------------------------------------------

  /// Moves placed vertex v by `shift`, its rest position by the inverse of its skinning map.
  void move_vertex(mesh::Mesh& m, mesh::RowMatrixXf<3>& placed, int v, const Eigen::Vector3d& shift) const;

  // ---- geometry -----------------------------------------------------------------------------

  [[nodiscard]] int weld(int v) const { return index_.weld[static_cast<std::size_t>(v)]; }
  [[nodiscard]] int corner(int f, int k) const { return mesh_.faces(f, k % 3); }
  /// Placed position of a vertex (of its welded representative).
  [[nodiscard]] Eigen::Vector3d position(int v) const;
  [[nodiscard]] bool near(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const { return (a - b).norm() <= tol_; }
  /// The point of face f at barycentric coordinates b.
  [[nodiscard]] Eigen::Vector3d at(int f, const std::array<double, 3>& b) const;
  /// A point of face f, moved onto a corner or an edge within the snapping tolerance.
  [[nodiscard]] PathPoint snapped(int f, const Eigen::Vector3d& bary) const;
  /// Corner k of face f.
  [[nodiscard]] PathPoint vertex_point(int f, int k) const;
  /// The point (1 − t) corner k + t corner k+1 of face f.
  [[nodiscard]] PathPoint edge_point(int f, int k, double t) const;
  /// Signed distance of vertex v from Π, 0 within the tolerance.
  [[nodiscard]] double distance(const StepPlane& p, int v) const;
  /// Signed distance of an extended vertex from Π (no snapping).
  [[nodiscard]] double signed_offset(const StepPlane& plane, int x) const;
  /// The corner of face f at welded vertex `welded` (−1: none).
  [[nodiscard]] int corner_of(int f, int welded) const;
  /// The faces around the welded vertex at corner k of face f, f first.
  [[nodiscard]] std::vector<int> fan(int f, int k) const;
  /// Barycentric coordinates of path point p in face g (a face sharing its support).
  [[nodiscard]] std::array<double, 3> bary_in(const PathPoint& p, int g) const;
  /// 2-D coordinates (b₁, b₂) of barycentric b, exact on the three edges.
  [[nodiscard]] static Eigen::Vector2d plane_coordinates(const std::array<double, 3>& b);

  // ---- vertices of the edit -----------------------------------------------------------------

  /// Extended id of path point i as seen from face f.
  int vertex_in(const std::vector<PathPoint>& path, int i, int f);
  /// The new vertex of path point i (not at a corner) in face f.
  int new_vertex(const PathPoint& p, int i, int f);
  /// Identity of an extended vertex on the surface: welded id, or −1 − i for path point i.
  [[nodiscard]] long long key(int x) const;
  /// key() of path point i.
  [[nodiscard]] long long point_key(const std::vector<PathPoint>& path, int i) const;
  /// `s` keeping only the influences of its source vertices on the copy's own side of Π.
  [[nodiscard]] mesh::VertexSource restricted_influences(mesh::VertexSource s, const StepPlane& plane, int sign) const;

  const mesh::Mesh& mesh_;
  const mesh::RowMatrixXf<3>& placed_;
  const anim::SkinningPalette& palette_;
  const MeshIndex& index_;
  const TearOptions& options_;
  const int nv_;
  const double tol_;

  std::vector<StepPlane> planes_;  ///< per step of the path
  LocalEdit edit_;
  std::map<std::array<int, 4>, int> vertex_of_point_;  ///< new vertex per (edge or face, path point)
  std::vector<int> point_of_new_;                      ///< per new vertex: its path point
  /// Per path point: its copies (extended id, side ±1); empty where it was not split.
  std::vector<std::vector<std::pair<int, int>>> copies_;
};

// By open·sin(π s/L) in all at arc length s of a path of length L; rest positions follow
// through the inverse of each vertex's blended skinning map (Σ w Aⱼ), so the tear is open in
// the placed pose. vertex_of maps an extended id to its vertex in m (−1: not used).
template <class VertexOf>
void Tearer::move_apart(const std::vector<PathPoint>& path, mesh::Mesh& m, mesh::RowMatrixXf<3>& placed,
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

// vertex_of maps an extended id to its vertex in the edited mesh (−1: not used).
template <class VertexOf, class Visit>
void Tearer::for_each_copy(const VertexOf& vertex_of, const Visit& visit) const {
  for (const auto& point : copies_)
    for (const auto& [x, sign] : point)
      if (const int v = vertex_of(x); v >= 0) visit(v, static_cast<signed char>(sign));
}

}  // namespace cgamesh::surgery::detail
