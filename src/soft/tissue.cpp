#include "cgamesh/soft/tissue.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>

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

}  // namespace

Tissue::Tissue(const surgery::LiveModel& live, const TissueOptions& options) : options_(options) {
  options_.validate();
  const anim::RiggedModel& model = live.model();
  const surgery::Placement& placed = live.placement();
  Eigen::AlignedBox3d box;
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    std::vector<double> mass(static_cast<std::size_t>(m.vertex_count()), 0.0);
    for (Eigen::Index f = 0; f < m.face_count(); ++f) {
      const int a = m.faces(f, 0), b = m.faces(f, 1), c = m.faces(f, 2);
      const Eigen::Vector3d pa = row(placed.positions[i], a);
      const double area = 0.5 * (row(placed.positions[i], b) - pa).cross(row(placed.positions[i], c) - pa).norm();
      for (const int v : {a, b, c}) mass[static_cast<std::size_t>(v)] += options_.density * area / 3;
    }
    for (Eigen::Index v = 0; v < m.vertex_count(); ++v) box.extend(row(placed.positions[i], static_cast<int>(v)));
    mass_.push_back(std::move(mass));
    particle_of_.emplace_back(static_cast<std::size_t>(m.vertex_count()), -1);
    vx_.emplace_back(static_cast<std::size_t>(m.vertex_count()));
    vv_.emplace_back(static_cast<std::size_t>(m.vertex_count()));
    saved_.emplace_back(static_cast<std::size_t>(m.vertex_count()), 0);
  }
  diagonal_ = box.isEmpty() ? 1.0 : std::max(box.diagonal().norm(), 1e-12);
  radius_ = options_.region_radius > 0 ? options_.region_radius : 0.1 * diagonal_;
  margin_ = options_.release_margin > 0 ? options_.release_margin : 0.25 * radius_;
}

double Tissue::total_mass() const noexcept {
  double total = 0;
  for (const auto& m : mass_)
    for (const double x : m) total += x;
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
        static_cast<std::size_t>(c.mesh) >= mass_.size())
      throw InvalidInputError("tissue: a change names mesh " + std::to_string(c.mesh) + " of " +
                              std::to_string(mass_.size()));
    const auto i = static_cast<std::size_t>(c.mesh);
    const mesh::Mesh& m = model.meshes[i];
    const auto nv = static_cast<std::size_t>(m.vertex_count());
    if (c.first_new_vertex < 0 || static_cast<std::size_t>(c.first_new_vertex) != mass_[i].size() ||
        static_cast<std::size_t>(c.first_new_vertex) + c.origins.size() != nv)
      throw InvalidInputError("tissue: the change of mesh " + std::to_string(c.mesh) +
                              " does not follow the last one the tissue saw (" + std::to_string(mass_[i].size()) +
                              " vertices known, " + std::to_string(c.first_new_vertex) + " + " +
                              std::to_string(c.origins.size()) + " in the change, " + std::to_string(nv) +
                              " in the mesh)");
    mass_[i].resize(nv, 0.0);
    particle_of_[i].resize(nv, -1);
    vx_[i].resize(nv);
    vv_[i].resize(nv);
    saved_[i].resize(nv, 0);
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
        const double share = 0.5 * w * mass_[i][src];
        mass_[i][src] -= share;
        mass_[i][v] += share;
        const bool known = saved_[i][src] == generation_;
        x += w * (known ? vx_[i][src] : row(placed, static_cast<int>(src)));
        if (known) vel += w * vv_[i][src];
      }
      vx_[i][v] = x;
      vv_[i][v] = vel;
      saved_[i][v] = generation_;
      const Eigen::Vector3d p = row(placed, static_cast<int>(v));
      // One ball per stretch of the wound: a new vertex farther than half a radius from the
      // centres so far.
      if (std::none_of(centers.begin(), centers.end(),
                       [&](int q) { return (row(placed, q) - p).norm() < 0.5 * margin_; }))
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
    vx_[i][v] = x_[static_cast<std::size_t>(u.particle)];
    vv_[i][v] = v_[static_cast<std::size_t>(u.particle)];
    saved_[i][v] = generation_;
    particle_of_[i][v] = -1;
  }
  members_.clear();
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
  std::vector<std::pair<int, int>> edges, bends;
  for (std::size_t i = 0; i < model.meshes.size(); ++i) {
    const mesh::Mesh& m = model.meshes[i];
    const surgery::MeshIndex& index = live.index().meshes[i];
    const mesh::RowMatrixXf<3>& placed = live.placement().positions[i];
    std::vector<int> faces;
    for (const Ball& b : balls_)
      if (b.mesh == static_cast<int>(i))
        index.bvh.faces_in_box(b.center(live.placement()) - Eigen::Vector3d::Constant(b.radius),
                               b.center(live.placement()) + Eigen::Vector3d::Constant(b.radius), faces);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    const auto inside = [&](const std::vector<Ball>& balls, const Eigen::Vector3d& p) {
      return std::any_of(balls.begin(), balls.end(), [&](const Ball& b) {
        return b.mesh == static_cast<int>(i) && (p - b.center(live.placement())).norm() <= b.radius;
      });
    };
    // Particles: one per welded class of the faces' corners.
    std::unordered_map<int, int> class_particle;
    const auto particle = [&](int v) {
      int& pv = particle_of_[i][static_cast<std::size_t>(v)];
      if (pv >= 0) return pv;
      const int rep = index.weld[static_cast<std::size_t>(v)];
      const auto [it, fresh] = class_particle.try_emplace(rep, static_cast<int>(x_.size()));
      if (fresh) {
        const Eigen::Vector3d at = row(placed, rep);
        const int known = saved_[i][static_cast<std::size_t>(rep)] == generation_ ? rep
                          : saved_[i][static_cast<std::size_t>(v)] == generation_  ? v
                                                                                    : -1;
        ref_.push_back({static_cast<int>(i), rep});
        x_.push_back(known >= 0 ? vx_[i][static_cast<std::size_t>(known)] : at);
        v_.push_back(known >= 0 ? vv_[i][static_cast<std::size_t>(known)] : Eigen::Vector3d::Zero());
        free_.push_back(inside(balls_, at) ? 1 : 0);
        attached_.push_back(inside(releases_, at) ? 0 : 1);
        particle_mass.push_back(0.0);
      }
      pv = it->second;
      members_.push_back({static_cast<int>(i), v, pv});
      particle_mass[static_cast<std::size_t>(pv)] += mass_[i][static_cast<std::size_t>(v)];
      return pv;
    };
    for (const int f : faces) {
      std::array<int, 3> corner{};
      for (int k = 0; k < 3; ++k) corner[static_cast<std::size_t>(k)] = particle(m.faces(f, k));
      for (int k = 0; k < 3; ++k) {
        const int a = corner[static_cast<std::size_t>(k)], b = corner[static_cast<std::size_t>((k + 1) % 3)];
        if (a != b) edges.emplace_back(std::min(a, b), std::max(a, b));
        // Bending across edge k, once per pair of region faces.
        const int g = index.neighbor[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
        if (g > f && std::binary_search(faces.begin(), faces.end(), g)) {
          const int kg = index.edge_across(f, k);
          if (kg < 0) continue;
          const int a2 = corner[static_cast<std::size_t>((k + 2) % 3)], b2 = particle(m.faces(g, (kg + 2) % 3));
          if (a2 != b2) bends.emplace_back(std::min(a2, b2), std::max(a2, b2));
        }
      }
    }
  }
  for (std::size_t p = 0; p < x_.size(); ++p)
    inverse_mass_.push_back(free_[p] != 0 && particle_mass[p] > 0 ? 1.0 / particle_mass[p] : 0.0);
  const auto add = [&](std::vector<std::pair<int, int>>& pairs, float scale, float compliance) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    for (const auto& [a, b] : pairs)
      if (inverse_mass_[static_cast<std::size_t>(a)] + inverse_mass_[static_cast<std::size_t>(b)] > 0)
        links_.push_back({a, b, scale, compliance});
  };
  // A piece the wound cut loose that no held particle holds through its links would fall away
  // for ever: its particles stay attached (it hangs on as surgery left it).
  mesh::UnionFind pieces(x_.size());
  for (const auto& [a, b] : edges) pieces.unite(a, b);
  std::vector<char> held(x_.size(), 0);
  for (std::size_t p = 0; p < x_.size(); ++p)
    if (free_[p] == 0 || attached_[p] != 0) held[static_cast<std::size_t>(pieces.find(static_cast<int>(p)))] = 1;
  for (std::size_t p = 0; p < x_.size(); ++p)
    if (held[static_cast<std::size_t>(pieces.find(static_cast<int>(p)))] == 0) attached_[p] = 1;
  add(edges, static_cast<float>(1 - options_.pretension), static_cast<float>(options_.stretch_compliance));
  add(bends, 1.0f, static_cast<float>(options_.bend_compliance));
}

// ---- Simulation ----

void Tissue::targets_in(const surgery::LiveModel& live, const anim::Pose& pose,
                        std::vector<Eigen::Vector3d>& out) const {
  const anim::RiggedModel& model = live.model();
  const std::vector<anim::SkinningPalette> p = surgery::palettes(model, pose);
  out.resize(x_.size());
  for (std::size_t k = 0; k < x_.size(); ++k) {
    const auto i = static_cast<std::size_t>(ref_[k].mesh);
    out[k] = skinned(model.meshes[i], p[i], ref_[k].vertex);
  }
}

void Tissue::substep(const std::vector<Eigen::Vector3d>& t, double h) {
  const std::size_t n = x_.size();
  std::vector<Eigen::Vector3d>& before = scratch_;
  before = x_;
  for (std::size_t p = 0; p < n; ++p) {
    if (free_[p] == 0) {
      x_[p] = t[p];
      continue;
    }
    v_[p] += h * options_.gravity;
    x_[p] += h * v_[p];
  }
  // One Gauss-Seidel pass per substep (small steps): λ starts at 0 each substep.
  const double attach = options_.attachment_compliance / (h * h);
  for (std::size_t p = 0; p < n; ++p) {
    if (free_[p] == 0 || attached_[p] == 0) continue;
    const Eigen::Vector3d d = x_[p] - t[p];
    x_[p] -= d * (inverse_mass_[p] / (inverse_mass_[p] + attach));
  }
  for (const Link& l : links_) {
    const auto a = static_cast<std::size_t>(l.a), b = static_cast<std::size_t>(l.b);
    const Eigen::Vector3d d = x_[a] - x_[b];
    const double len = d.norm(), w = inverse_mass_[a] + inverse_mass_[b];
    if (!(len > 0)) continue;
    const double c = len - l.scale * (t[a] - t[b]).norm();
    const double dl = -c / (w + l.compliance / (h * h));
    const Eigen::Vector3d g = d / len;
    x_[a] += (inverse_mass_[a] * dl) * g;
    x_[b] -= (inverse_mass_[b] * dl) * g;
  }
  const double keep = std::exp(-options_.damping * h);
  for (std::size_t p = 0; p < n; ++p) v_[p] = free_[p] != 0 ? Eigen::Vector3d((x_[p] - before[p]) * (keep / h)) : Eigen::Vector3d::Zero();
}

void Tissue::step(const surgery::LiveModel& live, const anim::Pose& pose, double dt) {
  if (!(dt >= 0) || !std::isfinite(dt)) throw InvalidInputError("tissue: step: dt must be a finite number >= 0");
  if (x_.empty()) return;
  std::vector<Eigen::Vector3d> to;
  targets_in(live, pose, to);
  const std::vector<Eigen::Vector3d> from = have_targets_ ? previous_target_ : to;
  const double h = options_.substep;
  const auto steps = static_cast<long>(std::floor((dt + carried_) / h));
  const std::vector<Eigen::Vector3d> x0 = x_, v0 = v_;
  std::vector<Eigen::Vector3d> t(to.size());
  for (long s = 1; s <= steps; ++s) {
    const double a = static_cast<double>(s) / static_cast<double>(steps);
    for (std::size_t p = 0; p < t.size(); ++p) t[p] = (1 - a) * from[p] + a * to[p];
    substep(t, h);
  }
  for (std::size_t p = 0; p < x_.size(); ++p)
    if (!x_[p].allFinite() || (x_[p] - to[p]).norm() > 10 * diagonal_) {
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
  for (const Member& u : members_)
    out[static_cast<std::size_t>(u.mesh)].row(u.vertex) = x_[static_cast<std::size_t>(u.particle)].transpose().cast<float>();
  return out;
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
