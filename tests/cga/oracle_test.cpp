// Comparison with ganja.js, an independent GA implementation (tests/oracle/README.md).
//
// The table is written in the ORTHONORMAL basis e1, e2, e3, e+, e- (bit 3 = e+, bit 4 = e-,
// each blade the geometric product of its vectors in increasing bit order); cgamesh stores the
// NULL basis. Each orthonormal blade is built here as the geometric product of cgamesh's
// e1, e2, e3, e_plus(), e_minus(), so the basis change goes through our own product (whose
// basis table is checked against the metric in products_test.cpp).

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <fstream>
#include <stdexcept>
#include <string>

#include "cga/test_util.hpp"

namespace {

using namespace cgatest;  // NOLINT(google-build-using-namespace)
using json = nlohmann::json;

/// The 32 blades of the orthonormal basis, as cgamesh multivectors.
const std::array<Dense<double>, kBladeCount>& orthonormal_blades() {
  static const auto blades = [] {
    const std::array<Vector<double>, 5> e{euclidean<double>(1, 0, 0), euclidean<double>(0, 1, 0),
                                          euclidean<double>(0, 0, 1), e_plus<double>(), e_minus<double>()};
    std::array<Dense<double>, kBladeCount> out;
    for (BladeIndex b = 0; b < kBladeCount; ++b) {
      Dense<double> blade(basis_blade<double, blade::scalar>());
      for (unsigned k = 0; k < 5; ++k)
        if ((b >> k) & 1u) blade = blade * e[k];
      out[b] = blade;
    }
    return out;
  }();
  return blades;
}

/// A multivector given by its 32 orthonormal-basis coefficients.
Dense<double> from_orthonormal(const json& coefficients) {
  if (!coefficients.is_array() || coefficients.size() != kBladeCount)
    throw std::runtime_error("oracle: a multivector is not an array of 32 numbers");
  Dense<double> out;
  for (BladeIndex b = 0; b < kBladeCount; ++b) out += orthonormal_blades()[b] * coefficients[b].get<double>();
  return out;
}

/// The table, parsed once per process (ctest runs every test in a process of its own, and the
/// 9 MB parse dominates in Debug+sanitizers: so all comparisons with it are in one test).
const json& oracle_table() {
  static const json table = [] {
    std::ifstream in(CGAMESH_ORACLE_TABLE);
    if (!in.good()) throw std::runtime_error("cannot open " CGAMESH_ORACLE_TABLE);
    return json::parse(in);
  }();
  return table;
}

::testing::AssertionResult same(const Dense<double>& ours, const json& theirs, double tol = 1e-12) {
  return mv_near(ours, from_orthonormal(theirs), tol);
}

TEST(Oracle, BasisChangeIsConsistent) {
  // The orthonormal blades are the expected null-basis combinations: e+ e- = einf ^ eo, e.g.
  const auto& ob = orthonormal_blades();
  EXPECT_MV_NEAR(ob[24], basis_blade<double, blade::info>(), 0.0);
  EXPECT_MV_NEAR(ob[8], e_plus<double>(), 0.0);
  EXPECT_MV_NEAR(ob[16], e_minus<double>(), 0.0);
  EXPECT_MV_NEAR(ob[31], pseudoscalar<double>(), 0.0);
  EXPECT_MV_NEAR(ob[5], basis_blade<double, blade::e13>(), 0.0);
  // The orthonormal blades are a basis: the Gram matrix of the scalar product is diagonal +-1.
  for (BladeIndex a = 0; a < kBladeCount; ++a)
    for (BladeIndex b = 0; b < kBladeCount; ++b) {
      const double s = scalar_product(ob[a], reverse(ob[b]));
      if (a == b) {
        EXPECT_EQ(std::abs(s), 1.0) << a;
      } else {
        EXPECT_EQ(s, 0.0) << a << "," << b;
      }
    }
}

/// gp, op, lc, dot, rev, inv_grade, conj, dual and inv of the 1200 random pairs.
void check_products_and_unary_operations(const json& table) {
  // The blade order of the table is the one documented.
  ASSERT_EQ(table.at("order").get<std::string>(), "bitmask e1=1,e2=2,e3=4,e+=8,e-=16");
  ASSERT_EQ(table.at("blade_names").at(24).get<std::string>(), "e+-");
  const json& cases = table.at("cases");
  ASSERT_GE(cases.size(), 1000u);
  int compared = 0, inverses = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const json& c = cases[k];
    const Dense<double> a = from_orthonormal(c.at("a")), b = from_orthonormal(c.at("b"));
    ASSERT_TRUE(same(a * b, c.at("gp"))) << "gp, case " << k;
    ASSERT_TRUE(same(a ^ b, c.at("op"))) << "op, case " << k;
    ASSERT_TRUE(same(left_contraction(a, b), c.at("lc"))) << "lc, case " << k;
    ASSERT_TRUE(same(fat_dot(a, b), c.at("dot"))) << "dot, case " << k;
    ASSERT_TRUE(same(reverse(a), c.at("rev"))) << "rev, case " << k;
    ASSERT_TRUE(same(involution(a), c.at("inv_grade"))) << "inv_grade, case " << k;
    ASSERT_TRUE(same(conjugate(a), c.at("conj"))) << "conj, case " << k;
    ASSERT_TRUE(same(dual(a), c.at("dual"))) << "dual, case " << k;
    compared += 8;
    if (!c.at("inv").is_null()) {
      const Dense<double> inv = inverse(a);
      // The inverse is a degree-8 rational function: scale the tolerance by its conditioning.
      const double tol = 1e-12 * std::max(1.0, max_abs(a) * max_abs(inv));
      ASSERT_TRUE(same(inv, c.at("inv"), tol)) << "inv, case " << k;
      ++compared;
      ++inverses;
    }
  }
  EXPECT_GE(compared, 1000);
  EXPECT_GE(inverses, 1000);
}

/// exp of the 200 random bivectors, and the sandwich of a random vector by it.
void check_exp_and_sandwich(const json& table) {
  const json& cases = table.at("versor_cases");
  ASSERT_GE(cases.size(), 100u);
  int compared = 0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const json& c = cases[k];
    const Dense<double> b_dense = from_orthonormal(c.at("exp_biv"));
    const Bivector<double> biv = project<mask::bivector>(b_dense);
    ASSERT_MV_NEAR(biv, b_dense, 0.0) << "the generator is a bivector, case " << k;
    const Dense<double> ganja_exp = from_orthonormal(c.at("exp"));
    // The Taylor reference and the closed form (invariant decomposition) against ganja's.
    ASSERT_MV_NEAR(exp_series(biv), ganja_exp, 1e-12) << "exp_series, case " << k;
    ASSERT_MV_NEAR(exp(biv), ganja_exp, 1e-12) << "exp, case " << k;
    // The sandwich of a vector by ganja's exp.
    const Versor<double> v = project<mask::versor>(ganja_exp);
    ASSERT_MV_NEAR(v, ganja_exp, 0.0) << "exp is even, case " << k;
    const Vector<double> x = project<mask::vector>(from_orthonormal(c.at("b")));
    ASSERT_TRUE(same(unit_sandwich(v, x), c.at("sandwich"))) << "sandwich, case " << k;
    ASSERT_TRUE(same(sandwich(v, x), c.at("sandwich"), 1e-11)) << "sandwich, case " << k;
    compared += 4;
  }
  EXPECT_GE(compared, 400);
}

TEST(Oracle, MatchesGanja) {
  const json* table = nullptr;
  ASSERT_NO_THROW(table = &oracle_table());
  {
    SCOPED_TRACE("cases");
    check_products_and_unary_operations(*table);
  }
  {
    SCOPED_TRACE("versor_cases");
    check_exp_and_sandwich(*table);
  }
}

}  // namespace
