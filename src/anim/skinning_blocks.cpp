#include "skinning_blocks.hpp"

#include <bit>
#include <cstdint>
#include <cstring>

#include "cgamesh/cga/multivector.hpp"
#include "cgamesh/cga/operations.hpp"
#include "cgamesh/cga/products.hpp"
#include "cgamesh/cga/versors.hpp"

#include "packed_palette.hpp"

// Every function here is internal and inlined into the entry points: the warning that 32-byte
// vectors passed by value change the calling convention without AVX does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

// The kernel is one template over the lane type. Its three entry points are flattened (every call
// inlined), so an entry's target attribute reaches all of its code, while nothing outside them is
// compiled for AVX2 or AVX-512: the released binary runs on any x86-64.

namespace cgamesh::detail {
namespace {

using Index = Eigen::Index;
using V8 = float __attribute__((vector_size(32)));
using I8 = std::int32_t __attribute__((vector_size(32)));
using V4 = float __attribute__((vector_size(16)));

/// 8 floats, one per vertex of a block: the scalar type of the CGA types in the kernel, so eq.
/// (17)'s versor products run on 8 vertices at once with the algebra's own product tables.
struct F8 {
  V8 v{};
  F8() = default;
  F8(V8 x) noexcept : v(x) {}                                 // NOLINT(google-explicit-constructor)
  F8(double s) noexcept : v(V8{} + static_cast<float>(s)) {}  // NOLINT(google-explicit-constructor)
  F8& operator+=(F8 o) noexcept {
    v += o.v;
    return *this;
  }
  F8& operator-=(F8 o) noexcept {
    v -= o.v;
    return *this;
  }
  F8& operator*=(F8 o) noexcept {
    v *= o.v;
    return *this;
  }
  F8& operator/=(F8 o) noexcept {
    v /= o.v;
    return *this;
  }
};
inline F8 operator+(F8 a, F8 b) noexcept { return a.v + b.v; }
inline F8 operator-(F8 a, F8 b) noexcept { return a.v - b.v; }
inline F8 operator*(F8 a, F8 b) noexcept { return a.v * b.v; }
inline F8 operator/(F8 a, F8 b) noexcept { return a.v / b.v; }
inline F8 operator-(F8 a) noexcept { return -a.v; }

inline F8 sqrt(F8 a) noexcept {
#if defined(__x86_64__)
  const V4 lo = __builtin_shufflevector(a.v, a.v, 0, 1, 2, 3), hi = __builtin_shufflevector(a.v, a.v, 4, 5, 6, 7);
  const V4 rl = __builtin_ia32_sqrtps(lo), rh = __builtin_ia32_sqrtps(hi);
  return V8(__builtin_shufflevector(rl, rh, 0, 1, 2, 3, 4, 5, 6, 7));
#else
  F8 r;
  for (int l = 0; l < 8; ++l) r.v[l] = __builtin_sqrtf(a.v[l]);
  return r;
#endif
}
/// 1 / √a for a > 0: the processor's estimate and one Newton step (relative error ≈ 1e-7, about
/// that of 1 / sqrt in float, at a fraction of the latency of a square root and a division).
inline F8 rsqrt(F8 a) noexcept {
#if defined(__x86_64__)
  const V4 lo = __builtin_shufflevector(a.v, a.v, 0, 1, 2, 3), hi = __builtin_shufflevector(a.v, a.v, 4, 5, 6, 7);
  const V8 y = __builtin_shufflevector(__builtin_ia32_rsqrtps(lo), __builtin_ia32_rsqrtps(hi), 0, 1, 2, 3, 4, 5, 6, 7);
  return y * (1.5f - 0.5f * a.v * y * y);
#else
  return F8(1.0) / sqrt(a);
#endif
}
/// Lanes of a where `mask` is set, else of b.
inline F8 select(I8 mask, F8 a, F8 b) noexcept { return mask ? a.v : b.v; }
/// a with the sign of b flipped into it: a where b >= 0, -a where b < 0.
inline F8 flip_sign(F8 a, F8 b) noexcept {
  const I8 s = __builtin_bit_cast(I8, b.v) & std::int32_t(0x80000000u);
  return __builtin_bit_cast(V8, __builtin_bit_cast(I8, a.v) ^ s);
}
inline bool any(I8 mask) noexcept {
  std::int32_t r = 0;
  for (int l = 0; l < 8; ++l) r |= mask[l];
  return r != 0;
}

inline V8 load8(const float* p) noexcept {
  V8 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline V4 load4(const float* p) noexcept {
  V4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// Writes 8 floats at p: with a non-temporal store when `streaming` and p is 16-byte aligned
/// (straight to memory, without first reading the cache lines it fills), else an ordinary one.
inline void store8(float* p, V8 v, bool streaming) noexcept {
#if defined(__x86_64__)
  if (streaming && (reinterpret_cast<std::uintptr_t>(p) & 15) == 0) {
    __builtin_ia32_movntps(p, __builtin_shufflevector(v, v, 0, 1, 2, 3));
    __builtin_ia32_movntps(p + 4, __builtin_shufflevector(v, v, 4, 5, 6, 7));
    return;
  }
#endif
  std::memcpy(p, &v, sizeof v);
}

/// Orders the non-temporal stores before any later store (another thread reads them next).
inline void store_fence() noexcept {
#if defined(__x86_64__)
  __builtin_ia32_sfence();
#endif
}

/// Columns 0-3 of the 4×4 blocks in the two halves of a[0..3]: out[c] = (a[0][c], a[1][c],
/// a[2][c], a[3][c] | the same from the upper halves).
inline void transpose_halves(const V8 (&a)[4], V8* out) noexcept {
  const V8 t0 = __builtin_shufflevector(a[0], a[1], 0, 8, 1, 9, 4, 12, 5, 13);
  const V8 t1 = __builtin_shufflevector(a[0], a[1], 2, 10, 3, 11, 6, 14, 7, 15);
  const V8 t2 = __builtin_shufflevector(a[2], a[3], 0, 8, 1, 9, 4, 12, 5, 13);
  const V8 t3 = __builtin_shufflevector(a[2], a[3], 2, 10, 3, 11, 6, 14, 7, 15);
  out[0] = __builtin_shufflevector(t0, t2, 0, 1, 8, 9, 4, 5, 12, 13);
  out[1] = __builtin_shufflevector(t0, t2, 2, 3, 10, 11, 6, 7, 14, 15);
  out[2] = __builtin_shufflevector(t1, t3, 0, 1, 8, 9, 4, 5, 12, 13);
  out[3] = __builtin_shufflevector(t1, t3, 2, 3, 10, 11, 6, 7, 14, 15);
}

/// 4 floats at row[l] + offset for the 8 lanes l, as 4 F8 across lanes. Rows l and l + 4 are
/// loaded into one register's halves (loads, not shuffles: shuffles share one port), leaving a
/// 4×4 transpose per half.
inline void gather4(const float* const (&row)[8], int offset, V8* out) noexcept {
  V8 a[4];
  for (int i = 0; i < 4; ++i)
    a[i] = __builtin_shufflevector(load4(row[i] + offset), load4(row[i + 4] + offset), 0, 1, 2, 3, 4, 5, 6, 7);
  transpose_halves(a, out);
}

/// rows[r][c] -> rows[c][r] for an 8x8 block in registers: the halves regrouped as gather4 loads
/// them, then the same 4×4 transposes.
inline void transpose(V8 (&r)[8]) noexcept {
  V8 lo[4], hi[4];
  for (int i = 0; i < 4; ++i) {
    lo[i] = __builtin_shufflevector(r[i], r[i + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    hi[i] = __builtin_shufflevector(r[i], r[i + 4], 4, 5, 6, 7, 12, 13, 14, 15);
  }
  transpose_halves(lo, r);
  transpose_halves(hi, r + 4);
}

/// Three coordinates of 8 vertices, one F8 each.
struct Xyz8 {
  F8 x, y, z;
};

inline Xyz8 load_xyz(const float* p) noexcept {
  const V8 a = load8(p), b = load8(p + 8), c = load8(p + 16);
  // a = x0 y0 z0 x1 y1 z1 x2 y2, b = z2 x3 y3 z3 x4 y4 z4 x5, c = y5 z5 x6 y6 z6 x7 y7 z7
  const V8 ab_x = __builtin_shufflevector(a, b, 0, 3, 6, 9, 12, 15, 0, 0);
  const V8 ab_y = __builtin_shufflevector(a, b, 1, 4, 7, 10, 13, 0, 0, 0);
  const V8 ab_z = __builtin_shufflevector(a, b, 2, 5, 8, 11, 14, 0, 0, 0);
  return {__builtin_shufflevector(ab_x, c, 0, 1, 2, 3, 4, 5, 10, 13),
          __builtin_shufflevector(ab_y, c, 0, 1, 2, 3, 4, 8, 11, 14),
          __builtin_shufflevector(ab_z, c, 0, 1, 2, 3, 4, 9, 12, 15)};
}

inline void store_xyz(float* p, const Xyz8& v, bool streaming) noexcept {
  const V8 x = v.x.v, y = v.y.v, z = v.z.v;
  const V8 xy = __builtin_shufflevector(x, y, 0, 8, 1, 9, 2, 10, 3, 11);  // x0 y0 x1 y1 x2 y2 x3 y3
  const V8 xy_hi = __builtin_shufflevector(x, y, 4, 12, 5, 13, 6, 14, 7, 15);
  const V8 a = __builtin_shufflevector(xy, z, 0, 1, 8, 2, 3, 9, 4, 5);        // x0 y0 z0 x1 y1 z1 x2 y2
  const V8 b = __builtin_shufflevector(xy, z, 10, 6, 7, 11, 0, 0, 0, 0);      // z2 x3 y3 z3
  const V8 b2 = __builtin_shufflevector(b, xy_hi, 0, 1, 2, 3, 8, 9, 0, 0);    // .. x4 y4
  const V8 b3 = __builtin_shufflevector(b2, z, 0, 1, 2, 3, 4, 5, 12, 0);      // .. z4
  const V8 bb = __builtin_shufflevector(b3, xy_hi, 0, 1, 2, 3, 4, 5, 6, 10);  // .. x5
  const V8 c = __builtin_shufflevector(xy_hi, z, 3, 13, 4, 5, 14, 6, 7, 15);  // y5 z5 x6 y6 z6 x7 y7 z7
  store8(p, a, streaming);
  store8(p + 8, bb, streaming);
  store8(p + 16, c, streaming);
}

inline Xyz8 cross(const Xyz8& a, const Xyz8& b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// n / |n| per lane; `fallback` where |n| is zero or not finite (as the scalar kernel).
inline Xyz8 unit_or(const Xyz8& n, const Xyz8& fallback) noexcept {
  const F8 len2 = n.x * n.x + n.y * n.y + n.z * n.z;
  const I8 ok = (len2.v > 0.0f) & (len2.v <= __FLT_MAX__);
  const F8 inv = rsqrt(len2);
  return {select(ok, n.x * inv, fallback.x), select(ok, n.y * inv, fallback.y), select(ok, n.z * inv, fallback.z)};
}

/// The influences of one block: weights and joints per slot, lane = vertex. Slots after the last
/// one any of the 8 vertices uses are left out (weights are sorted by decreasing size), so a
/// block of rigid vertices costs one influence, without a branch per vertex.
struct Influences {
  const float* weights;         ///< the block's rows of Skin::weights (8×4)
  const std::uint16_t* joints;  ///< the block's rows of Skin::joints (8×4)
  int count;                    ///< slots used
  [[nodiscard]] float weight(int l, int k) const noexcept { return weights[4 * l + k]; }
  [[nodiscard]] int joint(int l, int k) const noexcept { return joints[4 * l + k]; }
  /// Vertex l's four joints in one load, for joint_in: the affine blend is bound by its loads,
  /// and one load instead of four makes a frame about 6 % faster.
  [[nodiscard]] std::uint64_t joints_of(int l) const noexcept {
    std::uint64_t j;
    std::memcpy(&j, joints + 4 * l, sizeof j);
    return j;
  }
  /// Joint k of the four joints_of gave.
  [[nodiscard]] static int joint_in(std::uint64_t joints, int k) noexcept {
    const int shift = std::endian::native == std::endian::little ? 16 * k : 48 - 16 * k;
    return static_cast<int>((joints >> shift) & 0xffffu);
  }
  /// The weights of the used slots across lanes: w[k] = slot k of each vertex.
  void slots(F8 (&w)[4]) const noexcept {
    const float* const row[8] = {weights,      weights + 4,  weights + 8,  weights + 12,
                                 weights + 16, weights + 20, weights + 24, weights + 28};
    V8 out[4];
    gather4(row, 0, out);
    for (int k = 0; k < 4; ++k) w[k] = out[k];
  }
};

/// A mesh without a skin follows palette entry 0 with weight 1.
constexpr float kNodeWeights[32] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0,
                                    1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
constexpr std::uint16_t kNodeJoints[32] = {};

inline Influences influences(const mesh::Mesh& m, Index i) noexcept {
  if (m.skin.empty()) return {kNodeWeights, kNodeJoints, 1};
  const float* w = m.skin.weights.data() + 4 * i;
  // Each load holds two vertices' four weights.
  const I8 used = (load8(w) > 0.0f) | (load8(w + 8) > 0.0f) | (load8(w + 16) > 0.0f) | (load8(w + 24) > 0.0f);
  int count = 1;
  for (int k = 1; k < 4; ++k)
    if ((used[k] | used[k + 4]) != 0) count = k + 1;
  return {w, m.skin.joints.data() + 4 * i, count};
}

/// Palette entries of slot k for the 8 lanes, transposed: rows[c] = coefficient c of each lane
/// (the 8 floats of each entry from `offset`).
inline void entries(const anim::SkinningPalette& p, const Influences& f, int k, int offset, V8 (&rows)[8]) noexcept {
  const float* row[8];
  const float* packed = PackedPalette::entries(p).data();
  const int stride = PackedPalette::stride(p);
  for (int l = 0; l < 8; ++l) row[l] = packed + stride * f.joint(l, k) + offset;
  gather4(row, 0, rows);
  gather4(row, 4, rows + 4);
}

// ---- cga, matrix: Σ w [A b] per vertex, then x -> A x + b and n -> cof(A) n ----
/// One block with `Count` influences a vertex (a constant, so the blend is unrolled).
template <int Count>
inline void block_affine(const BlockJob& job, const Influences& f, Index i) noexcept {
  const float* packed = PackedPalette::entries(*job.palette).data();
  V8 lo[8], hi[8];  // per vertex: columns 0, 1 of A, and column 2, b (each padded to 4)
  // Unrolled, the 16 rows stay in registers instead of a round trip through the stack (5 % here).
#pragma GCC unroll 8
  for (int l = 0; l < 8; ++l) {
    const std::uint64_t joints = f.joints_of(l);
    V8 a{}, b{};
    for (int k = 0; k < Count; ++k) {
      const float* e = packed + 16 * Influences::joint_in(joints, k);
      const float w = f.weight(l, k);
      a += w * load8(e);
      b += w * load8(e + 8);
    }
    lo[l] = a;
    hi[l] = b;
  }
  // Each vertex's map applied as it is (measured faster than across lanes), the same whether or
  // not normals are asked for, so positions do not depend on it.
  const float* x = job.rest_position(i);
  float* y = job.positions + 3 * i;
  // Streaming stores write whole 16-byte lines: the block is put together on the stack first.
  float block[24];
  float* out = job.streaming ? block : y;
#pragma GCC unroll 8
  for (int l = 0; l < 8; ++l) {
    const float xl = x[3 * l], yl = x[3 * l + 1], zl = x[3 * l + 2];
    const V8 s = lo[l] * V8{xl, xl, xl, xl, yl, yl, yl, yl} + hi[l] * V8{zl, zl, zl, zl, 1, 1, 1, 1};
    const V4 r = __builtin_shufflevector(s, s, 0, 1, 2, 3) + __builtin_shufflevector(s, s, 4, 5, 6, 7);
    // 4 floats (the 4th is the next vertex's x, written after) but for the block's last vertex.
    std::memcpy(out + 3 * l, &r, l < 7 ? sizeof r : 3 * sizeof(float));
  }
  if (job.streaming)
    for (int k = 0; k < 3; ++k) store8(y + 8 * k, load8(block + 8 * k), true);
  if (!job.normals) return;
  // Normals: the maps across lanes for their cofactors.
  transpose(lo);  // A's columns 0, 1: rows 0-2, 4-6
  transpose(hi);  // A's column 2: rows 0-2
  const Xyz8 c0{lo[0], lo[1], lo[2]}, c1{lo[4], lo[5], lo[6]}, c2{hi[0], hi[1], hi[2]};
  const Xyz8 n = load_xyz(job.rest_normal(i));
  const Xyz8 k0 = cross(c1, c2), k1 = cross(c2, c0), k2 = cross(c0, c1);
  store_xyz(job.normals + 3 * i,
            unit_or({k0.x * n.x + k1.x * n.y + k2.x * n.z, k0.y * n.x + k1.y * n.y + k2.y * n.z,
                     k0.z * n.x + k1.z * n.y + k2.z * n.z},
                    n),
            job.streaming);
}

// ---- versor: Σ ±w V per vertex, renormalised (closed form), one sandwich ----

/// (V ~V)^(-1/2) V per lane, as cga::normalized: V ~V = a + Q, Q a 4-vector with Q² = q, the
/// inverse square root α + β Q from the eigenvalues a ± √q (complex for q < 0, a series for
/// q ≈ 0). Returns false when a lane has a <= 0 or is not finite.
template <cga::BladeMask M>
inline bool normalize(cga::Multivector<F8, M>& v) noexcept {
  constexpr cga::BladeMask keep = cga::mask::scalar | cga::mask::quadvector;
  const auto n = cga::product_part<keep>(v, cga::reverse(v));
  const F8 a = cga::scalar_part(n);
  if (any(~((a.v > 0.0f) & (a.v <= __FLT_MAX__)))) return false;
  const auto q4 = cga::grade_part<4>(n);
  const F8 q = cga::scalar_product(q4, q4);
  const F8 ra = rsqrt(a);
  const F8 inv_a = ra * ra;  // 1 / a without a division (three a block were 8 % of a motor frame)
  const F8 ra3 = ra * inv_a;
  // Series about a, to second order in q.
  F8 alpha = ra + F8(3.0 / 8.0) * q * ra3 * inv_a;
  F8 beta = F8(-0.5) * ra3 - F8(15.0 / 48.0) * q * ra3 * (inv_a * inv_a);
  const I8 small = (q.v < 1e-8f * a.v * a.v) & (q.v > -1e-8f * a.v * a.v);
  if (!any(small == 0) || cga::Multivector<F8, M>::size <= 8) {  // motors: Q² = 0
    v = cga::project<M>(v * alpha + q4 * v * beta);
    return true;
  }
  const I8 positive = q.v > 0.0f;
  const F8 r = sqrt(select(positive, q, -q));
  // q > 0: α = (f+ + f-)/2, β = (f+ - f-)/(2√q) with f± = (a ± √q)^(-1/2).
  const F8 fp = F8(1.0) / sqrt(a + r), fm = F8(1.0) / sqrt(a - r);
  // q < 0: √(a + iρ) = u + iv, α = u/|z|, β = -v/(|z| ρ).
  const F8 z = sqrt(a * a + r * r);
  const F8 u = sqrt(F8(0.5) * (z + a)), w = sqrt(F8(0.5) * (z - a));
  const F8 alpha_c = select(positive, F8(0.5) * (fp + fm), u / z);
  const F8 beta_c = select(positive, (fp - fm) / (F8(2.0) * r), -w / (z * r));
  alpha = select(small, alpha, alpha_c);
  beta = select(small, beta, beta_c);
  v = cga::project<M>(v * alpha + q4 * v * beta);
  return true;
}

template <cga::BladeMask M>
inline bool block_versor(const BlockJob& job, const Influences& f, Index i) noexcept {
  using Mv = cga::Multivector<F8, M>;
  constexpr int size = static_cast<int>(Mv::size);
  const anim::SkinningPalette& p = *job.palette;
  Mv first, v;
  F8 w[4];
  f.slots(w);
  for (int k = 0; k < f.count; ++k) {
    Mv e;
    for (int half = 0; half < size; half += 8) {
      V8 rows[8];
      entries(p, f, k, half, rows);
      for (int c = 0; c < 8; ++c) e[static_cast<std::size_t>(half + c)] = rows[c];
    }
    if (k == 0) {
      first = e;
      v += w[0] * e;
    } else {
      // V and -V are the same transform: blend on the side of the first influence.
      v += flip_sign(w[k], cga::scalar_product(first, cga::reverse(e))) * e;
    }
  }
  if (!normalize(v)) return false;
  const Xyz8 x = load_xyz(job.rest_position(i));
  if constexpr (M == cga::mask::motor) {
    // A unit motor T R maps points affinely (cga::motor_affine_matrix): x -> A x + t, A's
    // columns the rotor's sandwiches R eⱼ ~R, t from the translator ⟨V ~R⟩: fewer products than
    // sandwiching the point and the normal by the whole motor (a frame with normals 18 % faster).
    const cga::Rotor<F8> r = cga::project<cga::mask::rotor>(v);
    const cga::Translator<F8> t = cga::product_part<cga::mask::translator>(v, cga::reverse(r));
    const auto column = [&](const auto& e) {
      const cga::Vector<F8> y = cga::unit_sandwich(r, e);
      return Xyz8{y[0], y[1], y[2]};
    };
    const Xyz8 c0 = column(cga::basis_blade<F8, cga::blade::e1>()), c1 = column(cga::basis_blade<F8, cga::blade::e2>()),
               c2 = column(cga::basis_blade<F8, cga::blade::e3>());
    const auto map = [&](const Xyz8& u) {
      return Xyz8{c0.x * u.x + c1.x * u.y + c2.x * u.z, c0.y * u.x + c1.y * u.y + c2.y * u.z,
                  c0.z * u.x + c1.z * u.y + c2.z * u.z};
    };
    const Xyz8 y = map(x);
    const F8 minus_two(-2.0);
    store_xyz(job.positions + 3 * i, {y.x + minus_two * t[1], y.y + minus_two * t[2], y.z + minus_two * t[3]},
              job.streaming);
    if (!job.normals) return true;
    const Xyz8 n = load_xyz(job.rest_normal(i));
    store_xyz(job.normals + 3 * i, unit_or(map(n), n), job.streaming);
    return true;
  }
  const F8 half_sq = F8(0.5) * (x.x * x.x + x.y * x.y + x.z * x.z);
  const cga::Vector<F8> y = cga::unit_sandwich(v, cga::make_vector<F8>(x.x, x.y, x.z, half_sq, F8(1.0)));
  const F8 inv = F8(1.0) / y.get<cga::blade::eo>();
  store_xyz(job.positions + 3 * i, {y[0] * inv, y[1] * inv, y[2] * inv}, job.streaming);
  if (!job.normals) return true;
  const Xyz8 n = load_xyz(job.rest_normal(i));
  const cga::Vector<F8> yn = cga::unit_sandwich(v, cga::euclidean<F8>(n.x, n.y, n.z));
  store_xyz(job.normals + 3 * i, unit_or({yn[0], yn[1], yn[2]}, n), job.streaming);
  return true;
}

// ---- dqs: Σ ±w (q, d) per vertex, normalised, x -> q (S x) q* + t ----

/// q v q* for a unit quaternion (x, y, z, w): v + 2w (u × v) + 2 u × (u × v), u = (x, y, z).
inline Xyz8 rotate(const Xyz8& u, F8 w, const Xyz8& v) noexcept {
  const Xyz8 c = cross(u, v);
  const Xyz8 t{c.x + c.x, c.y + c.y, c.z + c.z};
  const Xyz8 c2 = cross(u, t);
  return {v.x + w * t.x + c2.x, v.y + w * t.y + c2.y, v.z + w * t.z + c2.z};
}

inline void block_dqs(const BlockJob& job, const Influences& f, Index i) noexcept {
  const anim::SkinningPalette& p = *job.palette;
  const bool scaled = !p.scales.empty();
  F8 b[8], s[9], first[4], weights[4];
  f.slots(weights);
  for (int k = 0; k < f.count; ++k) {
    V8 rows[8];
    entries(p, f, k, 0, rows);
    const F8 wk = weights[k];
    F8 w = wk;
    if (k == 0)
      for (int c = 0; c < 4; ++c) first[c] = rows[c];
    else
      w = flip_sign(w, first[0] * rows[0] + first[1] * rows[1] + first[2] * rows[2] + first[3] * rows[3]);
    for (int c = 0; c < 8; ++c) b[c] += w * F8(rows[c]);
    if (!scaled) continue;
    entries(p, f, k, 8, rows);
    for (int c = 0; c < 8; ++c) s[c] += wk * F8(rows[c]);
    const float* packed = PackedPalette::entries(p).data();
    const int stride = PackedPalette::stride(p);
    for (int l = 0; l < 8; ++l) s[8].v[l] += wk.v[l] * packed[stride * f.joint(l, k) + 16];
  }
  const F8 inv = rsqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2] + b[3] * b[3]);
  const Xyz8 u{b[0] * inv, b[1] * inv, b[2] * inv};
  const F8 w = b[3] * inv;
  // t = 2 vec(d q*), d and q normalised alike.
  const Xyz8 d{b[4] * inv, b[5] * inv, b[6] * inv};
  const F8 dw = b[7] * inv;
  const Xyz8 du = cross(d, u);
  const Xyz8 t{F8(2.0) * (w * d.x - dw * u.x - du.x), F8(2.0) * (w * d.y - dw * u.y - du.y),
               F8(2.0) * (w * d.z - dw * u.z - du.z)};
  Xyz8 x = load_xyz(job.rest_position(i));
  const Xyz8 s0{s[0], s[1], s[2]}, s1{s[3], s[4], s[5]}, s2{s[6], s[7], s[8]};  // columns of S
  if (scaled)
    x = {s0.x * x.x + s1.x * x.y + s2.x * x.z, s0.y * x.x + s1.y * x.y + s2.y * x.z,
         s0.z * x.x + s1.z * x.y + s2.z * x.z};
  const Xyz8 y = rotate(u, w, x);
  store_xyz(job.positions + 3 * i, {y.x + t.x, y.y + t.y, y.z + t.z}, job.streaming);
  if (!job.normals) return;
  const Xyz8 n = load_xyz(job.rest_normal(i));
  Xyz8 m = n;
  if (scaled) {
    const Xyz8 k0 = cross(s1, s2), k1 = cross(s2, s0), k2 = cross(s0, s1);
    m = {k0.x * n.x + k1.x * n.y + k2.x * n.z, k0.y * n.x + k1.y * n.y + k2.y * n.z,
         k0.z * n.x + k1.z * n.y + k2.z * n.z};
  }
  store_xyz(job.normals + 3 * i, unit_or(rotate(u, w, m), n), job.streaming);
}

/// The kernel: whole blocks of [begin, end), stopping at a block a lane cannot do.
inline Index skin_blocks(const BlockJob& job, Index begin, Index end) noexcept {
  const mesh::Mesh& m = *job.mesh;
  const anim::SkinningPalette& p = *job.palette;
  const Index last = begin + (end - begin) / 8 * 8;
  for (Index i = begin; i < last; i += 8) {
    const Influences f = influences(m, i);
    switch (p.mode) {
      case anim::SkinningMode::cga:
      case anim::SkinningMode::matrix:
        switch (f.count) {
          case 1:
            block_affine<1>(job, f, i);
            break;
          case 2:
            block_affine<2>(job, f, i);
            break;
          case 3:
            block_affine<3>(job, f, i);
            break;
          default:
            block_affine<4>(job, f, i);
            break;
        }
        break;
      case anim::SkinningMode::versor:
        if (!(p.motors.empty() ? block_versor<cga::mask::versor>(job, f, i)
                               : block_versor<cga::mask::motor>(job, f, i))) {
          if (job.streaming) store_fence();
          return i;
        }
        break;
      case anim::SkinningMode::dqs:
        block_dqs(job, f, i);
        break;
    }
  }
  if (job.streaming) store_fence();
  return last;
}

}  // namespace

__attribute__((flatten)) Index skin_blocks_vector(const BlockJob& job, Index begin, Index end) {
  return skin_blocks(job, begin, end);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((flatten, target("avx2,fma"))) Index skin_blocks_avx2(const BlockJob& job, Index begin, Index end) {
  return skin_blocks(job, begin, end);
}

// The same 8-lane code: AVX-512VL gives it 32 vector registers instead of 16 (the versor and dqs
// blends no longer spill) and no 512-bit instruction, so no clock slowdown.
__attribute__((flatten, target("avx2,fma,avx512f,avx512vl,avx512dq,avx512bw"))) Index skin_blocks_avx512(
    const BlockJob& job, Index begin, Index end) {
  return skin_blocks(job, begin, end);
}

bool cpu_has_avx2_fma() noexcept { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
bool cpu_has_avx512() noexcept {
  return cpu_has_avx2_fma() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw");
}
#else
Index skin_blocks_avx2(const BlockJob& job, Index begin, Index end) { return skin_blocks(job, begin, end); }
Index skin_blocks_avx512(const BlockJob& job, Index begin, Index end) { return skin_blocks(job, begin, end); }
bool cpu_has_avx2_fma() noexcept { return false; }
bool cpu_has_avx512() noexcept { return false; }
#endif

}  // namespace cgamesh::detail
