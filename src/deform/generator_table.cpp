#include "generator_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#if defined(__x86_64__) && defined(__GNUC__)
#define CGAMESH_X86_64_V3 1
#else
#define CGAMESH_X86_64_V3 0
#endif

namespace cgamesh::detail {
namespace {

namespace bl = cga::blade;
constexpr unsigned index_of(cga::BladeIndex b) noexcept {
  return cga::storage_index(cga::mask::similarity_generator, b);
}

/// sin and cos of x ≥ 0 (up to ≈ 1e4: a blended half angle is a few π at most) in single
/// precision: x reduced by the nearest multiple j of π/2 (π/2 split in three so that j π/2 is
/// exact), then the minimax polynomials of Cephes' sinf/cosf on [−π/4, π/4] (≈ 1 ulp), the
/// quadrant chosen by selects so that a loop over lanes vectorises.
inline void sincos_nonnegative(float x, float& s, float& c) noexcept {
  const auto j = static_cast<std::int32_t>(x * 0.636619772f + 0.5f);
  const auto fj = static_cast<float>(j);
  const float r = ((x - fj * 1.5703125f) - fj * 4.837512969970703125e-4f) - fj * 7.549789954891882e-8f;
  const float z = r * r;
  const float sr = ((-1.9515295891e-4f * z + 8.3321608736e-3f) * z - 1.6666654611e-1f) * z * r + r;
  const float cr =
      ((2.443315711809948e-5f * z - 1.388731625493765e-3f) * z + 4.166664568298827e-2f) * z * z - 0.5f * z + 1.0f;
  const bool swap = (j & 1) != 0;
  const float s_abs = swap ? cr : sr, c_abs = swap ? sr : cr;
  s = (j & 2) != 0 ? -s_abs : s_abs;
  c = ((j + 1) & 2) != 0 ? -c_abs : c_abs;
}

/// exp_apply_block()'s body, inlined into each instruction-set variant below.
[[gnu::always_inline]] inline void exp_apply_lanes(const GeneratorBlock& b, int count, const float* rest,
                                                   float* out) noexcept {
  const float* b12 = b.c[index_of(bl::e12)];
  const float* b13 = b.c[index_of(bl::e13)];
  const float* b23 = b.c[index_of(bl::e23)];
  const float* b1i = b.c[index_of(bl::e1inf)];
  const float* b2i = b.c[index_of(bl::e2inf)];
  const float* b3i = b.c[index_of(bl::e3inf)];
  float px[kBlock] = {}, py[kBlock] = {}, pz[kBlock] = {};
  for (int lane = 0; lane < count; ++lane) {
    px[lane] = rest[3 * lane];
    py[lane] = rest[3 * lane + 1];
    pz[lane] = rest[3 * lane + 2];
  }
  float ox[kBlock], oy[kBlock], oz[kBlock];
  // As similarity_exp_affine() for λ = 0: the rotor cos θ + sinc θ (b12 e12 + b13 e13 + b23 e23) as
  // a quaternion, and t = c1 v + c2 (w·v) w + c3 w × v.
  for (int lane = 0; lane < kBlock; ++lane) {
    const float theta2 = b12[lane] * b12[lane] + b13[lane] * b13[lane] + b23[lane] * b23[lane];
    const float theta = std::sqrt(theta2);
    float s, c;
    sincos_nonnegative(theta, s, c);
    // Both sides of each select are computed (no branch, no division that could trap).
    const float sinc = theta < 1e-4f ? 1.0f - theta2 / 6.0f : s / std::max(theta, 1e-4f);
    const float qw = c, qx = -sinc * b23[lane], qy = sinc * b13[lane], qz = -sinc * b12[lane];
    const float wx = -2.0f * b23[lane], wy = 2.0f * b13[lane], wz = -2.0f * b12[lane];
    const float vx = -2.0f * b1i[lane], vy = -2.0f * b2i[lane], vz = -2.0f * b3i[lane];
    const float c1 = c * sinc, c3 = 0.5f * sinc * sinc;
    // c2 = (1 − c1) / φ², φ = 2θ: its series below φ = 0.5, where 1 − c1 loses digits.
    const float phi2 = 4.0f * theta2;
    const float series = 1.0f / 6.0f - phi2 * (1.0f / 120.0f - phi2 * (1.0f / 5040.0f - phi2 / 362880.0f));
    const float c2 = phi2 < 0.25f ? series : (1.0f - c1) / std::max(phi2, 0.25f);
    const float wv = c2 * (wx * vx + wy * vy + wz * vz);
    const float tx = c1 * vx + wv * wx + c3 * (wy * vz - wz * vy);
    const float ty = c1 * vy + wv * wy + c3 * (wz * vx - wx * vz);
    const float tz = c1 * vz + wv * wz + c3 * (wx * vy - wy * vx);
    const float xx = qx * qx, yy = qy * qy, zz = qz * qz, xy = qx * qy, xz = qx * qz, yz = qy * qz;
    const float rwx = qw * qx, rwy = qw * qy, rwz = qw * qz;
    const float x = px[lane], y = py[lane], z = pz[lane];
    ox[lane] = (1 - 2 * (yy + zz)) * x + 2 * (xy - rwz) * y + 2 * (xz + rwy) * z + tx;
    oy[lane] = 2 * (xy + rwz) * x + (1 - 2 * (xx + zz)) * y + 2 * (yz - rwx) * z + ty;
    oz[lane] = 2 * (xz - rwy) * x + 2 * (yz + rwx) * y + (1 - 2 * (xx + yy)) * z + tz;
  }
  const float* dilation = b.c[index_of(bl::info)];
  for (int lane = 0; lane < count; ++lane) {
    if (dilation[lane] != 0) {
      Eigen::Matrix<float, kGeneratorSize, 1> g;
      for (int k = 0; k < kGeneratorSize; ++k) g[k] = b.c[k][lane];
      const Eigen::RowVector3f p = exp_apply(g, Eigen::RowVector3f(px[lane], py[lane], pz[lane]));
      ox[lane] = p[0], oy[lane] = p[1], oz[lane] = p[2];
    }
    out[3 * lane] = ox[lane];
    out[3 * lane + 1] = oy[lane];
    out[3 * lane + 2] = oz[lane];
  }
}

void exp_apply_baseline(const GeneratorBlock& b, int count, const float* rest, float* out) noexcept {
  exp_apply_lanes(b, count, rest, out);
}

#if CGAMESH_X86_64_V3
// The released binary runs on any x86-64; this variant (8 lanes a vector, fused multiply-adds)
// runs where the CPU has AVX2 and FMA: ≈ 2× the baseline's SSE2 here. The attribute adds AVX2 and
// FMA to what the build targets: "arch=x86-64-v3" would take away what a -march=x86-64-v4 or
// native build has, and GCC then refuses to inline exp_apply_lanes (always_inline) into it.
__attribute__((target("avx2,fma"))) void exp_apply_v3(const GeneratorBlock& b, int count, const float* rest,
                                                      float* out) noexcept {
  exp_apply_lanes(b, count, rest, out);
}
#endif

}  // namespace

bool has_isa(Isa isa) noexcept {
#if CGAMESH_X86_64_V3
  static const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return isa == Isa::baseline || v3;
#else
  return isa == Isa::baseline;
#endif
}

void exp_apply_block(const GeneratorBlock& b, int count, const float* rest, float* out, Isa isa) noexcept {
#if CGAMESH_X86_64_V3
  if (isa == Isa::x86_64_v3) return exp_apply_v3(b, count, rest, out);
#endif
  (void)isa;
  exp_apply_baseline(b, count, rest, out);
}

void exp_apply_block(const GeneratorBlock& b, int count, const float* rest, float* out) noexcept {
  static const Isa best = has_isa(Isa::x86_64_v3) ? Isa::x86_64_v3 : Isa::baseline;
  exp_apply_block(b, count, rest, out, best);
}

}  // namespace cgamesh::detail
