#pragma once
// Multivector<T, Mask>: a multivector of G(4,1) that stores only the blades in Mask.
// Mask = kAllBlades is the dense 32-coefficient multivector; the named aliases below are the
// sparse types used for geometry and versors. Products of sparse types (products.hpp) get,
// at compile time, exactly the blades that can be non-zero.

#include <array>
#include <bit>
#include <cstddef>
#include <utility>

#include "cgamesh/cga/blade.hpp"

namespace cgamesh::cga {

template <class T, BladeMask M = kAllBlades>
class Multivector {
 public:
  using value_type = T;
  static constexpr BladeMask mask = M;
  static constexpr std::size_t size = static_cast<std::size_t>(std::popcount(M));
  /// blades[i] is the blade whose coefficient is stored at position i.
  static constexpr std::array<BladeIndex, size> blades = [] {
    std::array<BladeIndex, size> out{};
    std::size_t i = 0;
    for (BladeIndex b = 0; b < kBladeCount; ++b)
      if (has_blade(M, b)) out[i++] = b;
    return out;
  }();

  constexpr Multivector() noexcept = default;
  /// From coefficients in storage order (increasing blade index).
  constexpr explicit Multivector(const std::array<T, size>& coefficients) noexcept : c_(coefficients) {}

  /// Lossless widening from a type whose blades are a subset of ours.
  template <BladeMask N>
    requires((N & ~M) == 0 && N != M)
  constexpr Multivector(const Multivector<T, N>& other) noexcept {  // NOLINT(google-explicit-constructor)
    [&]<std::size_t... I>(std::index_sequence<I...>) {
      ((c_[storage_index(M, Multivector<T, N>::blades[I])] = other[I]), ...);
    }(std::make_index_sequence<Multivector<T, N>::size>{});
  }

  /// Coefficient at storage position i.
  [[nodiscard]] constexpr T operator[](std::size_t i) const noexcept { return c_[i]; }
  [[nodiscard]] constexpr T& operator[](std::size_t i) noexcept { return c_[i]; }

  /// Coefficient of blade B (zero when this type cannot hold it).
  template <BladeIndex B>
  [[nodiscard]] constexpr T get() const noexcept {
    if constexpr (has_blade(M, B)) return c_[storage_index(M, B)];
    else return T(0);
  }
  /// Mutable coefficient of blade B; B must be one of this type's blades.
  template <BladeIndex B>
    requires(has_blade(M, B))
  [[nodiscard]] constexpr T& at() noexcept {
    return c_[storage_index(M, B)];
  }
  /// Coefficient of blade b, chosen at run time (zero when absent).
  [[nodiscard]] constexpr T coefficient(BladeIndex b) const noexcept {
    return has_blade(M, b) ? c_[storage_index(M, b)] : T(0);
  }

  [[nodiscard]] constexpr const std::array<T, size>& coefficients() const noexcept { return c_; }

  constexpr Multivector& operator+=(const Multivector& o) noexcept {
    for (std::size_t i = 0; i < size; ++i) c_[i] += o.c_[i];
    return *this;
  }
  constexpr Multivector& operator-=(const Multivector& o) noexcept {
    for (std::size_t i = 0; i < size; ++i) c_[i] -= o.c_[i];
    return *this;
  }
  constexpr Multivector& operator*=(T s) noexcept {
    for (auto& x : c_) x *= s;
    return *this;
  }
  constexpr Multivector& operator/=(T s) noexcept {
    for (auto& x : c_) x /= s;
    return *this;
  }

  [[nodiscard]] friend constexpr bool operator==(const Multivector&, const Multivector&) noexcept = default;

 private:
  std::array<T, size> c_{};
};

/// The blades of b, as a basis element of type Multivector<T, 1 << b>.
template <class T, BladeIndex B>
[[nodiscard]] constexpr Multivector<T, BladeMask{1} << B> basis_blade(T coefficient = T(1)) noexcept {
  return Multivector<T, BladeMask{1} << B>({coefficient});
}

/// Drops every blade not in N (grade projection and friends are built on this).
template <BladeMask N, class T, BladeMask M>
[[nodiscard]] constexpr Multivector<T, N> project(const Multivector<T, M>& a) noexcept {
  Multivector<T, N> out;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    ((out[I] = a.template get<Multivector<T, N>::blades[I]>()), ...);
  }(std::make_index_sequence<Multivector<T, N>::size>{});
  return out;
}

// ---- Sums and scalings: blades of a sum are the union of the blades of its terms. ----

template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr Multivector<T, A | B> operator+(const Multivector<T, A>& a,
                                                       const Multivector<T, B>& b) noexcept {
  Multivector<T, A | B> out(a);
  out += Multivector<T, A | B>(b);
  return out;
}
template <class T, BladeMask A, BladeMask B>
[[nodiscard]] constexpr Multivector<T, A | B> operator-(const Multivector<T, A>& a,
                                                       const Multivector<T, B>& b) noexcept {
  Multivector<T, A | B> out(a);
  out -= Multivector<T, A | B>(b);
  return out;
}
template <class T, BladeMask A>
[[nodiscard]] constexpr Multivector<T, A> operator-(Multivector<T, A> a) noexcept {
  a *= T(-1);
  return a;
}
template <class T, BladeMask A>
[[nodiscard]] constexpr Multivector<T, A> operator*(Multivector<T, A> a, T s) noexcept {
  a *= s;
  return a;
}
template <class T, BladeMask A>
[[nodiscard]] constexpr Multivector<T, A> operator*(T s, Multivector<T, A> a) noexcept {
  a *= s;
  return a;
}
template <class T, BladeMask A>
[[nodiscard]] constexpr Multivector<T, A> operator/(Multivector<T, A> a, T s) noexcept {
  a /= s;
  return a;
}
/// Scalar plus multivector.
template <class T, BladeMask A>
[[nodiscard]] constexpr Multivector<T, A | 1u> operator+(T s, const Multivector<T, A>& a) noexcept {
  return basis_blade<T, blade::scalar>(s) + a;
}
template <class T, BladeMask A>
[[nodiscard]] constexpr Multivector<T, A | 1u> operator+(const Multivector<T, A>& a, T s) noexcept {
  return a + basis_blade<T, blade::scalar>(s);
}

// ---- The named types. ----
namespace mask {
inline constexpr BladeMask scalar = grade_mask(0);
inline constexpr BladeMask vector = grade_mask(1);
inline constexpr BladeMask bivector = grade_mask(2);
inline constexpr BladeMask trivector = grade_mask(3);
inline constexpr BladeMask quadvector = grade_mask(4);
inline constexpr BladeMask pseudoscalar = grade_mask(5);
/// Scalar + e12, e13, e23: rotations (eq. 8).
inline constexpr BladeMask rotor = (1u << 0) | (1u << blade::e12) | (1u << blade::e13) | (1u << blade::e23);
/// Scalar + t ^ einf: translations (eq. 10).
inline constexpr BladeMask translator = (1u << 0) | (1u << blade::e1inf) | (1u << blade::e2inf) | (1u << blade::e3inf);
/// Scalar + einf ^ eo: dilations about the origin (eq. 12).
inline constexpr BladeMask dilator = (1u << 0) | (1u << blade::info);
/// Translator times rotor: rigid motions.
inline constexpr BladeMask motor = rotor | translator | (1u << blade::e123inf);
/// The even subalgebra: every composition of translations, rotations and dilations.
inline constexpr BladeMask versor = kEvenBlades;
}  // namespace mask

template <class T> using Scalar = Multivector<T, mask::scalar>;
template <class T> using Vector = Multivector<T, mask::vector>;          ///< points, spheres, planes
template <class T> using Bivector = Multivector<T, mask::bivector>;      ///< point pairs, generators
template <class T> using Trivector = Multivector<T, mask::trivector>;    ///< circles, lines (outer forms)
template <class T> using Quadvector = Multivector<T, mask::quadvector>;  ///< spheres, planes (outer forms)
template <class T> using Pseudoscalar = Multivector<T, mask::pseudoscalar>;
template <class T> using Rotor = Multivector<T, mask::rotor>;
template <class T> using Translator = Multivector<T, mask::translator>;
template <class T> using Dilator = Multivector<T, mask::dilator>;
template <class T> using Motor = Multivector<T, mask::motor>;
template <class T> using Versor = Multivector<T, mask::versor>;  ///< translation * rotation * dilation
template <class T> using Dense = Multivector<T, kAllBlades>;

static_assert(Versor<float>::size == 16 && Motor<float>::size == 8 && Dense<double>::size == 32);
static_assert(Translator<float>::size == 4 && Rotor<float>::size == 4 && Dilator<float>::size == 2);

/// x1 e1 + x2 e2 + x3 e3 + x_inf einf + x_o eo (eq. 2).
template <class T>
[[nodiscard]] constexpr Vector<T> make_vector(T x1, T x2, T x3, T x_inf, T x_o) noexcept {
  return Vector<T>({x1, x2, x3, x_inf, x_o});
}
/// eo: the origin.
template <class T>
[[nodiscard]] constexpr Vector<T> eo() noexcept {
  return make_vector<T>(0, 0, 0, 0, 1);
}
/// einf: the point at infinity.
template <class T>
[[nodiscard]] constexpr Vector<T> einf() noexcept {
  return make_vector<T>(0, 0, 0, 1, 0);
}
/// e+ = einf/2 - eo (square +1).
template <class T>
[[nodiscard]] constexpr Vector<T> e_plus() noexcept {
  return make_vector<T>(0, 0, 0, T(0.5), T(-1));
}
/// e- = einf/2 + eo (square -1).
template <class T>
[[nodiscard]] constexpr Vector<T> e_minus() noexcept {
  return make_vector<T>(0, 0, 0, T(0.5), T(1));
}
/// A Euclidean vector x1 e1 + x2 e2 + x3 e3.
template <class T>
[[nodiscard]] constexpr Vector<T> euclidean(T x1, T x2, T x3) noexcept {
  return make_vector<T>(x1, x2, x3, 0, 0);
}

}  // namespace cgamesh::cga
