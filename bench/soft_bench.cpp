// Living tissue (soft/tissue.hpp): one frame (1/90 s of simulated time, the default substep of
// 1/900 s: 10 substeps) on CesiumMan all simulated, and a wound's region on CesiumMan
// subdivided to 1.2 M faces; how a step's cost grows with the region and with the mesh (a tear
// step while dragging with the tissue's update: session_bench.cpp, BM_DragStepTissue*). Baseline in the same binary: Bullet 3.24's
// btSoftBody on the same welded mesh with the same links and one iteration per substep.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#ifdef CGAMESH_BENCH_BULLET
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletSoftBody/btDefaultSoftBodySolver.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#endif

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"
#include "cgamesh/soft/tissue.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/tear.hpp"

namespace {

using namespace cgamesh;

constexpr double kFrame = 1.0 / 90.0;

/// CesiumMan subdivided `levels` times (4672 faces × 4^levels), placed at t = 0.5 s, with the
/// poses of 90 frames of its clip from there.
struct Subject {
  std::unique_ptr<surgery::LiveModel> live;
  std::vector<anim::Pose> poses;
  Eigen::Vector3d centre;
  double diagonal = 0;
};

const Subject& subject(int levels) {
  static std::array<std::unique_ptr<Subject>, 5> cache;
  std::unique_ptr<Subject>& s = cache.at(static_cast<std::size_t>(levels));
  if (s) return *s;
  anim::RiggedModel m = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb");
  for (int l = 0; l < levels; ++l) m.meshes[0] = mesh::subdivide_midpoint(m.meshes[0]);
  s = std::make_unique<Subject>();
  for (int k = 0; k < 90; ++k)
    s->poses.push_back(anim::sample(m.skeleton, m.clips[0], 0.5 + k * kFrame, anim::BlendMode::format));
  surgery::Placement placed = surgery::place(m, s->poses[0]);
  s->live = std::make_unique<surgery::LiveModel>(std::move(m), std::move(placed));
  s->centre = s->live->placement().positions[0].colwise().mean().cast<double>().transpose();
  s->diagonal = s->live->index().meshes[0].bvh.diagonal();
  return *s;
}

/// A scalpel stroke of `steps` blade positions across the chest (the front, +z), moving up by
/// 1 % of the size per step.
std::vector<surgery::Scalpel> chest_stroke(const Subject& s, int steps) {
  std::vector<surgery::Scalpel> out;
  const Eigen::Vector3d front(0, 0, 1), up = Eigen::Vector3d(-0.3, 1, 0).normalized();
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector3d c = s.centre + Eigen::Vector3d(0, 0.1 * s.diagonal, 0) + 0.01 * s.diagonal * i * up;
    out.push_back({c + s.diagonal * front, c});
  }
  return out;
}

/// Steps `tissue` a frame per iteration through the clip (the poses of the subject).
void frames(benchmark::State& state, const Subject& s, surgery::LiveModel& live, soft::Tissue& tissue) {
  for (int k = 0; k < 30; ++k) tissue.step(live, s.poses[static_cast<std::size_t>(k)], kFrame);
  std::size_t k = 0;
  for (auto _ : state) {
    tissue.step(live, s.poses[k], kFrame);
    k = (k + 1) % s.poses.size();
  }
  state.counters["particles"] = static_cast<double>(tissue.free_particles());
  state.counters["links"] = static_cast<double>(tissue.links());
  state.counters["faces"] = static_cast<double>(live.model().meshes[0].face_count());
}

/// The whole of CesiumMan simulated (the region holds every face).
void BM_TissueFrameWholeCesiumMan(benchmark::State& state) {
  const Subject& s = subject(0);
  surgery::LiveModel live = *s.live;
  soft::TissueOptions options;
  options.max_particles = 0;
  soft::Tissue tissue(live, options);
  tissue.select(live, 0, s.centre, 2 * s.diagonal);
  frames(state, s, live, tissue);
}

/// A tear's wound on CesiumMan subdivided `range(0)` times, region `range(1)` % of the
/// diagonal (the default is 10 %), budget `range(2)` particles (0: none; the default is 2000).
void BM_TissueFrameWound(benchmark::State& state) {
  const Subject& s = subject(static_cast<int>(state.range(0)));
  surgery::LiveModel live = *s.live;
  soft::TissueOptions options;
  options.region_radius = static_cast<double>(state.range(1)) / 100.0 * s.diagonal;
  options.max_particles = static_cast<int>(state.range(2));
  soft::Tissue tissue(live, options);
  const surgery::LiveTear t = surgery::tear(live, chest_stroke(s, 3));
  tissue.follow(live, std::span(&t.change, 1));
  frames(state, s, live, tissue);
}

#ifdef CGAMESH_BENCH_BULLET
/// Bullet's btSoftBody on CesiumMan's welded surface with the links our tissue builds on it:
/// one per welded edge and one across each interior edge (between the opposite corners), the
/// same total mass (spread evenly), one position iteration per substep of 1/900 s, no collisions. Bullet has no
/// attachment to a moving skinned target; ours does that work besides.
void BM_BulletSoftBodyFrameWholeCesiumMan(benchmark::State& state) {
  const Subject& s = subject(0);
  const surgery::LiveModel& live = *s.live;
  const mesh::Mesh& m = live.model().meshes[0];
  const surgery::MeshIndex& index = live.index().meshes[0];
  const auto& placed = live.placement().positions[0];
  std::vector<int> node_of(index.weld.size(), -1);
  std::vector<btVector3> nodes;
  std::vector<btScalar> masses;
  for (std::size_t v = 0; v < index.weld.size(); ++v) {
    const auto rep = static_cast<std::size_t>(index.weld[v]);
    if (node_of[rep] < 0) {
      node_of[rep] = static_cast<int>(nodes.size());
      nodes.emplace_back(placed(static_cast<Eigen::Index>(rep), 0), placed(static_cast<Eigen::Index>(rep), 1),
                         placed(static_cast<Eigen::Index>(rep), 2));
      masses.push_back(0);
    }
    node_of[v] = node_of[rep];
  }
  std::vector<std::pair<int, int>> links;
  const soft::Tissue area_masses(live);
  for (Eigen::Index f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = node_of[static_cast<std::size_t>(m.faces(f, k))], b = node_of[static_cast<std::size_t>(m.faces(f, (k + 1) % 3))];
      if (a != b) links.emplace_back(std::min(a, b), std::max(a, b));
      const int g = index.neighbor[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
      if (g > f) {
        const int kg = index.edge_across(static_cast<int>(f), k);
        if (kg < 0) continue;
        const int a2 = node_of[static_cast<std::size_t>(m.faces(f, (k + 2) % 3))];
        const int b2 = node_of[static_cast<std::size_t>(m.faces(g, (kg + 2) % 3))];
        if (a2 != b2) links.emplace_back(std::min(a2, b2), std::max(a2, b2));
      }
    }
  std::sort(links.begin(), links.end());
  links.erase(std::unique(links.begin(), links.end()), links.end());
  std::fill(masses.begin(), masses.end(), static_cast<btScalar>(area_masses.total_mass() / static_cast<double>(nodes.size())));

  btSoftBodyRigidBodyCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher(&configuration);
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDefaultSoftBodySolver soft_solver;
  btSoftRigidDynamicsWorld world(&dispatcher, &broadphase, &solver, &configuration, &soft_solver);
  world.setGravity(btVector3(0, -9.81f, 0));
  btSoftBodyWorldInfo& info = world.getWorldInfo();
  info.m_gravity = btVector3(0, -9.81f, 0);
  info.m_sparsesdf.Initialize();
  auto body = std::make_unique<btSoftBody>(&info, static_cast<int>(nodes.size()), nodes.data(), masses.data());
  for (const auto& [a, b] : links) body->appendLink(a, b);
  body->m_cfg.piterations = 1;
  body->m_cfg.kDP = 0.005f;
  body->m_cfg.collisions = 0;
  world.addSoftBody(body.get());
  for (int k = 0; k < 30; ++k) world.stepSimulation(static_cast<btScalar>(kFrame), 10, static_cast<btScalar>(1.0 / 900.0));
  for (auto _ : state) world.stepSimulation(static_cast<btScalar>(kFrame), 10, static_cast<btScalar>(1.0 / 900.0));
  world.removeSoftBody(body.get());
  state.counters["particles"] = static_cast<double>(nodes.size());
  state.counters["links"] = static_cast<double>(links.size());
}
BENCHMARK(BM_BulletSoftBodyFrameWholeCesiumMan)->Unit(benchmark::kMicrosecond);
#endif

BENCHMARK(BM_TissueFrameWholeCesiumMan)->Unit(benchmark::kMicrosecond);
// The wound on 1.2 M faces with the default region (10 %) and budget; then the region growing
// with no budget (mesh fixed: 74.8 k faces), and the mesh growing with the region fixed (5 %, no
// budget).
BENCHMARK(BM_TissueFrameWound)
    ->ArgNames({"subdivisions", "region%", "budget"})
    ->Args({4, 10, 2000})
    ->Args({2, 2, 0})
    ->Args({2, 5, 0})
    ->Args({2, 10, 0})
    ->Args({2, 20, 0})
    ->Args({0, 5, 0})
    ->Args({1, 5, 0})
    ->Args({3, 5, 0})
    ->Args({4, 5, 0})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
