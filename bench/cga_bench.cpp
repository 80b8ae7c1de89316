// Benchmarks of the algebra core. The batch point transforms run the 3x4 matrix baseline in
// the same binary, so BENCHMARKS.md can report ratios that do not depend on the machine.
#include <benchmark/benchmark.h>

#include <cstddef>
#include <random>
#include <span>
#include <vector>

#include "cgamesh/cga.hpp"

namespace {

using namespace cgamesh::cga;

template <class T>
Dense<T> random_dense(std::mt19937& rng) {
  std::uniform_real_distribution<T> u(-1, 1);
  Dense<T> m;
  for (std::size_t i = 0; i < Dense<T>::size; ++i) m[i] = u(rng);
  return m;
}

template <class T>
Versor<T> sample_versor() {
  return similarity<T>(Vec3<T>(T(0.3), T(-1.2), T(2.5)), rotor<T>(Vec3<T>(T(1), T(2), T(-0.5)), T(1.1)), T(1.7));
}
template <class T>
Motor<T> sample_motor() {
  return translator<T>(Vec3<T>(T(0.3), T(-1.2), T(2.5))) * rotor<T>(Vec3<T>(T(1), T(2), T(-0.5)), T(1.1));
}

template <class T>
void BM_DenseGeometricProduct(benchmark::State& state) {
  std::mt19937 rng(1);
  Dense<T> a = random_dense<T>(rng), b = random_dense<T>(rng);
  for (auto _ : state) {
    benchmark::DoNotOptimize(a);
    benchmark::DoNotOptimize(b);
    Dense<T> c = a * b;
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(BM_DenseGeometricProduct<float>);
BENCHMARK(BM_DenseGeometricProduct<double>);

void BM_MotorCompose(benchmark::State& state) {
  Motor<float> a = sample_motor<float>(), b = reverse(sample_motor<float>());
  for (auto _ : state) {
    benchmark::DoNotOptimize(a);
    benchmark::DoNotOptimize(b);
    Motor<float> c = a * b;
    benchmark::DoNotOptimize(c);
  }
}
BENCHMARK(BM_MotorCompose);

template <class V>
void sandwich_point(benchmark::State& state, const V& v) {
  Vector<float> x = up(Vec3<float>(0.5f, -0.25f, 2.0f));
  for (auto _ : state) {
    benchmark::DoNotOptimize(x);
    Vector<float> y = unit_sandwich(v, x);
    benchmark::DoNotOptimize(y);
  }
}
void BM_SandwichPointMotor(benchmark::State& state) { sandwich_point(state, sample_motor<float>()); }
void BM_SandwichPointVersor(benchmark::State& state) { sandwich_point(state, sample_versor<float>()); }
BENCHMARK(BM_SandwichPointMotor);
BENCHMARK(BM_SandwichPointVersor);

constexpr std::size_t kBatch = 8192;

std::vector<float> batch_points() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2, 2);
  std::vector<float> p(3 * kBatch);
  for (float& x : p) x = u(rng);
  return p;
}

// Baseline: the same points by a 3x4 matrix [s R | t], the matrix pipeline's per-vertex cost.
void BM_BatchMatrix3x4(benchmark::State& state) {
  const std::vector<float> in = batch_points();
  std::vector<float> out(in.size());
  const Eigen::Matrix<float, 3, 4> m = to_matrix(sample_versor<float>()).topRows<3>();
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const Eigen::Vector3f p(in[3 * i], in[3 * i + 1], in[3 * i + 2]);
      Eigen::Map<Eigen::Vector3f> o(&out[3 * i]);
      o = m.leftCols<3>() * p + m.col(3);
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kBatch));
}
BENCHMARK(BM_BatchMatrix3x4);

// The versor's sandwich as a linear map (built once per versor, cost included per batch).
void BM_BatchVersorPointMap(benchmark::State& state) {
  const std::vector<float> in = batch_points();
  std::vector<float> out(in.size());
  const Versor<float> v = sample_versor<float>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(v);
    const PointMap<float> map(v);
    map.apply(in, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kBatch));
}
BENCHMARK(BM_BatchVersorPointMap);

// Per-point sandwich V up(x) ~V and down-projection, with compile-time sparse products.
void BM_BatchVersorSandwich(benchmark::State& state) {
  const std::vector<float> in = batch_points();
  std::vector<float> out(in.size());
  const Versor<float> v = sample_versor<float>();
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const Vector<float> y = unit_sandwich(v, up(Vec3<float>(in[3 * i], in[3 * i + 1], in[3 * i + 2])));
      const float w = 1.0f / y.get<blade::eo>();
      out[3 * i] = y[0] * w;
      out[3 * i + 1] = y[1] * w;
      out[3 * i + 2] = y[2] * w;
    }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kBatch));
}
BENCHMARK(BM_BatchVersorSandwich);

// One joint of a `cga` skinning palette: the product M_n B_n and its PointMap, in double.
void BM_PaletteEntryProduct(benchmark::State& state) {
  const Versor<double> m = sample_versor<double>(), b = sample_versor<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(m);
    benchmark::DoNotOptimize(Versor<double>(m * b));
  }
}
void BM_PaletteEntryPointMap(benchmark::State& state) {
  const Versor<double> v = sample_versor<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(v);
    benchmark::DoNotOptimize(PointMap<double>(v).affine_matrix());
  }
}
BENCHMARK(BM_PaletteEntryProduct);
BENCHMARK(BM_PaletteEntryPointMap);

void BM_MotorExp(benchmark::State& state) {
  const MotorGenerator<double> b = log(sample_motor<double>());
  for (auto _ : state) {
    benchmark::DoNotOptimize(b);
    Motor<double> m = exp(b);
    benchmark::DoNotOptimize(m);
  }
}
void BM_MotorLog(benchmark::State& state) {
  const Motor<double> m = sample_motor<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(m);
    MotorGenerator<double> b = log(m);
    benchmark::DoNotOptimize(b);
  }
}
void BM_VersorExp(benchmark::State& state) {
  const SimilarityGenerator<double> b = log(sample_versor<double>());
  for (auto _ : state) {
    benchmark::DoNotOptimize(b);
    Versor<double> v = exp(b);
    benchmark::DoNotOptimize(v);
  }
}
void BM_VersorLog(benchmark::State& state) {
  const Versor<double> v = sample_versor<double>();
  for (auto _ : state) {
    benchmark::DoNotOptimize(v);
    SimilarityGenerator<double> b = log(v);
    benchmark::DoNotOptimize(b);
  }
}
void BM_VersorExpSeries(benchmark::State& state) {
  const SimilarityGenerator<double> b = log(sample_versor<double>());
  for (auto _ : state) {
    benchmark::DoNotOptimize(b);
    Dense<double> v = exp_series(b);
    benchmark::DoNotOptimize(v);
  }
}
BENCHMARK(BM_MotorExp);
BENCHMARK(BM_MotorLog);
BENCHMARK(BM_VersorExp);
BENCHMARK(BM_VersorLog);
BENCHMARK(BM_VersorExpSeries);

}  // namespace
