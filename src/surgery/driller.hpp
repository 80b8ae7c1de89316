#pragma once
// Private to surgery: the drill of one mesh (paper Algorithm 3, eqs. 18–20), declared as the
// steps it runs so that each can be read, and tested, alone.

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/vertex_source.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/surface_index.hpp"

#include "../flat_map.hpp"
#include "surgery_common.hpp"

namespace cgamesh::surgery::detail {

using Triangle = std::array<int, 3>;

/// The drill: the axis from B along the unit vector n, the radius, and its CGA objects in the
/// drill's own frame (origin at B, so that the conformal points of a small region far from the
/// world origin keep their precision: X·Y is translation invariant).
struct Cylinder {
  Eigen::Vector3d base, axis;
  double radius = 0;
  double length = 0;           ///< |A − B|: the drill takes what lies between its two end disks
  cga::Vector<double> sphere;  ///< S = eo − ½ r² e∞: the sphere of radius r about B (eq. 4)
  cga::Vector<double> plane;   ///< Π = n: the plane ⟂ AB through B (eq. 5)
  Predicates predicates = Predicates::cga;
  Eigen::Vector3d e1, e2;  ///< an orthonormal basis of Π, for angles about the axis
};

/// The drill from `base` B to `tip` A as a Cylinder, after checking its parameters and `options`.
/// @throws InvalidInputError for non-finite points, radius <= 0 or NaN, tip == base, bad options.
[[nodiscard]] Cylinder make_cylinder(const Eigen::Vector3d& tip, const Eigen::Vector3d& base, double radius,
                                     const DrillOptions& options);

/// A vertex of the region being drilled: an input vertex, or a new point of an input edge or
/// face (a midpoint of a refinement, an intersection point).
struct Vertex {
  int old = -1;               ///< input vertex, or −1
  mesh::VertexSource source;  ///< where it comes from in the input mesh
  Eigen::Vector3d placed;
  int weld = -1;              ///< seam copies share it
  bool crossing = false;      ///< an intersection point of an edge with the drill's boundary
  bool off_surface = false;   ///< a point of a blind hole's wall: not on the input surface
  double s = 0;               ///< ρ² − r² (ρ: distance of its projection onto Π from B); 0 on the cylinder
  double h = 0;               ///< X·Π: height above Π
  cga::Vector<double> point;  ///< X = up(x − B) (cga predicates)
};

/// d²(ξ, B) − r² along an edge (a, b) at ξ = (1 − α) a + α b, as Kα² + Lα + N: K is eq. (18),
/// N = s(a) eq. (20) and L = s(b) − s(a) − K eq. (19) (the quadratic is s(b) at α = 1).
struct EdgeQuadratic {
  double K = 0, L = 0, N = 0;
  [[nodiscard]] double operator()(double t) const { return (K * t + L) * t + N; }
  [[nodiscard]] double discriminant() const { return L * L - 4 * K * N; }
  /// −(L ± √disc)/2 with the sign of L: the roots are q/K and N/q, stable, and right for an
  /// edge along the axis too (K → 0: the quadratic becomes linear and N/q its root).
  [[nodiscard]] double q() const { return -0.5 * (L + std::copysign(std::sqrt(std::max(discriminant(), 0.0)), L)); }
};

/// How the cylinder crosses an edge, from its end with the smaller welded id (so that both
/// sides of a seam compute the same points).
struct EdgeCut {
  /// Intersection points strictly inside the edge, in order: at most 2 on the cylinder and 1
  /// on each end disk's plane.
  int roots = 0;
  std::array<double, 4> alpha{};
  /// What each point lies on: the cylinder (-1), or the plane of the end disk at that height.
  std::array<double, 4> level{-1, -1, -1, -1};
  std::array<int, 4> weld{-1, -1, -1, -1};  ///< welded ids of the intersection points
  std::array<bool, 5> inside{};             ///< sub-segment k (between points k, k+1) in the drill
  bool any_inside = false;
};

struct Face {
  Triangle v;
  int origin;     ///< the input face it lies in
  bool original;  ///< still the input face itself
  bool alive = true;
  int visited = -1;                    ///< pass of the last search that reached it
  std::array<int, 3> cut{-1, -1, -1};  ///< per edge k (v[k], v[k + 1]), its cut in cuts_ once known
};

/// The boundary of a face walked from corner 0: its corners and the points where it crosses
/// the drill's boundary, and whether the part from each point to the next is in the drill.
struct FaceBoundary {
  std::array<int, 15> point{};  ///< 3 corners and up to 4 points per edge
  std::array<bool, 15> inside{};
  int size = 0;
};

/// A chord replacing an arc of the circle: the closing edge p -> e of a kept polygon.
struct Chord {
  int p, e;
};

/// One pass over the affected region: which faces the drill meets and what is left of them.
struct Pass {
  std::vector<int> affected;
  std::vector<int> corners;                  ///< kept polygons, flattened
  std::vector<std::array<int, 3>> polygons;  ///< face, first corner, corner count
  std::vector<Chord> chords;
  int disks_inside = 0;  ///< faces the disk lies inside of (no point of their boundary in the drill)
  int coarse_arcs = 0;   ///< chords replacing too long an arc
};

/// A boundary loop (or chain) of chords around the hole, as a sequence of chords.
struct Rim {
  std::vector<int> chords;
  bool closed = false;
};

/// What refinement did: its rounds, and whether the budget stopped it.
struct Refinement {
  int rounds = 0;
  bool over_budget = false;
};

/// One round of red-green refinement: the faces split 1 -> 4 and those split 1 -> 2.
struct RedGreen {
  FlatMap<char> split;     ///< welded undirected edges split at their midpoints
  std::vector<int> red;    ///< in the order they turned red
  std::vector<int> green;  ///< one split edge each, sorted
};

/// A closed rim that winds about the axis, as the first points of its chords.
struct Loop {
  std::vector<int> points;  ///< in the rim's own direction
  double winding = 0, height = 0;
  double low = 0, high = 0;  ///< the least and greatest height of its points
};

/// Where the drill's axis, from B on past the tip, crosses the surface: its height above B, and
/// whether the surface faces along the axis there (the axis leaves the material).
struct AxisHit {
  double height = 0;
  bool exit = false;
};

/// A rim left without a wall, and why (for the warning that names it).
struct OpenRim {
  std::vector<int> points;
  std::string reason;
};

/// The triangles of the walls: tubes, and the bottom disks of blind holes (each gets its own
/// copies of the vertices it shares with the other, for its own normals).
struct Walls {
  std::vector<Triangle> tube, bottom;
  [[nodiscard]] int size() const { return static_cast<int>(tube.size() + bottom.size()); }
};

/// Drills one mesh: pulls the faces the drill meets into a region, cuts them, refines the
/// region while the rims are too coarse, walls the hole and emits the changed faces.
class Driller {
 public:
  Driller(const mesh::Mesh& mesh, const mesh::RowMatrixXf<3>& placed, const MeshIndex& index, const Cylinder& cylinder,
          const DrillOptions& options);

  /// Drills the faces of `candidates` that meet the drill and those reached from them through
  /// faces that meet it; fills `edit` (left empty when none does) and the counters.
  void run(const std::vector<int>& candidates, LocalEdit& edit, DrillStats& out);

  // ---- the steps of run, in order (public building blocks, each tested on its own) ----

  /// Room for the region pulled in from `candidates` input faces.
  void reserve_region(std::size_t candidates);

  /// The input faces `faces` as faces of the region.
  std::vector<int> slots_of(const std::vector<int>& faces);
  /// Algorithm 3, steps 2, 3 and 5: the faces the drill meets, reached from `seeds`, and their kept polygons.
  Pass analyse(const std::vector<int>& seeds);
  /// Chains the chords into rims by welded ids (seam copies join).
  [[nodiscard]] std::vector<Rim> find_rims(const Pass& pass) const;
  /// Splits the faces the rims cross and analyses again while a rim is too coarse, within the budget.
  Refinement refine_while_coarse(Pass& pass, std::vector<Rim>& rims);
  /// Warns of a refinement the budget stopped, a disk still inside a face, or a rim still coarse.
  void warn_if_coarse(const Pass& pass, const std::vector<Rim>& rims, const Refinement& refinement,
                      const std::string& name, std::vector<std::string>& warnings) const;
  /// Tubes between an entry rim and the exit rim that bounds the same hole across the material,
  /// blind holes below a last entry rim whose tip lies in the material; every other rim stays
  /// open, with a warning naming it. Counts walls and open rims in `out`.
  Walls wall(const Pass& pass, const std::vector<Rim>& rims, const std::string& name, DrillStats& out);
  /// Step 5: replaces the input faces of the region that changed by their pieces and the walls.
  void emit(const Pass& pass, const Walls& walls, LocalEdit& edit, DrillStats& out) const;

  // ---- the region, as the steps build it ----

  /// Adds a vertex to the region; its index.
  int add_vertex(const Vertex& v);
  [[nodiscard]] const Vertex& vertex(int x) const { return vertices_[static_cast<std::size_t>(x)]; }
  [[nodiscard]] int vertex_count() const { return static_cast<int>(vertices_.size()); }
  /// The region's faces, by slot (dead ones included, alive false).
  [[nodiscard]] const std::vector<Face>& faces() const { return faces_; }
  /// The cut of edge (x, y), made once per welded edge; an index for cut().
  int edge_cut(int x, int y);
  [[nodiscard]] const EdgeCut& cut(int i) const { return cuts_[static_cast<std::size_t>(i)]; }
  /// Red-green refinement of `red_faces` (no T-junctions).
  void refine(const std::vector<int>& red_faces);

 private:

  // ---- analyse ----

  /// The faces that meet the drill, by a breadth-first search from `seeds` through such faces.
  std::vector<int> search(const std::vector<int>& seeds);
  /// Whether face `slot` meets the open drill (step 2's test).
  bool meets(int slot);
  [[nodiscard]] bool axis_through(const Face& f) const;
  /// Adds the polygons of face `slot` outside the drill, and their chords, to `pass`.
  void keep(int slot, Pass& pass);
  FaceBoundary boundary(int slot);
  void keep_run(int slot, std::span<const int> run, Pass& pass);
  static void add_polygon(Pass& pass, int slot, std::span<const int> corners);
  [[nodiscard]] double arc(const Chord& chord, std::span<const int> polygon) const;

  // ---- the cylinder against an edge: edge_cut, then its steps in order ----

  [[nodiscard]] EdgeQuadratic quadratic(const Vertex& a, const Vertex& b) const;
  /// Adds the points where the edge crosses the cylinder (0, 1 or 2).
  void cylinder_roots(const Vertex& a, const Vertex& b, const EdgeQuadratic& f, EdgeCut& e) const;
  /// Adds the points where the edge crosses the end disks' planes.
  void plane_crossings(const Vertex& a, const Vertex& b, double edge_length, EdgeCut& e) const;
  /// Sorts the points along the edge and merges those within the tolerance of each other.
  void merge_points(double edge_length, EdgeCut& e) const;
  /// Sets which sub-segments of the edge lie in the drill.
  void classify(const Vertex& a, const Vertex& b, const EdgeQuadratic& f, EdgeCut& e) const;
  /// Drops the points with the outside on both sides.
  static void drop_non_bounding(EdgeCut& e);

  const EdgeCut& cut_of(int slot, int k);
  int crossing(int x, int y, const EdgeCut& e, int k);
  [[nodiscard]] double own_alpha(const Vertex& a, const Vertex& b, const EdgeCut& e, int k) const;
  [[nodiscard]] double projected_length2(const Vertex& a, const Vertex& b) const;

  // ---- refinement ----

  [[nodiscard]] bool too_coarse(const Pass& pass, const std::vector<Rim>& rims) const;
  [[nodiscard]] static std::vector<int> rim_faces(const Pass& pass);
  [[nodiscard]] static int rim_points(const Rim& rim);
  RedGreen red_green(const std::vector<int>& red_faces);
  void split_red(int slot);
  void split_green(int slot, const FlatMap<char>& split);
  int midpoint(int x, int y);
  [[nodiscard]] std::vector<int> alive_faces() const;

  // ---- the wall ----

  [[nodiscard]] std::vector<Loop> closed_loops(const Pass& pass, const std::vector<Rim>& rims,
                                               std::vector<OpenRim>& open) const;
  [[nodiscard]] Loop loop_of(const Pass& pass, const Rim& rim) const;
  [[nodiscard]] bool on_boundary_to_tip(const Loop& loop) const;
  /// The surface along the axis from B to a diagonal past the tip, nearest first.
  [[nodiscard]] std::vector<AxisHit> axis_hits() const;
  /// Why no tube joins entry `a` to exit `b` (empty when one may): surface between them.
  [[nodiscard]] std::string between(const std::vector<AxisHit>& hits, const Loop& a, const Loop& b) const;
  /// Why entry `a` cannot be the top of a blind hole (empty when it can): the material must go on
  /// from it past the tip.
  [[nodiscard]] std::string blind_reason(const std::vector<AxisHit>& hits, const Loop& a) const;
  [[nodiscard]] std::string describe(const OpenRim& rim) const;
  void zipper(const std::vector<int>& a, const std::vector<int>& b, std::vector<Triangle>& tube) const;
  bool blind(const std::vector<int>& a, Walls& walls);
  int add_off_surface(int above, const Eigen::Vector3d& at);
  [[nodiscard]] double angle(int x) const;

  // ---- output ----

  [[nodiscard]] std::vector<char> remove_changed_faces(const Pass& pass, LocalEdit& edit) const;
  void reserve_output(const Pass& pass, const Walls& walls, LocalEdit& edit) const;
  void emit_split_faces(const std::vector<char>& affected, LocalEdit& edit, std::vector<int>& ids) const;
  void emit_kept_polygons(const Pass& pass, LocalEdit& edit, std::vector<int>& ids) const;
  void emit_walls(const Walls& walls, LocalEdit& edit) const;
  /// Emits t, a piece of input face `origin` (whose material it keeps).
  void emit_triangle(const Triangle& t, int origin, LocalEdit& edit, std::vector<int>& ids) const;
  int extended(int x, LocalEdit& edit, std::vector<int>& ids) const;

  // ---- the region: vertices and faces, pulled in from the input on demand ----

  void probe(Vertex& v) const;
  int local_of_old(int old);
  [[nodiscard]] int weld(int x) const { return vertex(x).weld; }
  [[nodiscard]] std::pair<int, int> canonical(int a, int b) const;
  [[nodiscard]] Eigen::Vector3d projected(int x) const;
  [[nodiscard]] mesh::VertexSource blend(int a, int b, double t) const;
  int slot_of(int f);
  void add_input_face(int f);
  void add_face(const Triangle& v, int origin, bool original);
  void kill(int slot);
  int neighbor(int slot, int k);

  const mesh::Mesh& mesh_;
  const mesh::RowMatrixXf<3>& placed_;
  const MeshIndex& index_;
  const Cylinder& c_;
  const DrillOptions& options_;
  const int nv_;
  int next_weld_;
  double tolerance_ = 0, s_tolerance_ = 0;
  int pass_ = 0;
  std::vector<Vertex> vertices_;
  std::vector<Face> faces_;
  FlatMap<int> local_of_old_, slot_of_old_;
  FlatMap<int> half_edges_;  ///< welded directed edge -> 3 · face + k, or −1 once its face is gone
  std::vector<EdgeCut> cuts_;
  FlatMap<int> cut_of_edge_;  ///< welded undirected edge -> its cut in cuts_
  FlatMap<std::array<int, 4>> crossing_of_edge_;
  FlatMap<int> midpoint_of_edge_, midpoint_weld_;
};

}  // namespace cgamesh::surgery::detail
