// The motor frames' block kernel (single precision, polynomial sincos, vectorised over vertices)
// against the double-precision exp of one vertex it replaces.
#include "deform/generator_table.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

namespace {

using namespace cgamesh;  // NOLINT(google-build-using-namespace)
namespace bl = cga::blade;
using detail::kBlock;
using detail::kGeneratorSize;
using Generator = Eigen::Matrix<float, kGeneratorSize, 1>;

constexpr unsigned index_of(cga::BladeIndex b) noexcept {
  return cga::storage_index(cga::mask::similarity_generator, b);
}

/// A generator of half angle `theta` about a fixed oblique axis, translation part `v`, and
/// log-scale part `dilation`.
Generator generator(float theta, const Eigen::Vector3f& v, float dilation) {
  const Eigen::Vector3f axis = Eigen::Vector3f(1, -2, 3).normalized() * theta;
  Generator g = Generator::Zero();
  g[index_of(bl::e12)] = axis[0], g[index_of(bl::e13)] = axis[1], g[index_of(bl::e23)] = axis[2];
  g[index_of(bl::e1inf)] = v[0], g[index_of(bl::e2inf)] = v[1], g[index_of(bl::e3inf)] = v[2];
  g[index_of(bl::info)] = dilation;
  return g;
}

/// The kernel's variants this CPU runs (the baseline always).
std::vector<detail::Isa> isas() {
  std::vector<detail::Isa> out;
  for (const detail::Isa isa : {detail::Isa::baseline, detail::Isa::x86_64_v3})
    if (detail::has_isa(isa)) out.push_back(isa);
  return out;
}

/// Runs each variant of the block kernel on `generators` (≤ kBlock) and compares each lane with
/// exp_apply(): within `tolerance` × (|p| + |v| + 1), the float rounding of a 3×4 map applied to p.
void expect_block_matches(const std::vector<Generator>& generators, const mesh::RowMatrixXf<3>& rest,
                          double tolerance) {
  detail::GeneratorBlock block;
  const int count = static_cast<int>(generators.size());
  for (int lane = 0; lane < count; ++lane)
    for (int k = 0; k < kGeneratorSize; ++k) block.c[k][lane] = generators[static_cast<std::size_t>(lane)][k];
  for (const detail::Isa isa : isas()) {
    mesh::RowMatrixXf<3> out(count, 3);
    detail::exp_apply_block(block, count, rest.data(), out.data(), isa);
    for (int lane = 0; lane < count; ++lane) {
      const Generator& g = generators[static_cast<std::size_t>(lane)];
      const Eigen::RowVector3f expected = detail::exp_apply(g, rest.row(lane));
      const double scale = rest.row(lane).norm() + 2 * g.segment<3>(3).norm() + 1;
      EXPECT_LE((out.row(lane) - expected).cwiseAbs().maxCoeff(), tolerance * scale)
          << "isa " << static_cast<int>(isa) << ", lane " << lane << ": " << out.row(lane) << " vs " << expected;
    }
  }
}

TEST(MotorFrameBlock, MatchesTheDoublePathOverAnglesAndTranslations) {
  // Half angles from 0 through tiny and the series/division switch of c2 (φ = 2θ = 0.5) to past
  // 2π (B-spline lattices with linear ends weigh some motors negatively: |Σ w log R| can exceed π).
  std::vector<float> thetas = {0, 1e-7f, 1e-5f, 1e-4f, 2e-4f, 1e-3f, 0.01f, 0.1f, 0.2499f, 0.25f, 0.2501f, 0.5f};
  for (int k = 0; k <= 40; ++k) thetas.push_back(0.7f + 0.15f * static_cast<float>(k));
  mesh::RowMatrixXf<3> rest(kBlock, 3);
  for (int lane = 0; lane < kBlock; ++lane)
    rest.row(lane) << std::sin(1.0f * lane) * 5, std::cos(2.0f * lane) * 3, 0.5f * static_cast<float>(lane) - 4;
  std::vector<Generator> generators;
  for (std::size_t t = 0; t < thetas.size(); ++t) {
    const float s = static_cast<float>(t);
    generators.push_back(generator(thetas[t], Eigen::Vector3f(std::sin(s), 2 * std::cos(3 * s), -1.5f), 0));
    if (static_cast<int>(generators.size()) == kBlock || t + 1 == thetas.size()) {
      expect_block_matches(generators, rest.topRows(static_cast<Eigen::Index>(generators.size())), 1e-6);
      generators.clear();
    }
  }
}

TEST(MotorFrameBlock, ZeroGeneratorIsExactlyTheIdentity) {
  detail::GeneratorBlock block;
  mesh::RowMatrixXf<3> rest(kBlock, 3), out(kBlock, 3);
  for (int lane = 0; lane < kBlock; ++lane) rest.row(lane) << 1e3f * lane, -0.1f * lane, 3.7f / (lane + 1);
  for (const detail::Isa isa : isas()) {
    detail::exp_apply_block(block, kBlock, rest.data(), out.data(), isa);
    EXPECT_EQ(out, rest);
  }
}

TEST(MotorFrameBlock, DilatingLanesAndPartialBlocksTakeTheDoublePath) {
  std::vector<Generator> generators;
  for (int lane = 0; lane < 7; ++lane)
    generators.push_back(generator(0.3f * lane, Eigen::Vector3f(0.5f, -lane, 2),
                                   lane % 2 == 0 ? 0.0f : 0.1f * static_cast<float>(lane)));
  mesh::RowMatrixXf<3> rest(7, 3);
  for (int lane = 0; lane < 7; ++lane) rest.row(lane) << lane, 2 - lane, 0.25f * lane;
  expect_block_matches(generators, rest, 1e-6);
  // Lanes past `count` are not written.
  detail::GeneratorBlock block;
  for (const detail::Isa isa : isas()) {
    mesh::RowMatrixXf<3> out = mesh::RowMatrixXf<3>::Constant(kBlock, 3, -7);
    detail::exp_apply_block(block, 3, rest.data(), out.data(), isa);
    EXPECT_EQ(out.topRows(3), rest.topRows(3));
    EXPECT_TRUE((out.bottomRows(kBlock - 3).array() == -7).all());
  }
}

}  // namespace
