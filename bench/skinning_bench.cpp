// Per-frame skinning, every mode over the same data, in one binary: CesiumMan as shipped and
// subdivided (1 -> 4 midpoint splits) to over a million vertices. The palette (one versor
// sandwich map or matrix per joint) is rebuilt every frame, as an animation would.
#include <benchmark/benchmark.h>

#include <string>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"

namespace {

using namespace cgamesh;

struct Scene {
  anim::RiggedModel model;
  mesh::Mesh big;
  std::vector<cga::Versor<double>> gv;
  std::vector<Eigen::Matrix4d> gm;
};

const Scene& scene() {
  static const Scene s = [] {
    Scene out;
    out.model = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb");
    out.big = out.model.meshes[0];
    while (out.big.vertex_count() < 1'000'000) out.big = mesh::subdivide_midpoint(out.big);
    const anim::Pose pose = anim::sample(out.model.skeleton, out.model.clips[0], 0.5, anim::BlendMode::format);
    out.gv = anim::global_versors(out.model.skeleton, pose);
    out.gm = anim::global_matrices(out.model.skeleton, pose);
    return out;
  }();
  return s;
}

void skin_frame(benchmark::State& state, const mesh::Mesh& m) {
  const auto mode = static_cast<anim::SkinningMode>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const Scene& s = scene();
  for (auto _ : state) {
    const anim::SkinningPalette palette = anim::make_palette(m, s.gv, s.gm, mode);
    mesh::RowMatrixXf<3> out = anim::skin(m, palette, threads);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * m.vertex_count());
  state.counters["vertices"] = static_cast<double>(m.vertex_count());
}

void BM_SkinCesiumMan(benchmark::State& state) { skin_frame(state, scene().model.meshes[0]); }
void BM_SkinMillion(benchmark::State& state) { skin_frame(state, scene().big); }

// Args: mode (0 cga, 1 versor, 2 matrix, 3 dqs), threads (0 = all).
void modes(benchmark::internal::Benchmark* b) {
  for (int threads : {1, 0})
    for (int mode = 0; mode < 4; ++mode) b->Args({mode, threads});
  b->ArgNames({"mode", "threads"});
}
BENCHMARK(BM_SkinCesiumMan)->Apply(modes)->UseRealTime();
BENCHMARK(BM_SkinMillion)->Apply(modes)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
