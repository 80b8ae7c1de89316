// The viewer's surgery while dragging: one tear step of a stroke (Session::stroke_step, in place
// on the LiveModel), on CesiumMan and on CesiumMan subdivided to over a million faces. A step
// must stay under 11 ms so that a drag never costs a 90 Hz frame. With living tissue on, the step
// and the tissue's update and frame (issue #34: ≤ 2 ms on 1.2 M faces).
#include <chrono>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"
#include "cgamesh/session/session.hpp"
#include "cgamesh/surgery/placement.hpp"

namespace {

using namespace cgamesh;
using session::Session;

anim::RiggedModel cesium_model(int min_faces) {
  anim::RiggedModel m = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb");
  while (m.meshes[0].face_count() < min_faces) m.meshes[0] = mesh::subdivide_midpoint(m.meshes[0]);
  return m;
}

/// Blade positions of a stroke across the front of the placed model, `spacing` model sizes apart.
std::vector<surgery::Scalpel> stroke(const anim::RiggedModel& m, const anim::Pose& pose, int steps, double spacing) {
  const surgery::Placement p = surgery::place(m, pose);
  const Eigen::Vector3d centre = p.positions[0].colwise().mean().cast<double>().transpose();
  const double size = (p.positions[0].colwise().maxCoeff() - p.positions[0].colwise().minCoeff()).norm();
  const Eigen::Vector3d front = Eigen::Vector3d(0.1, 0.1, 1).normalized(),
                        move = Eigen::Vector3d(-0.5, 1, 0).normalized();
  std::vector<surgery::Scalpel> out;
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector3d c = centre + spacing * size * i * move;
    out.push_back({c + size * front, c});
  }
  return out;
}

/// Times each stroke_step of a stroke replayed over and over (ended and undone, untimed, after
/// its last step); only the blade positions a first trial stroke accepted are used, so every
/// timed step tears.
/// With `tissue`, living tissue is on (soft/tissue.hpp, default options) and each timed step
/// is the tear step, the tissue following it, and one frame of the tissue (1/90 s).
void drag_step(benchmark::State& state, int min_faces, bool tissue = false) {
  Session session(cesium_model(min_faces));
  session.set_clip(0);
  session.set_time(0.5);
  if (tissue) session.set_tissue(soft::TissueOptions{});
  std::vector<surgery::Scalpel> blades;
  session.begin_stroke();
  for (const surgery::Scalpel& b : stroke(session.model(), session.pose(), 24, 0.01))
    if (session.stroke_step(b) || blades.empty()) blades.push_back(b);
  (void)session.end_stroke();
  (void)session.undo();
  if (blades.size() < 3) {
    state.SkipWithError("the stroke does not stay on the surface");
    return;
  }
  std::size_t next = 0;
  int dropped = 0;
  for (auto _ : state) {
    if (next == 0) {
      if (session.stroking()) {
        (void)session.end_stroke();
        (void)session.undo();
      }
      session.begin_stroke();
      (void)session.stroke_step(blades[next++]);
    }
    const auto start = std::chrono::steady_clock::now();
    const auto step = session.stroke_step(blades[next]);
    if (tissue) (void)session.step_tissue(1.0 / 90);
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    dropped += step ? 0 : 1;
    next = (next + 1) % blades.size();
  }
  state.counters["steps"] = static_cast<double>(blades.size() - 1);
  state.counters["dropped"] = dropped;
  long faces = 0;
  for (const auto& m : session.model().meshes) faces += m.face_count();
  state.counters["faces"] = static_cast<double>(faces);
  if (tissue) state.counters["particles"] = static_cast<double>(session.tissue()->free_particles());
}

void BM_DragStepCesiumMan(benchmark::State& state) { drag_step(state, 0); }
void BM_DragStepMillion(benchmark::State& state) { drag_step(state, 1'000'000); }

void BM_DragStepTissueCesiumMan(benchmark::State& state) { drag_step(state, 0, true); }
void BM_DragStepTissueMillion(benchmark::State& state) { drag_step(state, 1'000'000, true); }

BENCHMARK(BM_DragStepCesiumMan)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DragStepMillion)->UseManualTime()->Iterations(40)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DragStepTissueCesiumMan)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DragStepTissueMillion)->UseManualTime()->Iterations(40)->Unit(benchmark::kMillisecond);

}  // namespace
