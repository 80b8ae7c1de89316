// One 1280×960 picture (upload, draw with 4× multisampling, read back) of CesiumMan and of
// CesiumMan subdivided to over a million faces, on whatever EGL gives (llvmpipe without a GPU).
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"
#include "cgamesh/render/headless_context.hpp"
#include "cgamesh/render/model_scene.hpp"
#include "cgamesh/render/renderer.hpp"

namespace {

using namespace cgamesh;

struct Gl {
  render::HeadlessContext context;
  render::Renderer renderer;
};

Gl& gl() {
  static Gl g;
  return g;
}

render::Scene scene_of(int min_faces) {
  anim::RiggedModel m = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb");
  while (m.meshes[0].face_count() < min_faces) m.meshes[0] = mesh::subdivide_midpoint(m.meshes[0]);
  const render::ModelInstance in{&m, anim::sample(m.skeleton, m.clips[0], 0.5, anim::BlendMode::format)};
  return render::model_scene(std::span(&in, 1), {});
}

void picture(benchmark::State& state, const render::Scene& scene) {
  const render::RenderOptions options;  // 1280×960, 4 samples
  const render::Camera camera = render::frame(scene.bounds(), render::View::iso, 35, 1280.0 / 960.0);
  Gl& g = gl();
  for (auto _ : state) benchmark::DoNotOptimize(g.renderer.render(scene, camera, options));
  state.counters["faces"] = static_cast<double>(scene.meshes[0].faces.rows());
}

void BM_RenderCesiumMan(benchmark::State& state) {
  static const render::Scene scene = scene_of(0);
  picture(state, scene);
}
BENCHMARK(BM_RenderCesiumMan)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_RenderMillion(benchmark::State& state) {
  static const render::Scene scene = scene_of(1'000'000);
  picture(state, scene);
}
BENCHMARK(BM_RenderMillion)->Unit(benchmark::kMillisecond)->UseRealTime();

/// What `cgamesh render` pays once: an EGL context and the shaders compiled.
void BM_RenderSetup(benchmark::State& state) {
  for (auto _ : state) {
    render::HeadlessContext context;
    render::Renderer renderer;
    benchmark::DoNotOptimize(&renderer);
  }
}
BENCHMARK(BM_RenderSetup)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
