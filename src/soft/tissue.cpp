#include "cgamesh/soft/tissue.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

#if defined(__SSE2__)
#include <xmmintrin.h>
#include <emmintrin.h>
#endif

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/mesh/union_find.hpp"

#include "../surgery/surgery_common.hpp"

namespace cgamesh::soft {
namespace {

Eigen::Vector3d row(const mesh::RowMatrixXf<3>& p, int v) { return p.row(v).transpose().cast<double>(); }

/// Vertex v of `m` skinned with `palette`, its morph displacement included.
Eigen::Vector3d skinned(const mesh::Mesh& m, const anim::SkinningPalette& palette, int v) {
  const Eigen::Matrix<double, 3, 4> a = anim::blended_affine(m, palette, v);
  const Eigen::Vector3d x = row(m.positions, v) + anim::morph_offset(m, palette.morph_weights, v).cast<double>();
  return a.leftCols<3>() * x + a.col(3);
}

/// Removes repeated keys (lesser particle << 32 | greater, both < n) from `keys`, which end up
/// ordered by their lesser particle, in linear time (a counting sort; a sort was a tenth of a
/// rebuild).
void unique_pairs(std::vector<std::uint64_t>& keys, std::size_t n) {
  std::vector<std::size_t> begin(n + 1, 0);
  for (const std::uint64_t k : keys) ++begin[(k >> 32) + 1];
  for (std::size_t a = 0; a < n; ++a) begin[a + 1] += begin[a];
  std::vector<std::uint64_t> sorted(keys.size());
  std::vector<std::size_t> next(begin.begin(), begin.end() - 1);
  for (const std::uint64_t k : keys) sorted[next[k >> 32]++] = k;
  // Within one lesser particle, a greater one seen before (stamped with lesser + 1) repeats.
  std::vector<std::size_t> seen(n, 0);
  keys.clear();
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t j = begin[a]; j < begin[a + 1]; ++j) {
      std::size_t& s = seen[sorted[j] & 0xffffffffu];
      if (s != a + 1) keys.push_back(sorted[j]);
      s = a + 1;
    }
}

/// The factors of links [begin, end) of one colour (as Tissue::substep() solves them): Δλ =
/// −C / (w_a + w_b + α/h²) along d/|d|, with C = |d| − scale·|t_a − t_b|, gives the step s·d with
/// s = Δλ/|d| = gain·(√(rest²/|d|²) − 1), rest = scale·(t_a − t_b) = d0 + alpha·Δd (`rest`: the
/// columns of d0 and Δd, Tissue::step()); l2 = |d|². In single precision, four links per
/// instruction (relative error 6e-8, far below the solver's): a frame streams its links' data,
/// and this halves it. A zero |d| is floored and the ratio capped, so that s stays finite.
/// `begin` and `end` are multiples of 4.
void link_factors(const std::array<const float*, 6>& rest, std::size_t begin, std::size_t end, float alpha,
                  const float* gain, const float* l2, float* s) {
  for (std::size_t k = begin; k < end; k += 4) {
#if defined(__SSE2__)
    const __m128 a = _mm_set1_ps(alpha);
    __m128 r2 = _mm_setzero_ps();
    for (std::size_t c = 0; c < 3; ++c) {
      const __m128 d = _mm_add_ps(_mm_loadu_ps(rest[c] + k), _mm_mul_ps(a, _mm_loadu_ps(rest[c + 3] + k)));
      r2 = _mm_add_ps(r2, _mm_mul_ps(d, d));
    }
    const __m128 q =
        _mm_min_ps(_mm_div_ps(r2, _mm_max_ps(_mm_loadu_ps(l2 + k), _mm_set1_ps(1e-30f))), _mm_set1_ps(1e30f));
    _mm_storeu_ps(s + k, _mm_mul_ps(_mm_loadu_ps(gain + k), _mm_sub_ps(_mm_sqrt_ps(q), _mm_set1_ps(1.0f))));
#else
    for (std::size_t j = k; j < k + 4; ++j) {
      float r2 = 0;
      for (std::size_t c = 0; c < 3; ++c) {
        const float d = rest[c][j] + alpha * rest[c + 3][j];
        r2 += d * d;
      }
      s[j] = gain[j] * (std::sqrt(std::min(r2 / std::max(l2[j], 1e-30f), 1e30f)) - 1.0f);
    }
#endif
  }
}

}  // namespace

Tissue::Tissue(const surgery::LiveModel& live, const TissueOptions& options) : options_(options) {
  options_.validate();
  const anim::RiggedModel& model = live.model();
  const surgery::Placement& placed = live.placement();
  Eigen::AlignedBox3d box;
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    ChunkedArray<VertexState> state(static_cast<std::size_t>(m.vertex_count()), VertexState{});
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      const int a = m.faces(f, 0), b = m.faces(f, 1), c = m.faces(f, 2);
      const Eigen::Vector3d pa = row(placed.positions[i], a);
      const double area = 0.5 * (row(placed.positions[i], b) - pa).cross(row(placed.positions[i], c) - pa).norm();
      for (const int v : {a, b, c}) state[static_cast<std::size_t>(v)].mass += options_.density * area / 3;
    }
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) box.extend(row(placed.positions[i], static_cast<int>(v)));
    state_.push_back(std::move(state));
    face_mark_.emplace_back(static_cast<std::size_t>(m.face_count()), 0);
  }
  diagonal_ = box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-12);
  radius_ = options_.region_radius > 0 ? options_.region_radius : 0.1 * diagonal_;
  margin_ = options_.release_margin > 0 ? options_.release_margin : 0.25 * radius_;
}

void Tissue::set_options(const surgery::LiveModel& live, const TissueOptions& options) {
  options.validate();
  const double density_ratio = options.density / options_.density;
  for (auto& m : state_) m.for_each([&](VertexState& u) { u.mass *= density_ratio; });
  options_ = options;
  radius_ = options_.region_radius > 0 ? options_.region_radius : 0.1 * diagonal_;
  margin_ = options_.release_margin > 0 ? options_.release_margin : 0.25 * radius_;
  for (Ball& b : balls_)
    if (b.vertex >= 0) b.radius = radius_;
  for (Ball& b : releases_) b.radius = margin_;
  save_state();
  rebuild(live);
}

Eigen::Vector3d Tissue::momentum() const noexcept {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < x_.size(); ++k)
    if (free_[k] != 0 && inverse_mass_[k] > 0) p += v_[k] / inverse_mass_[k];
  return p;
}

double Tissue::total_mass() const noexcept {
  double total = 0;
  for (const auto& m : state_) m.for_each([&](const VertexState& u) { total += u.mass; });
  return total;
}

std::size_t Tissue::free_particles() const noexcept {
  return static_cast<std::size_t>(std::count(free_.begin(), free_.end(), 1));
}

// ---- Topology and region ----

Eigen::Vector3d Tissue::Ball::center(const surgery::Placement& placed) const {
  return vertex < 0 ? point : row(placed.positions[static_cast<std::size_t>(mesh)], vertex);
}

void Tissue::follow(const surgery::LiveModel& live, std::span<const surgery::MeshChange> changes) {
  const anim::RiggedModel& model = live.model();
  save_state();
  for (const surgery::MeshChange& c : changes) {
    if (c.mesh < 0 || c.mesh >= static_cast<int>(model.meshes.size()) ||
        static_cast<std::size_t>(c.mesh) >= state_.size())
      throw InvalidInputError("tissue: a change names mesh " + std::to_string(c.mesh) + " of " +
                              std::to_string(state_.size()));
    const auto i = static_cast<std::size_t>(c.mesh);
    const mesh::Mesh& m = model.meshes[i];
    const auto nv = static_cast<std::size_t>(m.vertex_count());
    if (c.first_new_vertex < 0 || static_cast<std::size_t>(c.first_new_vertex) != state_[i].size() ||
        static_cast<std::size_t>(c.first_new_vertex) + c.origins.size() != nv)
      throw InvalidInputError("tissue: the change of mesh " + std::to_string(c.mesh) +
                              " does not follow the last one the tissue saw (" + std::to_string(state_[i].size()) +
                              " vertices known, " + std::to_string(c.first_new_vertex) + " + " +
                              std::to_string(c.origins.size()) + " in the change, " + std::to_string(nv) +
                              " in the mesh)");
    ChunkedArray<VertexState>& state = state_[i];
    state.resize(nv, VertexState{});
    const mesh::RowMatrixXf<3>& placed = live.placement().positions[i];
    std::vector<int> centers;
    for (std::size_t k = 0; k < c.origins.size(); ++k) {
      const std::size_t v = static_cast<std::size_t>(c.first_new_vertex) + k;
      const mesh::VertexSource& o = c.origins[k];
      Eigen::Vector3d x = Eigen::Vector3d::Zero(), vel = Eigen::Vector3d::Zero();
      for (int s = 0; s < o.count(); ++s) {
        const auto src = static_cast<std::size_t>(o.vertex[static_cast<std::size_t>(s)]);
        const double w = o.weight[static_cast<std::size_t>(s)];
        if (src >= static_cast<std::size_t>(c.first_new_vertex))
          throw InvalidInputError("tissue: a new vertex's origin is not a vertex from before the change");
        // Half of each source's share moves to the new vertex: the total stays.
        VertexState& from = state[src];
        const double share = 0.5 * w * from.mass;
        from.mass -= share;
        state[v].mass += share;
        const bool known = from.saved == generation_;
        x += w * (known ? from.x : row(placed, static_cast<int>(src)));
        if (known) vel += w * from.v;
      }
      state[v].x = x;
      state[v].v = vel;
      state[v].saved = generation_;
      const Eigen::Vector3d p = row(placed, static_cast<int>(v));
      // One ball per stretch of the wound: a new vertex farther than half a margin from the
      // centres so far, this change's and earlier ones' (a long stroke adds few balls).
      const auto near = [&](const Eigen::Vector3d& q) { return (q - p).norm() < 0.5 * margin_; };
      if (std::none_of(centers.begin(), centers.end(), [&](int q) { return near(row(placed, q)); }) &&
          std::none_of(balls_.begin(), balls_.end(),
                       [&](const Ball& b) { return b.mesh == c.mesh && near(b.center(live.placement())); }))
        centers.push_back(static_cast<int>(v));
    }
    for (const int v : centers) {
      balls_.push_back({c.mesh, v, Eigen::Vector3d::Zero(), radius_});
      releases_.push_back({c.mesh, v, Eigen::Vector3d::Zero(), margin_});
    }
  }
  rebuild(live);
}

void Tissue::select(const surgery::LiveModel& live, int mesh, const Eigen::Vector3d& center, double radius) {
  if (mesh < 0 || mesh >= static_cast<int>(live.model().meshes.size()))
    throw InvalidInputError("tissue: select: mesh " + std::to_string(mesh) + " of " +
                            std::to_string(live.model().meshes.size()));
  if (!(radius >= 0) || !std::isfinite(radius) || !center.allFinite())
    throw InvalidInputError("tissue: select: the centre and radius must be finite, the radius >= 0");
  save_state();
  balls_.push_back({mesh, -1, center, radius});
  rebuild(live);
}

void Tissue::save_state() {
  ++generation_;
  for (std::size_t k = 0; k < members_.size(); ++k) {
    const Member& u = members_[k];
    const auto i = static_cast<std::size_t>(u.mesh), v = static_cast<std::size_t>(u.vertex);
    VertexState& s = state_[i][v];
    s.x = x_[static_cast<std::size_t>(u.particle)];
    s.v = v_[static_cast<std::size_t>(u.particle)];
    s.saved = generation_;
    s.particle = -1;
  }
  members_.clear();
}

std::vector<Eigen::Vector4d> Tissue::spheres(const std::vector<Ball>& balls, int mesh,
                                             const surgery::Placement& placed) {
  std::vector<Eigen::Vector4d> out;
  for (const Ball& b : balls)
    if (b.mesh == mesh) {
      const Eigen::Vector3d c = b.center(placed);
      const double r = std::max(b.radius, 1e-150);
      out.emplace_back(c.x(), c.y(), c.z(), 1.0 / (r * r));
    }
  return out;
}

double Tissue::reach(const std::vector<Eigen::Vector4d>& spheres, const Eigen::Vector3d& p) {
  // The least of |p − centre|² / radius², then one root.
  double best = INFINITY;
  for (const Eigen::Vector4d& s : spheres) best = std::min(best, (p - s.head<3>()).squaredNorm() * s.w());
  return std::sqrt(best);
}

float Tissue::vertex_reach(const surgery::LiveModel& live, std::size_t mesh, int v) {
  const auto k = static_cast<std::size_t>(v);
  VertexState& s = state_[mesh][k];
  if (s.reach_mark != reach_mark_) {
    s.reach_mark = reach_mark_;
    s.reach = static_cast<float>(reach(region_spheres_[mesh], row(live.placement().positions[mesh], v)));
  }
  return s.reach;
}

std::vector<std::vector<int>> Tissue::region_faces(const surgery::LiveModel& live) {
  const anim::RiggedModel& model = live.model();
  const std::size_t budget = options_.max_particles > 0 ? 2 * static_cast<std::size_t>(options_.max_particles)
                                                        : std::numeric_limits<std::size_t>::max();
  // A vertex's reach is its distance to the nearest ball over that ball's radius; a face's, the
  // least of its corners'. The region grows from the faces at the balls' centres across the
  // surface, nearest first (a priority queue), over the faces of reach < 1: every free vertex
  // (reach < 1) then has all its faces and links, and the other corners pin the border. Past
  // the budget it stops, as if every ball were shrunk by one factor (scale_). It costs what the
  // region holds, whatever the size of the mesh or of the balls.
  // A candidate is one 64-bit key: its reach's bits (a float ≥ 0 orders as its bits do) over
  // its index in `faces` (ties go to the first pushed, as the walk is deterministic).
  std::vector<std::pair<int, int>>& faces = candidates_;
  faces.clear();
  ReachQueue& queue = queue_;
  queue.clear();
  region_spheres_.resize(model.meshes.size());
  ++mark_;
  reach_mark_ = mark_;
  const auto push = [&](std::size_t i, int f) {
    int& seen = face_mark_[i][static_cast<std::size_t>(f)];
    if (seen == mark_) return;
    seen = mark_;
    const mesh::Mesh& m = model.meshes[i];
    float r = INFINITY;
    for (int k = 0; k < 3; ++k) r = std::min(r, vertex_reach(live, i, m.faces(f, k)));
    if (r < 1) {
      queue.push(std::uint64_t{std::bit_cast<std::uint32_t>(r)} << 32 | faces.size());
      faces.emplace_back(static_cast<int>(i), f);
    }
  };
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    face_mark_[i].resize(static_cast<std::size_t>(model.meshes[i].face_count()), 0);
    region_spheres_[i] = spheres(balls_, static_cast<int>(i), live.placement());
    std::vector<int> seeds;
    for (const Ball& b : balls_) {
      if (b.mesh != static_cast<int>(i)) continue;
      // A wound's ball starts at the faces around its vertex; a selected point's, at every
      // face its ball's box meets (the point need not lie on the surface).
      const Eigen::Vector3d c = b.center(live.placement());
      const double half = b.vertex >= 0 ? 0.0 : b.radius;
      live.index().meshes[i].bvh.faces_in_box(c - Eigen::Vector3d::Constant(half), c + Eigen::Vector3d::Constant(half),
                                              seeds);
    }
    for (const int f : seeds) push(i, f);
  }
  std::vector<std::vector<int>> out(model.meshes.size());
  std::size_t taken = 0;
  scale_ = 1;
  while (!queue.empty()) {
    const std::uint64_t top = queue.top();
    if (taken == budget) {
      scale_ = std::bit_cast<float>(static_cast<std::uint32_t>(top >> 32));
      break;
    }
    queue.pop();
    ++taken;
    const auto [mesh, face] = faces[static_cast<std::size_t>(top & 0xffffffffu)];
    const auto i = static_cast<std::size_t>(mesh);
    out[i].push_back(face);
    for (const int g : live.index().meshes[i].neighbor[static_cast<std::size_t>(face)])
      if (g >= 0) push(i, g);
  }
  // From here, face_mark_ == mark_ means: in the region.
  ++mark_;
  for (std::size_t i = 0; i < out.size(); ++i)
    for (const int f : out[i]) face_mark_[i][static_cast<std::size_t>(f)] = mark_;
  return out;
}

void Tissue::rebuild(const surgery::LiveModel& live) {
  const anim::RiggedModel& model = live.model();
  ref_.clear();
  x_.clear();
  v_.clear();
  inverse_mass_.clear();
  free_.clear();
  attached_.clear();
  links_.clear();
  have_targets_ = false;
  std::vector<double> particle_mass;
  // A link's particles as one sortable key: the lesser over the greater.
  std::vector<std::uint64_t> edges, loose, bends;
  const auto key = [](int a, int b) {
    return std::uint64_t{static_cast<std::uint32_t>(std::min(a, b))} << 32 | static_cast<std::uint32_t>(std::max(a, b));
  };
  const std::vector<std::vector<int>> region = region_faces(live);
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    const surgery::MeshIndex& index = live.index().meshes[i];
    const mesh::RowMatrixXf<3>& placed = live.placement().positions[i];
    const std::vector<int>& faces = region[i];
    const ChunkedArray<int>& in_region = face_mark_[i];
    const std::vector<Eigen::Vector4d> release_spheres = spheres(releases_, static_cast<int>(i), live.placement());
    // Particles: one per welded class of the faces' corners.
    const auto particle = [&](int v) {
      VertexState& sv = state_[i][static_cast<std::size_t>(v)];
      int& pv = sv.particle;
      if (pv >= 0) return pv;
      const int rep = index.weld[static_cast<std::size_t>(v)];
      VertexState& sr = state_[i][static_cast<std::size_t>(rep)];
      std::array<int, 2>& cls = sr.cls;
      if (cls[0] != mark_) {
        cls = {mark_, static_cast<int>(x_.size())};
        const Eigen::Vector3d at = row(placed, rep);
        const VertexState* known = sr.saved == generation_ ? &sr : sv.saved == generation_ ? &sv : nullptr;
        ref_.push_back({static_cast<int>(i), rep});
        x_.push_back(known != nullptr ? known->x : at);
        v_.push_back(known != nullptr ? known->v : Eigen::Vector3d::Zero());
        free_.push_back(vertex_reach(live, i, v) < scale_ ? 1 : 0);
        attached_.push_back(reach(release_spheres, at) < scale_ ? 0 : 1);
        particle_mass.push_back(0.0);
      }
      pv = cls[1];
      members_.push_back({static_cast<int>(i), v, pv});
      particle_mass[static_cast<std::size_t>(pv)] += sv.mass;
      return pv;
    };
    for (const int f : faces) {
      std::array<int, 3> corner{};
      for (int k = 0; k < 3; ++k) corner[static_cast<std::size_t>(k)] = particle(m.faces(f, k));
      for (int k = 0; k < 3; ++k) {
        const int a = corner[static_cast<std::size_t>(k)], b = corner[static_cast<std::size_t>((k + 1) % 3)];
        // An edge between two region faces is taken from the first of them; one without a twin
        // (a border, a non-manifold edge) may come from several faces and is deduplicated.
        const int g = index.neighbor[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        const bool twin_in_region = g >= 0 && in_region[static_cast<std::size_t>(g)] == mark_;
        if (a != b && (g < 0 || !twin_in_region || g > f)) (g < 0 ? loose : edges).push_back(key(a, b));
        // Bending across edge k, once per pair of region faces.
        if (g > f && twin_in_region) {
          const int kg = index.edge_across(f, k);
          if (kg < 0) continue;
          const int a2 = corner[static_cast<std::size_t>((k + 2) % 3)], b2 = particle(m.faces(g, (kg + 2) % 3));
          if (a2 != b2) bends.push_back(key(a2, b2));
        }
      }
    }
  }
  for (std::size_t p = 0; p < x_.size(); ++p)
    inverse_mass_.push_back(free_[p] != 0 && particle_mass[p] > 0 ? 1.0 / particle_mass[p] : 0.0);
  std::sort(loose.begin(), loose.end());
  loose.erase(std::unique(loose.begin(), loose.end()), loose.end());
  edges.insert(edges.end(), loose.begin(), loose.end());
  // Two pairs of faces may share their opposite corners (about 2 % of CesiumMan's): one link.
  unique_pairs(bends, x_.size());
  const auto add = [&](const std::vector<std::uint64_t>& pairs, float scale, float compliance) {
    for (const std::uint64_t k : pairs) {
      const auto a = static_cast<int>(k >> 32), b = static_cast<int>(k & 0xffffffffu);
      if (inverse_mass_[static_cast<std::size_t>(a)] + inverse_mass_[static_cast<std::size_t>(b)] > 0)
        links_.push_back({a, b, scale, compliance});
    }
  };
  // A piece the wound cut loose that no held particle holds through its links would fall away
  // for ever: its particles stay attached (it hangs on as surgery left it).
  mesh::UnionFind pieces(x_.size());
  for (const std::uint64_t k : edges) pieces.unite(static_cast<int>(k >> 32), static_cast<int>(k & 0xffffffffu));
  std::vector<char> held(x_.size(), 0);
  for (std::size_t p = 0; p < x_.size(); ++p)
    if (free_[p] == 0 || attached_[p] != 0) held[static_cast<std::size_t>(pieces.find(static_cast<int>(p)))] = 1;
  for (std::size_t p = 0; p < x_.size(); ++p)
    if (held[static_cast<std::size_t>(pieces.find(static_cast<int>(p)))] == 0) attached_[p] = 1;
  add(edges, static_cast<float>(1 - options_.pretension), static_cast<float>(options_.stretch_compliance));
  add(bends, 1.0f, static_cast<float>(options_.bend_compliance));
  order_links();
}

void Tissue::order_links() {
  // Greedy colouring: a link takes the first colour that no earlier link at either of its
  // particles has. Links of one colour share no particle, so substep() computes their
  // corrections in packets before applying them (the same result as one after the other,
  // Gauss-Seidel).
  std::vector<std::uint64_t> used(x_.size(), 0);
  std::vector<int> colour(links_.size(), 0);
  for (std::size_t k = 0; k < links_.size(); ++k) {
    auto& ua = used[static_cast<std::size_t>(links_[k].a)];
    auto& ub = used[static_cast<std::size_t>(links_[k].b)];
    const std::uint64_t taken = ua | ub;
    const int c = taken == ~std::uint64_t{0} ? 63 : std::countr_one(taken);
    colour[k] = c;
    ua |= std::uint64_t{1} << c;
    ub |= std::uint64_t{1} << c;
  }
  // Colour by colour, in the order made (a counting sort: stable, in time proportional to the
  // links), each colour padded to a multiple of 4 (substep()'s packets) with its last link again,
  // with no gain.
  std::vector<std::size_t> count(64, 0);
  for (const int c : colour) ++count[static_cast<std::size_t>(c)];
  colour_begin_.assign(1, 0);
  std::vector<std::size_t> next;
  // First fit leaves no colour unused below one that is used.
  for (std::size_t c = 0; c < count.size() && count[c] > 0; ++c) {
    next.push_back(colour_begin_.back());
    colour_begin_.push_back(colour_begin_.back() + (count[c] + 3) / 4 * 4);
  }
  link_count_ = links_.size();
  std::vector<Link> sorted(colour_begin_.back());
  for (std::size_t k = 0; k < links_.size(); ++k) sorted[next[static_cast<std::size_t>(colour[k])]++] = links_[k];
  const double h2 = options_.substep * options_.substep;
  link_gain_.assign(sorted.size(), 0.0f);
  for (std::size_t c = 0; c + 1 < colour_begin_.size(); ++c)
    for (std::size_t k = colour_begin_[c]; k < colour_begin_[c + 1]; ++k) {
      if (k >= next[c]) {
        sorted[k] = sorted[next[c] - 1];
        continue;
      }
      const Link& l = sorted[k];
      link_gain_[k] = static_cast<float>(1.0 / (inverse_mass_[static_cast<std::size_t>(l.a)] +
                                                inverse_mass_[static_cast<std::size_t>(l.b)] +
                                                static_cast<double>(l.compliance) / h2));
    }
  links_ = std::move(sorted);
  ends_.resize(links_.size());
  for (std::size_t k = 0; k < links_.size(); ++k) ends_[k] = {links_[k].a, links_[k].b};
  length2_.assign(links_.size(), 0.0f);
  correction_.assign(links_.size(), 0.0f);
}

// ---- Simulation ----

void Tissue::targets_in(const surgery::LiveModel& live, const anim::Pose& pose,
                        std::vector<Eigen::Vector3d>& out) const {
  const anim::RiggedModel& model = live.model();
  const std::vector<anim::SkinningPalette> p = surgery::palettes(model, pose);
  // In the pose the model is placed in (paused while a tear is dragged, a settle), each target is
  // the vertex as placed: no skinning.
  const surgery::Placement& placed = live.placement();
  const bool as_placed = std::equal(p.begin(), p.end(), placed.palettes.begin(), placed.palettes.end(),
                                    [](const anim::SkinningPalette& a, const anim::SkinningPalette& b) {
                                      return a.affine == b.affine && a.morph_weights == b.morph_weights;
                                    });
  out.resize(x_.size());
  for (std::size_t k = 0; k < x_.size(); ++k) {
    const auto i = static_cast<std::size_t>(ref_[k].mesh);
    out[k] = as_placed ? row(placed.positions[i], ref_[k].vertex) : skinned(model.meshes[i], p[i], ref_[k].vertex);
  }
}

void Tissue::substep(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to, double alpha,
                     double h) {
  const std::size_t n = x_.size();
  std::vector<Eigen::Vector3d>& before = scratch_;
  before.resize(n);
  // One pass over the particles (a pass each was a sixth of the substep): the target, the
  // prediction, then the attachment (one Gauss-Seidel pass per substep, small steps: λ starts
  // at 0 each substep).
  for (std::size_t p = 0; p < n; ++p) {
    before[p] = x_[p];
    const Eigen::Vector3d t = (1 - alpha) * from[p] + alpha * to[p];
    if (free_[p] == 0) {
      x_[p] = t;
      continue;
    }
    v_[p] += h * options_.gravity;
    x_[p] += h * v_[p];
    if (attached_[p] == 0) continue;
    const Eigen::Vector3d d = x_[p] - t;
    x_[p] -= d * attach_gain_[p];
  }
  // Colour by colour: the links' |d|², their factors in packets, their steps. The links of a
  // colour share no particle, so this is Gauss-Seidel's result. Padding has no gain: no step.
  Eigen::Vector3d* const x = x_.data();
  const double* const w = inverse_mass_.data();
  const std::array<int, 2>* const ends = ends_.data();
  float* const len2 = length2_.data();
  float* const s = correction_.data();
  const std::array<const float*, 6> rest{rest_.col(0).data(), rest_.col(1).data(), rest_.col(2).data(),
                                         rest_.col(3).data(), rest_.col(4).data(), rest_.col(5).data()};
  for (std::size_t c = 0; c + 1 < colour_begin_.size(); ++c) {
    const std::size_t begin = colour_begin_[c], end = colour_begin_[c + 1];
    for (std::size_t k = begin; k < end; ++k) len2[k] = static_cast<float>((x[ends[k][0]] - x[ends[k][1]]).squaredNorm());
    link_factors(rest, begin, end, static_cast<float>(alpha), link_gain_.data(), len2, s);
    for (std::size_t k = begin; k < end; ++k) {
      const auto [a, b] = ends[k];
      const Eigen::Vector3d g = (x[a] - x[b]) * static_cast<double>(s[k]);
      x[a] += w[a] * g;
      x[b] -= w[b] * g;
    }
  }
  const double keep = std::exp(-options_.damping * h);
  for (std::size_t p = 0; p < n; ++p) v_[p] = free_[p] != 0 ? Eigen::Vector3d((x_[p] - before[p]) * (keep / h)) : Eigen::Vector3d::Zero();
}

void Tissue::step(const surgery::LiveModel& live, const anim::Pose& pose, double dt) {
  if (!(dt >= 0) || !std::isfinite(dt)) throw InvalidInputError("tissue: step: dt must be a finite number >= 0");
  if (x_.empty()) return;
  std::vector<Eigen::Vector3d> to;
  targets_in(live, pose, to);
  const std::vector<Eigen::Vector3d>& from = have_targets_ ? previous_target_ : to;
  const double h = options_.substep;
  // The attachment's w / (w + α/h²) of each particle (a division per substep was 5 % of one);
  // 0 for no mass to move (w = 0, also when the attachment is rigid: α = 0).
  const double attach = options_.attachment_compliance / (h * h);
  attach_gain_.resize(x_.size());
  for (std::size_t p = 0; p < x_.size(); ++p)
    attach_gain_[p] = inverse_mass_[p] > 0 ? inverse_mass_[p] / (inverse_mass_[p] + attach) : 0.0;
  const auto steps = static_cast<long>(std::floor((dt + carried_) / h));
  const std::vector<Eigen::Vector3d> x0 = x_, v0 = v_;
  // Each link's rest vector scale·(t_a − t_b) at the step's start (d0) and its change over the
  // step (Δd), as columns: the substeps read them in order instead of gathering targets.
  rest_.resize(static_cast<Eigen::Index>(links_.size()), 6);
  for (std::size_t k = 0; k < links_.size(); ++k) {
    const auto a = static_cast<std::size_t>(links_[k].a), b = static_cast<std::size_t>(links_[k].b);
    const double scale = links_[k].scale;
    const Eigen::Vector3d d0 = scale * (from[a] - from[b]), dd = scale * (to[a] - to[b]) - d0;
    for (Eigen::Index c = 0; c < 3; ++c) {
      rest_(static_cast<Eigen::Index>(k), c) = static_cast<float>(d0[c]);
      rest_(static_cast<Eigen::Index>(k), c + 3) = static_cast<float>(dd[c]);
    }
  }
  for (long s = 1; s <= steps; ++s) {
    const double a = static_cast<double>(s) / static_cast<double>(steps);
    substep(from, to, a, h);
  }
  for (std::size_t p = 0; p < x_.size(); ++p)
    if (!x_[p].allFinite() || (x_[p] - to[p]).squaredNorm() > 100 * diagonal_ * diagonal_) {
      x_ = x0;
      v_ = v0;
      throw SolverError("tissue: the simulation diverged (a particle left the model's reach); try a smaller "
                        "substep or larger compliances");
    }
  carried_ = dt + carried_ - static_cast<double>(steps) * h;
  previous_target_ = std::move(to);
  have_targets_ = true;
}

SettleReport Tissue::settle(const surgery::LiveModel& live, const anim::Pose& pose, double max_seconds,
                            double tolerance) {
  SettleReport r;
  const double frame = 1.0 / 90.0;
  while (r.seconds < max_seconds) {
    step(live, pose, frame);
    r.seconds += frame;
    r.max_speed = 0;
    for (std::size_t p = 0; p < v_.size(); ++p)
      if (free_[p] != 0) r.max_speed = std::max(r.max_speed, v_[p].norm());
    if (r.max_speed < tolerance * diagonal_) {
      r.settled = true;
      break;
    }
  }
  r.substeps = static_cast<int>(std::lround(r.seconds / options_.substep));
  return r;
}

// ---- Output ----

std::vector<mesh::RowMatrixXf<3>> Tissue::positions(const surgery::LiveModel& live, const anim::Pose& pose) const {
  std::vector<mesh::RowMatrixXf<3>> out = surgery::place(live.model(), pose).positions;
  for (std::size_t i = 0; i < out.size(); ++i)
    overlay(live, static_cast<int>(i), std::span<float>(out[i].data(), static_cast<std::size_t>(out[i].size())));
  return out;
}

void Tissue::overlay(const surgery::LiveModel& live, int mesh, std::span<float> positions) const {
  const auto& meshes = live.model().meshes;
  if (mesh < 0 || mesh >= static_cast<int>(meshes.size()))
    throw InvalidInputError("tissue: overlay: mesh " + std::to_string(mesh) + " of " + std::to_string(meshes.size()));
  const auto rows = static_cast<std::size_t>(meshes[static_cast<std::size_t>(mesh)].vertex_count());
  if (positions.size() != 3 * rows)
    throw InvalidInputError("tissue: overlay: " + std::to_string(positions.size()) + " floats for " +
                            std::to_string(rows) + " vertices (3 each)");
  for (const Member& u : members_)
    if (u.mesh == mesh) {
      const Eigen::Vector3d& x = x_[static_cast<std::size_t>(u.particle)];
      float* row = positions.data() + 3 * static_cast<std::size_t>(u.vertex);
      for (int c = 0; c < 3; ++c) row[c] = static_cast<float>(x[c]);
    }
}

anim::RiggedModel Tissue::bake(const surgery::LiveModel& live, const anim::Pose& pose) const {
  anim::RiggedModel out = live.model();
  const std::vector<anim::SkinningPalette> p = surgery::palettes(out, pose);
  for (const Member& u : members_) {
    if (free_[static_cast<std::size_t>(u.particle)] == 0) continue;
    mesh::Mesh& m = out.meshes[static_cast<std::size_t>(u.mesh)];
    const anim::SkinningPalette& palette = p[static_cast<std::size_t>(u.mesh)];
    const Eigen::Matrix<double, 3, 4> a = anim::blended_affine(m, palette, u.vertex);
    if (const auto x = surgery::unskin(a.leftCols<3>(), x_[static_cast<std::size_t>(u.particle)] - a.col(3)))
      m.positions.row(u.vertex) =
          (*x - anim::morph_offset(m, palette.morph_weights, u.vertex).cast<double>()).transpose().cast<float>();
  }
  return out;
}

}  // namespace cgamesh::soft
