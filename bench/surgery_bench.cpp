// Surgery on skinned models, operation only (the model is loaded and placed once): cut, tear and
// drill, with CGA predicates (X·Π, −2 X·S − (X·Π)²) against the same operation with Euclidean
// predicates in the same binary, on CesiumMan (about the seed's 3k-vertex arm), ogre (124k
// faces, when ../shared is present) and CesiumMan subdivided to over a million faces.
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <utility>
#include <string>
#include <vector>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/tear.hpp"
#include "cgamesh/surgery/surface_index.hpp"

namespace {

using namespace cgamesh;

struct Subject {
  anim::RiggedModel model;
  surgery::Placement placement;
  Eigen::Vector3d centre;
};

Subject make_subject(anim::RiggedModel model, double time) {
  Subject s;
  s.model = std::move(model);
  const anim::Pose pose = s.model.clips.empty()
                              ? anim::rest_pose(s.model.skeleton)
                              : anim::sample(s.model.skeleton, s.model.clips[0], time, anim::BlendMode::format);
  s.placement = surgery::place(s.model, pose);
  s.centre = s.placement.positions[0].colwise().mean().cast<double>().transpose();
  return s;
}

const Subject& cesium() {
  static const Subject s = make_subject(io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb"), 0.5);
  return s;
}

const Subject* ogre() {
  static const std::filesystem::path path = std::string(CGAMESH_SHARED_DATA) + "/meshes/ogre.obj";
  static const Subject* s = std::filesystem::exists(path) ? new Subject(make_subject(io::load_model(path), 0)) : nullptr;
  return s;
}

const Subject& million() {
  static const Subject s = [] {
    anim::RiggedModel m = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb");
    while (m.meshes[0].face_count() < 1'000'000) m.meshes[0] = mesh::subdivide_midpoint(m.meshes[0]);
    return make_subject(std::move(m), 0.5);
  }();
  return s;
}

/// Untimed runs before the timed ones, so that caches, branch predictors and the allocator's
/// free lists settle as in repeated use (an interactive session's); a few for the large models,
/// whose runs are long.
int warm_up_runs(const Subject& s) { return s.model.meshes[0].face_count() < 100'000 ? 20 : 2; }

/// False, with the benchmark skipped, when the model is missing (../shared/data not present).
bool present(benchmark::State& state, const Subject* s) {
  if (s == nullptr) state.SkipWithError("model not found (../shared/data is not present)");
  return s != nullptr;
}

/// Predicates of a benchmark's first argument: 0 cga, 1 euclidean.
surgery::Predicates predicates_of(const benchmark::State& state) {
  return state.range(0) == 0 ? surgery::Predicates::cga : surgery::Predicates::euclidean;
}

/// A slanted plane through the centre of the placed mesh.
cga::Vector<double> slanted_plane(const Subject& s) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, 1, 0.1).normalized();
  return cga::plane(n, n.dot(s.centre));
}

/// Tip and base of a slanted drill axis through the centre of the placed mesh of size `size`.
std::pair<Eigen::Vector3d, Eigen::Vector3d> slanted_axis(const Subject& s, double size) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 0.2, 0.1).normalized();
  return {s.centre + size * axis, s.centre - size * axis};
}

/// A stroke of 3 blade positions over the front of the placed mesh of size `size`: the blade
/// points from in front of the body at its centre and moves sideways and up by 4 % of the size.
std::vector<surgery::Scalpel> front_stroke(const Subject& s, double size) {
  const Eigen::Vector3d front = Eigen::Vector3d(0.1, 0.1, 1).normalized(), move = Eigen::Vector3d(-0.5, 1, 0).normalized();
  std::vector<surgery::Scalpel> steps;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d c = s.centre + 0.02 * size * i * move;
    steps.push_back({c + size * front, c});
  }
  return steps;
}

/// Cuts through the centre of the placed mesh with a slanted plane.
void cut(benchmark::State& state, const Subject* s) {
  if (!present(state, s)) return;
  surgery::CutOptions options;
  options.predicates = predicates_of(state);
  options.cap = state.range(1) != 0;
  const cga::Vector<double> plane = slanted_plane(*s);
  int faces = 0;
  const auto run = [&] {
    surgery::ModelCut c = surgery::cut(s->model, s->placement, plane, options);
    faces = c.faces_in;
    benchmark::DoNotOptimize(c.pieces[0].meshes.data());
  };
  for (int i = 0; i < warm_up_runs(*s); ++i) run();
  for (auto _ : state) run();
  state.counters["faces"] = faces;
  state.SetLabel(std::string(state.range(0) == 0 ? "cga" : "euclidean") + (options.cap ? " cap" : ""));
}

void BM_CutCesiumMan(benchmark::State& state) { cut(state, &cesium()); }
void BM_CutOgre(benchmark::State& state) { cut(state, ogre()); }
void BM_CutMillion(benchmark::State& state) { cut(state, &million()); }

/// Drills through the centre of the placed mesh along a slanted axis, with a radius of 2% of
/// the mesh's size; the SurfaceIndex is built once, outside the timed loop (as an interactive
/// tool would keep it per pose).
void drill(benchmark::State& state, const Subject* s) {
  if (!present(state, s)) return;
  const surgery::SurfaceIndex index = surgery::SurfaceIndex::build(s->model, s->placement);
  surgery::DrillOptions options;
  options.predicates = predicates_of(state);
  const double size = index.meshes[0].bvh.diagonal();
  const auto [tip, base] = slanted_axis(*s, size);
  surgery::ModelDrill d;
  const auto run = [&] {
    d = surgery::drill(s->model, s->placement, index, tip, base, 0.02 * size, options);
    benchmark::DoNotOptimize(d.model.meshes.data());
  };
  for (int i = 0; i < warm_up_runs(*s); ++i) run();
  for (auto _ : state) run();
  state.counters["faces"] = d.faces_in;
  state.counters["affected"] = d.faces_affected;
  state.counters["rim_points"] = d.intersection_points;
  state.SetLabel(state.range(0) == 0 ? "cga" : "euclidean");
}

void BM_DrillCesiumMan(benchmark::State& state) { drill(state, &cesium()); }
void BM_DrillOgre(benchmark::State& state) { drill(state, ogre()); }
void BM_DrillMillion(benchmark::State& state) { drill(state, &million()); }

/// Tears along front_stroke(); the SurfaceIndex is built once, outside the timed loop.
void tear(benchmark::State& state, const Subject* s) {
  if (!present(state, s)) return;
  const surgery::SurfaceIndex index = surgery::SurfaceIndex::build(s->model, s->placement);
  surgery::TearOptions options;
  options.predicates = predicates_of(state);
  options.open = 0.002 * index.meshes[0].bvh.diagonal();
  const std::vector<surgery::Scalpel> steps = front_stroke(*s, index.meshes[0].bvh.diagonal());
  surgery::ModelTear t;
  try {
    for (int i = 0; i < warm_up_runs(*s); ++i) t = surgery::tear(s->model, s->placement, index, steps, options);
  } catch (const Error& e) {
    state.SkipWithError(e.what());
    return;
  }
  for (auto _ : state) {
    t = surgery::tear(s->model, s->placement, index, steps, options);
    benchmark::DoNotOptimize(t.model.meshes.data());
  }
  state.counters["faces"] = t.faces_in;
  state.counters["path_points"] = t.intersection_points;
  state.counters["faces_split"] = t.faces_split;
  state.SetLabel(state.range(0) == 0 ? "cga" : "euclidean");
}

void BM_TearCesiumMan(benchmark::State& state) { tear(state, &cesium()); }
void BM_TearOgre(benchmark::State& state) { tear(state, ogre()); }
void BM_TearMillion(benchmark::State& state) { tear(state, &million()); }

// ---- in place (LiveModel) ------------------------------------------------------------------
// The same operations at the same places, editing a LiveModel where it is instead of returning a
// new model: each iteration operates on a fresh copy of the placed, indexed model (copied while
// the timer is paused), so it times exactly the operation the copying benchmark above times.

/// Times operate(live) on a fresh copy of `s` per iteration, by the clock around it (manual
/// time: PauseTiming/ResumeTiming cost more than a small operation).
template <class Operate>
void in_place(benchmark::State& state, const Subject* s, const Operate& operate) {
  if (!present(state, s)) return;
  const surgery::LiveModel original(s->model, s->placement);
  surgery::LiveModel live(original);
  for (int i = 0; i < warm_up_runs(*s); ++i) {
    live = original;
    operate(live);
  }
  for (auto _ : state) {
    live = original;  // the operated copy is freed, and a fresh one made, untimed
    const auto start = std::chrono::steady_clock::now();
    operate(live);
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  state.SetLabel(state.range(0) == 0 ? "cga in place" : "euclidean in place");
}

void cut_in_place(benchmark::State& state, const Subject* s) {
  surgery::CutOptions options;
  options.predicates = predicates_of(state);
  in_place(state, s, [&](surgery::LiveModel& live) {
    benchmark::DoNotOptimize(surgery::cut(live, slanted_plane(*s), options));
  });
}

void tear_in_place(benchmark::State& state, const Subject* s) {
  surgery::TearOptions options;
  options.predicates = predicates_of(state);
  in_place(state, s, [&](surgery::LiveModel& live) {
    options.open = 0.002 * live.index().meshes[0].bvh.diagonal();
    benchmark::DoNotOptimize(surgery::tear(live, front_stroke(*s, live.index().meshes[0].bvh.diagonal()), options));
  });
}

void drill_in_place(benchmark::State& state, const Subject* s) {
  surgery::DrillOptions options;
  options.predicates = predicates_of(state);
  in_place(state, s, [&](surgery::LiveModel& live) {
    const double size = live.index().meshes[0].bvh.diagonal();
    const auto [tip, base] = slanted_axis(*s, size);
    benchmark::DoNotOptimize(surgery::drill(live, tip, base, 0.02 * size, options));
  });
}

void BM_CutInPlaceCesiumMan(benchmark::State& state) { cut_in_place(state, &cesium()); }
void BM_CutInPlaceOgre(benchmark::State& state) { cut_in_place(state, ogre()); }
void BM_CutInPlaceMillion(benchmark::State& state) { cut_in_place(state, &million()); }
void BM_TearInPlaceCesiumMan(benchmark::State& state) { tear_in_place(state, &cesium()); }
void BM_TearInPlaceOgre(benchmark::State& state) { tear_in_place(state, ogre()); }
void BM_TearInPlaceMillion(benchmark::State& state) { tear_in_place(state, &million()); }
void BM_DrillInPlaceCesiumMan(benchmark::State& state) { drill_in_place(state, &cesium()); }
void BM_DrillInPlaceOgre(benchmark::State& state) { drill_in_place(state, ogre()); }
void BM_DrillInPlaceMillion(benchmark::State& state) { drill_in_place(state, &million()); }

void variants(benchmark::internal::Benchmark* b) {
  for (int cap : {0, 1})
    for (int predicates : {0, 1}) b->Args({predicates, cap});
}

/// The ~5k-face model's operations take tens of microseconds, less than this shared machine's
/// slow spells last: each is timed alone, many times, and reported by the median of the runs.
void single_runs(benchmark::internal::Benchmark* b) { b->Iterations(1)->Repetitions(301)->ReportAggregatesOnly(true); }

}  // namespace

BENCHMARK(BM_CutCesiumMan)->Apply(variants)->Apply(single_runs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CutOgre)->Apply(variants)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CutMillion)->Apply(variants)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TearCesiumMan)->Arg(0)->Arg(1)->Apply(single_runs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TearOgre)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TearMillion)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DrillCesiumMan)->Arg(0)->Arg(1)->Apply(single_runs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DrillOgre)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DrillMillion)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CutInPlaceCesiumMan)->Arg(0)->Arg(1)->UseManualTime()->Apply(single_runs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CutInPlaceOgre)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CutInPlaceMillion)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TearInPlaceCesiumMan)->Arg(0)->Arg(1)->UseManualTime()->Apply(single_runs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TearInPlaceOgre)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TearInPlaceMillion)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DrillInPlaceCesiumMan)->Arg(0)->Arg(1)->UseManualTime()->Apply(single_runs)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_DrillInPlaceOgre)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DrillInPlaceMillion)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);
