// Per-frame skinning, every mode over the same data, in one binary: CesiumMan as shipped and
// subdivided (1 -> 4 midpoint splits) to over a million vertices. The palette (one versor
// sandwich map or matrix per joint) is rebuilt every frame, as an animation would; the output
// arrays are kept from frame to frame, as a renderer would.
//
// The bound: a streaming loop over the same 48 bytes per vertex (rest position, 4 joints, 4
// weights in, a position out) with next to no arithmetic. Each skinning benchmark reports it
// (stream_vps, vertices per second, timed in the same run) and its own fraction of it
// (of_stream = stream time / frame time; 1 = as fast as memory allows).
#include <algorithm>
#include <chrono>
#include <map>
#include <string>
#include <thread>

#include <benchmark/benchmark.h>

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

/// One pass of the bound's loop over vertices [begin, end), in chunks of 1024 vertices: the bits
/// of the chunk's weights and joints or-ed together (vectorised reductions), then y = x + (that
/// & 1) for its positions.
void stream(const mesh::Mesh& m, float* out, Eigen::Index begin, Eigen::Index end) {
  const float* x = m.positions.data();
  const auto* w = reinterpret_cast<const std::uint32_t*>(m.skin.weights.data());
  const std::uint16_t* j = m.skin.joints.data();
  for (Eigen::Index b = begin; b < end; b += 1024) {
    const Eigen::Index e = std::min(end, b + 1024);
    std::uint32_t bits = 0;
    std::uint16_t joint_bits = 0;
    for (Eigen::Index k = 4 * b; k < 4 * e; ++k) bits |= w[k];
    for (Eigen::Index k = 4 * b; k < 4 * e; ++k) joint_bits = static_cast<std::uint16_t>(joint_bits | j[k]);
    const float add = static_cast<float>((bits ^ joint_bits) & 1u);
    for (Eigen::Index k = 3 * b; k < 3 * e; ++k) out[k] = x[k] + add;
  }
}
void stream(const mesh::Mesh& m, float* out) { stream(m, out, 0, m.vertex_count()); }

/// Seconds of one streaming pass over m: the median of 31, measured once per mesh and run.
double stream_seconds(const mesh::Mesh& m) {
  static std::map<const mesh::Mesh*, double> cache;
  if (const auto it = cache.find(&m); it != cache.end()) return it->second;
  mesh::RowMatrixXf<3> out(m.vertex_count(), 3);
  std::vector<double> t;
  for (int r = 0; r < 31; ++r) {
    const auto start = std::chrono::steady_clock::now();
    stream(m, out.data());
    benchmark::ClobberMemory();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::nth_element(t.begin(), t.begin() + 15, t.end());
  return cache[&m] = t[15];
}

void report(benchmark::State& state, const mesh::Mesh& m) {
  state.SetItemsProcessed(state.iterations() * m.vertex_count());
  const double bound = stream_seconds(m);
  state.counters["vertices"] = static_cast<double>(m.vertex_count());
  state.counters["stream_vps"] = static_cast<double>(m.vertex_count()) / bound;
  state.counters["of_stream"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * bound, benchmark::Counter::kIsRate);
}

// Args: mode (0 cga, 1 versor, 2 matrix, 3 dqs), threads (0 = all), normals (0: positions
// only, 1: and normals), kernel (0 automatic, 1 scalar, 2 vector, 3 avx2, 4 avx512), stores (0 automatic,
// 1 caching, 2 streaming).
void skin_frame(benchmark::State& state, const mesh::Mesh& m) {
  const auto mode = static_cast<anim::SkinningMode>(state.range(0));
  const anim::SkinningOptions options{.threads = static_cast<int>(state.range(1)),
                                      .kernel = static_cast<anim::SkinningKernel>(state.range(3)),
                                      .stores = static_cast<anim::SkinningStores>(state.range(4))};
  if (!anim::kernel_available(options.kernel)) {
    state.SkipWithError("kernel not available on this processor");
    return;
  }
  const Scene& s = scene();
  mesh::RowMatrixXf<3> positions, normals;
  stream_seconds(m);
  for (auto _ : state) {
    const anim::SkinningPalette palette = anim::make_palette(m, s.gv, s.gm, mode);
    anim::skin_into(m, palette, positions, state.range(2) != 0 ? &normals : nullptr, options);
    benchmark::DoNotOptimize(positions.data());
    benchmark::DoNotOptimize(normals.data());
  }
  report(state, m);
}

// Arg: threads (1, or 2: two threads streaming one half each, what two cores' memory allows).
void stream_frame(benchmark::State& state, const mesh::Mesh& m) {
  mesh::RowMatrixXf<3> out(m.vertex_count(), 3);
  const Eigen::Index n = m.vertex_count(), half = n / 2;
  for (auto _ : state) {
    if (state.range(0) == 1) {
      stream(m, out.data());
    } else {
      std::thread other([&] { stream(m, out.data(), half, n); });
      stream(m, out.data(), 0, half);
      other.join();
    }
    benchmark::ClobberMemory();
  }
  report(state, m);
}

// The per-frame palette alone (CesiumMan, 19 joints): part of every skinning frame above.
void BM_PaletteCesiumMan(benchmark::State& state) {
  const Scene& s = scene();
  for (auto _ : state) {
    const anim::SkinningPalette palette =
        anim::make_palette(s.model.meshes[0], s.gv, s.gm, static_cast<anim::SkinningMode>(state.range(0)));
    benchmark::DoNotOptimize(palette);
  }
}
BENCHMARK(BM_PaletteCesiumMan)->DenseRange(0, 3)->ArgName("mode");

void BM_SkinCesiumMan(benchmark::State& state) { skin_frame(state, scene().model.meshes[0]); }
void BM_SkinMillion(benchmark::State& state) { skin_frame(state, scene().big); }
void BM_StreamBoundCesiumMan(benchmark::State& state) { stream_frame(state, scene().model.meshes[0]); }
void BM_StreamBoundMillion(benchmark::State& state) { stream_frame(state, scene().big); }

void modes(benchmark::internal::Benchmark* b) {
  for (int mode = 0; mode < 4; ++mode) {
    b->Args({mode, 1, 0, 0, 0});  // one core, the fastest kernel here
    b->Args({mode, 1, 1, 0, 0});  // with normals
    b->Args({mode, 1, 0, 1, 0});  // the scalar kernel
    b->Args({mode, 1, 0, 3, 0});  // avx2, where automatic takes avx512
    b->Args({mode, 0, 0, 0, 0});  // every core
    b->Args({mode, 1, 0, 0, 1});  // ordinary stores whatever the size
    b->Args({mode, 1, 1, 0, 1});  // and with normals
  }
  b->ArgNames({"mode", "threads", "normals", "kernel", "stores"});
}
BENCHMARK(BM_StreamBoundCesiumMan)->Arg(1)->ArgName("threads")->UseRealTime();
BENCHMARK(BM_SkinCesiumMan)->Apply(modes)->UseRealTime();
BENCHMARK(BM_StreamBoundMillion)->Arg(1)->Arg(2)->ArgName("threads")->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SkinMillion)->Apply(modes)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
