// The C ABI's cost (issue #35): what a call through cgamesh.h adds to the library call it wraps,
// in the same binary. A trivial call (three counts) against reading the same counts in C++;
// skinning CesiumMan into a caller's buffer against anim::skin_into; an in-place cut against
// surgery::cut on a LiveModel. The target: ≤ 1 µs of overhead per call.
#include <chrono>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/cgamesh.h"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/placement.hpp"

namespace {

using namespace cgamesh;

const std::string kModel = std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb";

struct CModel {
  cgamesh_model* model = nullptr;
  cgamesh_pose* pose = nullptr;
  CModel() {
    if (cgamesh_model_load(kModel.c_str(), &model) != CGAMESH_OK || cgamesh_pose_create(model, &pose) != CGAMESH_OK ||
        cgamesh_pose_sample(pose, model, 0, 0.5, CGAMESH_BLEND_FORMAT) != CGAMESH_OK)
      model = nullptr;
  }
  ~CModel() {
    cgamesh_pose_free(pose);
    cgamesh_model_free(model);
  }
};

void BM_CAbiCall(benchmark::State& state) {
  CModel m;
  cgamesh_model_counts counts;
  for (auto _ : state) {
    benchmark::DoNotOptimize(cgamesh_model_counts_get(m.model, &counts));
    benchmark::DoNotOptimize(counts);
  }
}

void BM_CppCall(benchmark::State& state) {
  const anim::RiggedModel model = io::load_model(kModel);
  const anim::RiggedModel* p = &model;
  benchmark::DoNotOptimize(p);
  for (auto _ : state) {
    int counts[3] = {static_cast<int>(p->meshes.size()), p->skeleton.size(), static_cast<int>(p->clips.size())};
    benchmark::DoNotOptimize(counts);
  }
}

void BM_CAbiSkinCesiumMan(benchmark::State& state) {
  CModel m;
  int32_t v = 0;
  cgamesh_model_mesh_size(m.model, 0, &v, nullptr);
  std::vector<float> positions(3 * static_cast<std::size_t>(v)), normals(positions.size());
  for (auto _ : state)
    if (cgamesh_model_skin(m.model, m.pose, 0, CGAMESH_SKINNING_CGA, positions.data(), positions.size(), normals.data(),
                           normals.size()) != CGAMESH_OK)
      state.SkipWithError(cgamesh_last_error());
}

void BM_CppSkinCesiumMan(benchmark::State& state) {
  const anim::RiggedModel model = io::load_model(kModel);
  const anim::Pose pose = anim::sample(model.skeleton, model.clips[0], 0.5, anim::BlendMode::format);
  mesh::RowMatrixXf<3> positions, normals;
  const mesh::Mesh& m = model.meshes[0];
  for (auto _ : state) {
    const auto gv = anim::global_versors(model.skeleton, pose);
    const auto gm = anim::global_matrices(model.skeleton, pose);
    anim::skin_into(m, anim::make_palette(m, gv, gm, anim::SkinningMode::cga, anim::morph_weights(pose, m)), positions,
                    &normals);
    benchmark::DoNotOptimize(positions.data());
  }
}

/// The cut alone is timed; a fresh live model is made for each (untimed).
void BM_CAbiCutCesiumMan(benchmark::State& state) {
  CModel m;
  const double normal[3] = {0, 1, 0};
  for (auto _ : state) {
    cgamesh_live* live = nullptr;
    cgamesh_live_create(m.model, m.pose, &live);
    const auto start = std::chrono::steady_clock::now();
    cgamesh_change* change = nullptr;
    if (cgamesh_live_cut(live, normal, 0.9, &change) != CGAMESH_OK) state.SkipWithError(cgamesh_last_error());
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    cgamesh_change_free(change);
    cgamesh_live_free(live);
  }
}

void BM_CppCutCesiumMan(benchmark::State& state) {
  const anim::RiggedModel model = io::load_model(kModel);
  const anim::Pose pose = anim::sample(model.skeleton, model.clips[0], 0.5, anim::BlendMode::format);
  const surgery::Placement placed = surgery::place(model, pose);
  const cga::Vector<double> plane = surgery::cut_plane({0, 1, 0}, 0.9);
  for (auto _ : state) {
    surgery::LiveModel live(model, placed);
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(surgery::cut(live, plane));
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
}

BENCHMARK(BM_CAbiCall);
BENCHMARK(BM_CppCall);
BENCHMARK(BM_CAbiSkinCesiumMan)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CppSkinCesiumMan)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CAbiCutCesiumMan)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CppCutCesiumMan)->UseManualTime()->Unit(benchmark::kMicrosecond);

}  // namespace
