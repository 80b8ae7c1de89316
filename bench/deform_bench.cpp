// Motor-handle deformation (paper sections III, IV, VIII): binding (harmonic parameter +
// bound points) and one frame (per-vertex blended motor and sandwich) on the cow (~3k
// vertices) and ogre (62k) from ../shared/data, and on CesiumMan subdivided past a million
// vertices; single thread and all threads. FFD (section V) frames, classic and motor, on the
// million-vertex mesh; cage coordinates (section VI): the grid precompute up to 64³, and frames
// on the million-vertex mesh, classic and motor. The million-vertex frame takes its parameter from
// the height instead of a harmonic solve (the frame cost does not depend on where lambda
// comes from). Also the factorisation and the solve of the harmonic field on ogre. ARAP
// (section VII): precompute and time per iteration on cow, arm_16k, stanford-bunny and ogre, one
// thread and all threads, rotor and SVD local steps.
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>

#include "cgamesh/cga/point_map.hpp"
#include "cgamesh/cga/versors.hpp"
#include "cgamesh/deform/arap.hpp"
#include "cgamesh/deform/cage_coordinates.hpp"
#include "cgamesh/deform/ffd.hpp"
#include "cgamesh/deform/harmonic_field.hpp"
#include "cgamesh/deform/spline_deform.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/mesh/subdivide.hpp"

namespace {

using namespace cgamesh;
using cga::Versor;

constexpr std::size_t kKeys = 4;

/// The first mesh of a shared-data model, or nullptr when ../shared/data is absent.
const mesh::Mesh* shared_mesh(const std::string& name) {
  static std::map<std::string, mesh::Mesh> cache;
  const std::filesystem::path path = std::string(CGAMESH_SHARED_DATA) + "/meshes/" + name;
  if (!std::filesystem::exists(path)) return nullptr;
  auto [it, inserted] = cache.try_emplace(name);
  if (inserted) it->second = io::load_model(path).meshes.at(0);
  return &it->second;
}

/// Vertices in the lowest / highest 10% of the height (y).
std::vector<int> slab(const mesh::Mesh& m, bool top) {
  const float lo = m.positions.col(1).minCoeff(), hi = m.positions.col(1).maxCoeff();
  std::vector<int> out;
  for (Eigen::Index i = 0; i < m.vertex_count(); ++i) {
    const float y = m.positions(i, 1);
    if (top ? y >= hi - 0.1f * (hi - lo) : y <= lo + 0.1f * (hi - lo)) out.push_back(static_cast<int>(i));
  }
  return out;
}

std::vector<Versor<double>> rest_keys() {
  return std::vector<Versor<double>>(kKeys, Versor<double>(cga::basis_blade<double, cga::blade::scalar>()));
}

/// A bend: each key turns a little more about z and shifts.
std::vector<Versor<double>> posed_keys() {
  std::vector<Versor<double>> keys;
  for (std::size_t j = 0; j < kKeys; ++j)
    keys.push_back(cga::similarity(Eigen::Vector3d(0.1 * j, 0, 0), cga::rotor(Eigen::Vector3d(0, 0, 1), 0.4 * j), 1.0));
  return keys;
}

/// The bottom slab plus the lowest vertex of every connected part (welded by position) that
/// neither slab reaches: each part needs a constrained vertex (ogre has loose parts).
std::vector<int> start_handle(const mesh::Mesh& m) {
  std::vector<int> parent(static_cast<std::size_t>(m.vertex_count()));
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = static_cast<int>(v);
  const auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v)
      v = parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    return v;
  };
  std::map<std::array<float, 3>, int> first;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const int w =
        first.try_emplace({m.positions(v, 0), m.positions(v, 1), m.positions(v, 2)}, static_cast<int>(v)).first->second;
    parent[static_cast<std::size_t>(root(static_cast<int>(v)))] = root(w);
  }
  for (Eigen::Index f = 0; f < m.face_count(); ++f)
    for (int k = 1; k < 3; ++k) parent[static_cast<std::size_t>(root(m.faces(f, k)))] = root(m.faces(f, 0));
  std::vector<int> start = slab(m, false);
  std::map<int, int> reached, lowest;
  for (const std::vector<int>& s : {start, slab(m, true)})
    for (const int v : s) reached[root(v)] = v;
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v) {
    const auto [it, added] = lowest.try_emplace(root(static_cast<int>(v)), static_cast<int>(v));
    if (m.positions(v, 1) < m.positions(it->second, 1)) it->second = static_cast<int>(v);
  }
  for (const auto& [part, v] : lowest)
    if (!reached.contains(part)) start.push_back(v);
  return start;
}

deform::MotorBlend bind(const mesh::Mesh& m, int threads) {
  return deform::bind_spline(m, start_handle(m), slab(m, true), rest_keys(), {}, {threads});
}

/// CesiumMan subdivided past a million vertices.
const mesh::Mesh& million_mesh() {
  static const mesh::Mesh big = [] {
    mesh::Mesh m = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb").meshes.at(0);
    while (m.vertex_count() < 1'000'000) m = mesh::subdivide_midpoint(m);
    return m;
  }();
  return big;
}

/// The million-vertex mesh bound with lambda = normalised height.
const deform::MotorBlend& million(int threads) {
  const mesh::Mesh& big = million_mesh();
  static std::map<int, deform::MotorBlend> bound;
  auto it = bound.find(threads);
  if (it == bound.end()) {
    const int axis = 2;  // CesiumMan stands along z
    const float lo = big.positions.col(axis).minCoeff(), hi = big.positions.col(axis).maxCoeff();
    // As bind_spline() does for large meshes: the parameter rounded to SplineOptions::levels.
    const int top = deform::SplineOptions{}.levels - 1;
    deform::WeightMatrix w(top + 1, static_cast<Eigen::Index>(kKeys));
    for (int r = 0; r <= top; ++r)
      deform::spline_weights({}, static_cast<double>(r) / top, std::span<double>(w.row(r).data(), kKeys));
    std::vector<int> rows(static_cast<std::size_t>(big.vertex_count()));
    for (Eigen::Index i = 0; i < big.vertex_count(); ++i)
      rows[static_cast<std::size_t>(i)] =
          static_cast<int>(std::lround((big.positions(i, axis) - lo) / (hi - lo) * top));
    it =
        bound.emplace(threads, deform::MotorBlend(big.positions, std::move(w), std::move(rows), rest_keys(), {threads}))
            .first;
  }
  return it->second;
}

/// False (the benchmark skipped with the reason) when the mesh cannot be bound, e.g. a
/// connected part without a handle vertex.
bool bindable(benchmark::State& state, const mesh::Mesh& m) {
  try {
    (void)bind(m, 1);
    return true;
  } catch (const cgamesh::Error& e) {
    state.SkipWithError(e.what());
    return false;
  }
}

void frame(benchmark::State& state, const deform::MotorBlend& b) {
  const auto keys = posed_keys();
  mesh::RowMatrixXf<3> out;
  for (auto _ : state) {
    b.deform(keys, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * b.vertex_count());
  state.counters["vertices"] = static_cast<double>(b.vertex_count());
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_DeformBind(benchmark::State& state, const std::string& name) {
  const mesh::Mesh* m = shared_mesh(name);
  if (m == nullptr) return state.SkipWithError("model not found (../shared/data is not present)");
  if (!bindable(state, *m)) return;
  for (auto _ : state) benchmark::DoNotOptimize(bind(*m, 0).bound_points().data());
  state.counters["vertices"] = static_cast<double>(m->vertex_count());
}

void BM_DeformFrame(benchmark::State& state, const std::string& name) {
  const int threads = static_cast<int>(state.range(0));
  if (name == "million") return frame(state, million(threads));
  const mesh::Mesh* m = shared_mesh(name);
  if (m == nullptr) return state.SkipWithError("model not found (../shared/data is not present)");
  if (bindable(state, *m)) frame(state, bind(*m, threads));
}

/// The million-vertex mesh in a 5×5×5 lattice over its bounding box; one binding kept at a time
/// (each holds ≈ 100 MB of weights).
const deform::FreeFormDeformation& million_ffd(deform::LatticeBasis basis, int threads) {
  static std::optional<deform::FreeFormDeformation> bound;
  static std::pair<deform::LatticeBasis, int> key;
  if (!bound || key != std::pair{basis, threads}) {
    bound.reset();
    deform::Lattice lattice;
    lattice.resolution = {5, 5, 5};
    lattice.basis = basis;
    lattice.box = deform::bounding_lattice_box(million_mesh().positions, 0.01);
    bound.emplace(million_mesh().positions, lattice, deform::FfdOptions{threads});
    key = {basis, threads};
  }
  return *bound;
}

/// FFD frames (section V) on the million-vertex mesh: a twist, control point layer k along z (the
/// height) turned by 22.5° k about the box's axis — moved points (classic, eq. 6) or motors
/// (eqs. 7–8). Args: threads (0 = all), variant (0 classic, 1 motor).
void BM_FfdFrame(benchmark::State& state, deform::LatticeBasis basis) {
  const deform::FreeFormDeformation& ffd = million_ffd(basis, static_cast<int>(state.range(0)));
  const deform::Lattice& l = ffd.lattice();
  const Eigen::Vector3d center = l.box.origin + 0.5 * l.box.size;
  std::vector<Eigen::Vector3d> points = l.control_points();
  std::vector<Versor<double>> motors;
  for (std::size_t c = 0; c < points.size(); ++c) {
    const double angle = 0.125 * std::numbers::pi * static_cast<double>(c / 25);  // layer c / (5·5)
    motors.push_back(
        cga::project<cga::mask::versor>(cga::translator(center) * cga::rotor(Eigen::Vector3d(0, 0, 1), angle) *
                                        cga::translator(Eigen::Vector3d(-center))));
    const Eigen::Matrix<double, 3, 4> m = cga::PointMap<double>(motors.back()).affine_matrix();
    points[c] = m.leftCols<3>() * points[c] + m.col(3);
  }
  const bool motor = state.range(1) == 1;
  mesh::RowMatrixXf<3> out;
  for (auto _ : state) {
    if (motor)
      ffd.deform_motors(motors, out);
    else
      ffd.deform_points(points, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * ffd.vertex_count());
  state.counters["vertices"] = static_cast<double>(ffd.vertex_count());
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_FfdBind(benchmark::State& state, deform::LatticeBasis basis) {
  deform::Lattice lattice;
  lattice.resolution = {5, 5, 5};
  lattice.basis = basis;
  lattice.box = deform::bounding_lattice_box(million_mesh().positions, 0.01);
  for (auto _ : state)
    benchmark::DoNotOptimize(deform::FreeFormDeformation(million_mesh().positions, lattice).vertex_count());
  state.counters["vertices"] = static_cast<double>(million_mesh().vertex_count());
}

/// A cube cage (3 segments per side: 56 vertices) around `m`, 2 % wider than its longest side:
/// the grid is the full resolution³ cube.
deform::Cage cube_cage(const mesh::Mesh& m) {
  const Eigen::Vector3d lo = m.positions.colwise().minCoeff().transpose().cast<double>();
  const Eigen::Vector3d hi = m.positions.colwise().maxCoeff().transpose().cast<double>();
  const double side = 1.02 * (hi - lo).maxCoeff();
  const Eigen::Vector3d center = 0.5 * (lo + hi);
  return deform::box_cage(center - Eigen::Vector3d::Constant(side / 2), center + Eigen::Vector3d::Constant(side / 2),
                          {3, 3, 3});
}

/// Cage coordinates of CesiumMan in cube_cage(): the grid resolution³ (the cage fills the grid,
/// so every node but a shell of two is an unknown). Args: resolution, threads (0 = all).
void BM_CagePrecompute(benchmark::State& state) {
  const mesh::Mesh m = io::load_model(std::string(CGAMESH_DATA_DIR) + "/CesiumMan.glb").meshes.at(0);
  const deform::Cage cage = cube_cage(m);
  deform::CageOptions options;
  options.resolution = static_cast<int>(state.range(0));
  options.threads = static_cast<int>(state.range(1));
  for (auto _ : state) benchmark::DoNotOptimize(deform::cage_coordinates(m.positions, cage, options).data());
  state.counters["cage_vertices"] = static_cast<double>(cage.vertices.rows());
}

/// The million-vertex mesh's coordinates in cube_cage() at resolution 32 (the frame cost does not
/// depend on the resolution); one sparsity bound at a time (each holds up to ≈ 450 MB).
const deform::CageDeformation& million_cage(int max_weights, int threads) {
  static const deform::Cage cage = cube_cage(million_mesh());
  static const Eigen::MatrixXd coordinates = [] {
    deform::CageOptions options;
    options.resolution = 32;
    return deform::cage_coordinates(million_mesh().positions, cage, options);
  }();
  static std::optional<deform::CageDeformation> bound;
  static std::pair<int, int> key;
  if (!bound || key != std::pair{max_weights, threads}) {
    bound.reset();
    deform::CageSparsity sparsity;
    sparsity.max_weights = max_weights;
    bound.emplace(million_mesh().positions, cage, coordinates, sparsity, threads);
    key = {max_weights, threads};
  }
  return *bound;
}

/// Cage frames (section VI) on the million-vertex mesh: a twist, each cage vertex turned about
/// the vertical axis by 90° × its height in the cage — moved vertices (classic) or motors.
/// Args: threads (0 = all), variant (0 classic, 1 motor), max_weights.
void BM_CageFrame(benchmark::State& state) {
  const deform::CageDeformation& d = million_cage(static_cast<int>(state.range(2)), static_cast<int>(state.range(0)));
  const auto& c = d.cage_vertices();
  const Eigen::Vector3d lo = c.colwise().minCoeff().transpose(), hi = c.colwise().maxCoeff().transpose();
  const Eigen::Vector3d center = 0.5 * (lo + hi);
  std::vector<Eigen::Vector3d> points;
  std::vector<Versor<double>> motors;
  for (Eigen::Index v = 0; v < c.rows(); ++v) {
    const double angle = 0.5 * std::numbers::pi * (c(v, 2) - lo[2]) / (hi[2] - lo[2]);  // CesiumMan stands along z
    motors.push_back(
        cga::project<cga::mask::versor>(cga::translator(center) * cga::rotor(Eigen::Vector3d(0, 0, 1), angle) *
                                        cga::translator(Eigen::Vector3d(-center))));
    const Eigen::Matrix<double, 3, 4> m = cga::PointMap<double>(motors.back()).affine_matrix();
    points.push_back(m.leftCols<3>() * c.row(v).transpose() + m.col(3));
  }
  const bool motor = state.range(1) == 1;
  mesh::RowMatrixXf<3> out;
  for (auto _ : state) {
    if (motor)
      d.deform_motors(motors, out);
    else
      d.deform_points(points, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * d.vertex_count());
  state.counters["vertices"] = static_cast<double>(d.vertex_count());
  state.counters["weights"] = d.mean_weights();
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

std::vector<int> ogre_constraints(const mesh::Mesh& m) {
  std::vector<int> c = start_handle(m);
  const std::vector<int> top = slab(m, true);
  c.insert(c.end(), top.begin(), top.end());
  return c;
}

/// The harmonic field's factorisation on a mesh as io::load_model gives it (OBJ corners joined,
/// seams split; the field welds positions itself), against libigl's `igl::harmonic` (#19).
void BM_DeformHarmonicFactor(benchmark::State& state, const std::string& name) {
  const mesh::Mesh* m = shared_mesh(name);
  if (m == nullptr) return state.SkipWithError("model not found (../shared/data is not present)");
  if (!bindable(state, *m)) return;
  const std::vector<int> c = ogre_constraints(*m);
  for (auto _ : state) benchmark::DoNotOptimize(deform::harmonic_precompute(*m, c).vertex_count());
}

void BM_DeformHarmonicSolveOgre(benchmark::State& state) {
  const mesh::Mesh* m = shared_mesh("ogre.obj");
  if (m == nullptr) return state.SkipWithError("model not found (../shared/data is not present)");
  if (!bindable(state, *m)) return;
  const std::vector<int> c = ogre_constraints(*m);
  const auto pre = deform::harmonic_precompute(*m, c);
  Eigen::MatrixXd boundary = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(c.size()), 1);
  boundary.bottomRows(static_cast<Eigen::Index>(slab(*m, true).size())).setOnes();
  for (auto _ : state) benchmark::DoNotOptimize(deform::harmonic_solve(pre, boundary).data());
}

/// The ARAP handles of a shared mesh (start_handle() and the top slab) and their targets: the
/// top slab turned by 0.5 rad about z about its centre and moved by 10% of the height.
struct ArapProblem {
  std::vector<int> handles;
  Eigen::MatrixXd targets;
};
ArapProblem arap_problem(const mesh::Mesh& m) {
  ArapProblem p;
  p.handles = ogre_constraints(m);
  const std::size_t fixed = start_handle(m).size();
  const std::vector<int> top = slab(m, true);
  Eigen::MatrixXd rest = m.positions(p.handles, Eigen::all).cast<double>();
  const Eigen::Vector3d centre = rest.bottomRows(static_cast<Eigen::Index>(top.size())).colwise().mean().transpose();
  const double height = m.positions.col(1).maxCoeff() - m.positions.col(1).minCoeff();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.targets = rest;
  for (auto i = static_cast<Eigen::Index>(fixed); i < rest.rows(); ++i)
    p.targets.row(i) =
        (r * (rest.row(i).transpose() - centre) + centre + Eigen::Vector3d(0.1 * height, 0, 0)).transpose();
  return p;
}

void BM_ArapPrecompute(benchmark::State& state, const std::string& name) {
  const mesh::Mesh* m = shared_mesh(name);
  if (m == nullptr) return state.SkipWithError("model not found (../shared/data is not present)");
  const ArapProblem problem = arap_problem(*m);
  deform::ArapOptions options;
  options.threads = 1;
  Eigen::Index nodes = 0;
  for (auto _ : state) nodes = deform::arap_precompute(*m, problem.handles, options).node_count();
  state.counters["vertices"] = static_cast<double>(nodes);  // after welding
}

/// Args: threads (0 = all), local step (0 rotor, 1 SVD). 10 iterations from the rest shape per
/// solve; `iteration` is the time of one (the initial local step shared out).
void BM_ArapIteration(benchmark::State& state, const std::string& name) {
  const mesh::Mesh* m = shared_mesh(name);
  if (m == nullptr) return state.SkipWithError("model not found (../shared/data is not present)");
  const ArapProblem problem = arap_problem(*m);
  deform::ArapOptions options;
  options.threads = static_cast<int>(state.range(0));
  options.local_step = state.range(1) == 0 ? deform::ArapLocalStep::rotor : deform::ArapLocalStep::svd;
  const deform::ArapData data = deform::arap_precompute(*m, problem.handles, options);
  Eigen::MatrixXd positions;
  for (auto _ : state) {
    positions.resize(0, 3);
    benchmark::DoNotOptimize(deform::arap_solve(data, problem.targets, positions).iterations);
  }
  state.counters["vertices"] = static_cast<double>(data.node_count());
  state.counters["iteration"] = benchmark::Counter(static_cast<double>(state.iterations() * options.iterations),
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// The local step's rotation alone for 4096 random covariances (near-rotations of 7 weighted
/// edges, as a cell sees them): Horn's rotor (arg 0) or the SVD (arg 1).
void BM_ArapRotation(benchmark::State& state) {
  std::vector<Eigen::Matrix3d> covariances;
  unsigned seed = 1;
  const auto next = [&] {
    seed = seed * 1664525u + 1013904223u;
    return static_cast<double>(seed >> 8) / (1u << 24) - 0.5;
  };
  for (int i = 0; i < 4096; ++i) {
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(3 * next(), Eigen::Vector3d(next(), next(), next()).normalized()).toRotationMatrix();
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    for (int e = 0; e < 7; ++e) {
      const Eigen::Vector3d v(next(), next(), next());
      s += (0.5 + next()) * v * (r * v + 0.1 * Eigen::Vector3d(next(), next(), next())).transpose();
    }
    covariances.push_back(s);
  }
  const bool svd = state.range(0) == 1;
  for (auto _ : state)
    for (const Eigen::Matrix3d& s : covariances) {
      if (svd)
        benchmark::DoNotOptimize(deform::arap_rotation_svd(s).data());
      else
        benchmark::DoNotOptimize(deform::arap_rotor(s));
    }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(covariances.size()));
}

// Arg: threads (0 = all).
BENCHMARK_CAPTURE(BM_DeformBind, cow, std::string("cow.obj"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DeformBind, ogre, std::string("ogre.obj"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DeformFrame, cow, std::string("cow.obj"))
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_DeformFrame, ogre, std::string("ogre.obj"))
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_DeformFrame, million, std::string("million"))
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Args: threads (0 = all), variant (0 classic, 1 motor).
BENCHMARK_CAPTURE(BM_FfdFrame, bernstein, deform::LatticeBasis::bernstein)
    ->ArgsProduct({{1, 0}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_FfdFrame, bspline, deform::LatticeBasis::bspline)
    ->ArgsProduct({{1, 0}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_FfdBind, bspline, deform::LatticeBasis::bspline)->Unit(benchmark::kMillisecond)->UseRealTime();
// Args: resolution, threads (0 = all).
BENCHMARK(BM_CagePrecompute)->ArgsProduct({{32, 64}, {1, 0}})->Unit(benchmark::kMillisecond)->UseRealTime();
// Args: threads (0 = all), variant (0 classic, 1 motor), max_weights (56: all of the cube cage's).
BENCHMARK(BM_CageFrame)->ArgsProduct({{1, 0}, {0, 1}, {8, 16, 56}})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DeformHarmonicFactor, cow, std::string("cow.obj"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_DeformHarmonicFactor, bunny, std::string("stanford-bunny.obj"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_DeformHarmonicFactor, ogre, std::string("ogre.obj"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DeformHarmonicSolveOgre)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ArapPrecompute, cow, std::string("cow.obj"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ArapPrecompute, arm_16k, std::string("arm_16k.ply"))->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_ArapPrecompute, bunny, std::string("stanford-bunny.obj"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ArapPrecompute, ogre, std::string("ogre.obj"))->Unit(benchmark::kMillisecond)->UseRealTime();
// Args: threads (0 = all), local step (0 rotor, 1 SVD).
BENCHMARK_CAPTURE(BM_ArapIteration, cow, std::string("cow.obj"))
    ->ArgsProduct({{1, 0}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ArapIteration, arm_16k, std::string("arm_16k.ply"))
    ->ArgsProduct({{1, 0}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ArapIteration, bunny, std::string("stanford-bunny.obj"))
    ->ArgsProduct({{1, 0}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_ArapIteration, ogre, std::string("ogre.obj"))
    ->ArgsProduct({{1, 0}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_ArapRotation)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
