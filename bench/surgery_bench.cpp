// Surgery on skinned models, operation only (the model is loaded and placed once): cut, with
// CGA predicates (X·Π) against the same cut with Euclidean predicates (n·x − d) in the same
// binary, on CesiumMan (about the seed's 3k-vertex arm), ogre (124k faces, when ../shared is
// present) and CesiumMan subdivided to over a million faces.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"
#include "cgamesh/surgery/cut.hpp"

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

/// Cuts through the centre of the placed mesh with a slanted plane.
void cut(benchmark::State& state, const Subject* s) {
  if (s == nullptr) {
    state.SkipWithError("model not found (../shared/data is not present)");
    return;
  }
  surgery::CutOptions options;
  options.predicates = state.range(0) == 0 ? surgery::Predicates::cga : surgery::Predicates::euclidean;
  options.cap = state.range(1) != 0;
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, 1, 0.1).normalized();
  const cga::Vector<double> plane = cga::plane(n, n.dot(s->centre));
  int faces = 0;
  for (auto _ : state) {
    surgery::ModelCut c = surgery::cut(s->model, s->placement, plane, options);
    faces = c.faces_in;
    benchmark::DoNotOptimize(c.pieces[0].meshes.data());
  }
  state.counters["faces"] = faces;
  state.SetLabel(std::string(state.range(0) == 0 ? "cga" : "euclidean") + (options.cap ? " cap" : ""));
}

void BM_CutCesiumMan(benchmark::State& state) { cut(state, &cesium()); }
void BM_CutOgre(benchmark::State& state) { cut(state, ogre()); }
void BM_CutMillion(benchmark::State& state) { cut(state, &million()); }

void variants(benchmark::internal::Benchmark* b) {
  for (int cap : {0, 1})
    for (int predicates : {0, 1}) b->Args({predicates, cap});
}

}  // namespace

BENCHMARK(BM_CutCesiumMan)->Apply(variants)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CutOgre)->Apply(variants)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CutMillion)->Apply(variants)->Unit(benchmark::kMillisecond);
