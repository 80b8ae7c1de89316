// cgamesh.cga: multivectors of G(4,1) (a dense 32-coefficient form of the library's
// Multivector) and the library's geometry, versors, exp/log and blends, single and batched.
#include <array>
#include <bit>
#include <cmath>
#include <vector>

#include "cgamesh/cga.hpp"
#include "cgamesh/errors.hpp"

#include "bindings.hpp"

namespace cgamesh::python {
namespace {

using Mv = cga::Dense<double>;
using cga::BladeIndex;

Mv dense(const Mv& a) { return a; }
template <cga::BladeMask M>
requires(M != cga::kAllBlades) Mv dense(const cga::Multivector<double, M>& a) { return Mv(a); }

/// Blade names in storage order: bit 0 e1, bit 1 e2, bit 2 e3, bit 3 einf, bit 4 eo; blade b is
/// the outer product of its vectors in increasing bit order.
std::vector<std::string> blade_names() {
  static const std::array<const char*, 5> vectors{"e1", "e2", "e3", "einf", "eo"};
  std::vector<std::string> out;
  for (BladeIndex b = 0; b < cga::kBladeCount; ++b) {
    if (b == 0) {
      out.emplace_back("1");
      continue;
    }
    std::string name;
    for (unsigned k = 0; k < 5; ++k)
      if ((b >> k) & 1u) name += (name.empty() ? "" : "^") + std::string(vectors[k]);
    out.push_back(name);
  }
  return out;
}

/// clifford's conformalize(Cl(3)) blade order: by grade, then lexicographic over e1..e5.
std::vector<unsigned> clifford_order() {
  std::vector<unsigned> masks;
  for (unsigned g = 0; g <= 5; ++g)
    for (unsigned b = 0; b < 32; ++b)
      if (static_cast<unsigned>(std::popcount(b)) == g) masks.push_back(b);
  // Within a grade, lexicographic order of index tuples = increasing order of the reversed bits.
  std::stable_sort(masks.begin(), masks.end(), [](unsigned a, unsigned b) {
    if (std::popcount(a) != std::popcount(b)) return std::popcount(a) < std::popcount(b);
    for (unsigned k = 0; k < 5; ++k) {
      const bool ia = (a >> k) & 1u, ib = (b >> k) & 1u;
      if (ia != ib) return ia;
    }
    return false;
  });
  return masks;
}

std::vector<std::string> clifford_names() {
  std::vector<std::string> out;
  for (const unsigned b : clifford_order()) {
    std::string name = b == 0 ? "1" : "e";
    for (unsigned k = 0; k < 5; ++k)
      if ((b >> k) & 1u) name += std::to_string(k + 1);
    out.push_back(name);
  }
  return out;
}

/// The 32×32 change of basis: row i, column j the coefficient of target blade i in source blade
/// j. `vectors[k]` writes source basis vector k over the target basis vectors; `index[mask]` is
/// the position of the target blade `mask`. An outer product of basis vectors does not depend on
/// the metric, so each source blade expands term by term, with the sign of sorting its vectors.
Eigen::Matrix<double, 32, 32> change_of_basis(const std::array<std::array<double, 5>, 5>& vectors,
                                              const std::vector<unsigned>& index) {
  Eigen::Matrix<double, 32, 32> out = Eigen::Matrix<double, 32, 32>::Zero();
  for (unsigned source = 0; source < 32; ++source) {
    std::vector<unsigned> bits;
    for (unsigned k = 0; k < 5; ++k)
      if ((source >> k) & 1u) bits.push_back(k);
    // Every choice of one target vector per source vector.
    const std::size_t n = bits.size();
    std::vector<unsigned> choice(n, 0);
    while (true) {
      double coef = 1;
      unsigned mask = 0;
      int inversions = 0;
      bool repeated = false;
      for (std::size_t i = 0; i < n && !repeated; ++i) {
        coef *= vectors[bits[i]][choice[i]];
        if ((mask >> choice[i]) & 1u) repeated = true;
        mask |= 1u << choice[i];
        for (std::size_t k = 0; k < i; ++k) inversions += choice[k] > choice[i] ? 1 : 0;
      }
      if (!repeated && coef != 0) out(index[mask], source) += (inversions % 2 ? -coef : coef);
      std::size_t i = 0;
      while (i < n && ++choice[i] == 5) choice[i++] = 0;
      if (i == n) break;
    }
  }
  return out;
}

/// to_clifford (our coefficients → clifford's) and from_clifford.
const std::array<Eigen::Matrix<double, 32, 32>, 2>& clifford_maps() {
  static const std::array<Eigen::Matrix<double, 32, 32>, 2> maps = [] {
    const std::vector<unsigned> order = clifford_order();
    std::vector<unsigned> clifford_index(32), identity(32);
    for (unsigned i = 0; i < 32; ++i) clifford_index[order[i]] = i, identity[i] = i;
    // e1 e2 e3 as they are; einf = e4 + e5, eo = (e5 − e4) / 2 (e4 = e+, e5 = e−).
    const std::array<std::array<double, 5>, 5> to{
        {{1, 0, 0, 0, 0}, {0, 1, 0, 0, 0}, {0, 0, 1, 0, 0}, {0, 0, 0, 1, 1}, {0, 0, 0, -0.5, 0.5}}};
    // e4 = einf/2 − eo, e5 = einf/2 + eo.
    const std::array<std::array<double, 5>, 5> from{
        {{1, 0, 0, 0, 0}, {0, 1, 0, 0, 0}, {0, 0, 1, 0, 0}, {0, 0, 0, 0.5, -1}, {0, 0, 0, 0.5, 1}}};
    Eigen::Matrix<double, 32, 32> back = change_of_basis(from, identity);
    // Columns of `back` are clifford blades by bit mask; reorder to clifford's order.
    Eigen::Matrix<double, 32, 32> from_clifford;
    for (unsigned i = 0; i < 32; ++i) from_clifford.col(i) = back.col(order[i]);
    return std::array<Eigen::Matrix<double, 32, 32>, 2>{change_of_basis(to, clifford_index), from_clifford};
  }();
  return maps;
}

/// `values` (…×32) mapped by `map` (rows of the result: map · row).
py::array_t<double> map_rows(const Eigen::Matrix<double, 32, 32>& map, const py::handle& values) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  if (!a || a.ndim() < 1 || a.shape(a.ndim() - 1) != 32)
    throw InvalidInputError("expected an array of shape (32,) or (N, 32)");
  py::array_t<double> out(std::vector<py::ssize_t>(a.shape(), a.shape() + a.ndim()));
  const py::ssize_t rows = a.size() / 32;
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, 32, Eigen::RowMajor>;
  Eigen::Map<const Rows> in(a.data(), rows, 32);
  Eigen::Map<Rows> res(out.mutable_data(), rows, 32);
  res = in * map.transpose();
  return out;
}

Mv from_values(const py::handle& values) {
  const auto a = rows_of(values, 32, "value", 1);
  Mv m;
  for (std::size_t i = 0; i < 32; ++i) m[i] = a.data()[i];
  return m;
}

Mv grade_of(const Mv& a, int k) {
  if (k < 0 || k > 5) throw InvalidInputError("grade: k must be 0 … 5");
  Mv out;
  for (BladeIndex b = 0; b < 32; ++b)
    if (static_cast<int>(cga::grade(b)) == k) out[b] = a[b];
  return out;
}

BladeIndex blade_index(const std::string& name) {
  const auto names = blade_names();
  for (BladeIndex b = 0; b < 32; ++b)
    if (names[b] == name) return b;
  throw InvalidInputError("blade '" + name + "': expected one of 1, e1, e1^e2, ..., e1^e2^e3^einf^eo");
}

/// Rows of a #N×32 array as multivectors, f applied to each, written to a #N×K array.
template <int K, class F>
py::array_t<double> per_row(const py::array_t<double, py::array::c_style | py::array::forcecast>& a, F&& f) {
  const py::ssize_t n = a.shape(0);
  py::array_t<double> out({n, py::ssize_t{K}});
  const double* in = a.data();
  double* res = out.mutable_data();
  const std::size_t cols = static_cast<std::size_t>(a.shape(1));
  {
    py::gil_scoped_release release;
    for (py::ssize_t i = 0; i < n; ++i) f(in + static_cast<std::size_t>(i) * cols, res + i * K);
  }
  return out;
}

/// A (cols,) or #N×cols float64 array (a copy only when dtype or layout differ).
py::array_t<double, py::array::c_style | py::array::forcecast> one_or_rows(const py::handle& x, py::ssize_t cols,
                                                                           const char* what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(x);
  if (!a || !((a.ndim() == 1 && a.shape(0) == cols) || (a.ndim() == 2 && a.shape(1) == cols)))
    throw InvalidInputError(std::string(what) + ": expected an array of shape (" + std::to_string(cols) + ",) or (N, " +
                            std::to_string(cols) + ")");
  return a;
}

Mv rows_to_mv(const double* row) {
  Mv m;
  for (std::size_t c = 0; c < 32; ++c) m[c] = row[c];
  return m;
}

void mv_to_row(const Mv& m, double* row) {
  for (std::size_t c = 0; c < 32; ++c) row[c] = m[c];
}

cga::Vec3<double> vec3(const double* p) { return {p[0], p[1], p[2]}; }

}  // namespace

void add_cga(py::module_& m) {
  py::class_<Mv>(m, "Multivector",
                 "A multivector of G(4,1): 32 float64 coefficients over the null basis e1 e2 e3 einf eo (blade b = "
                 "outer product of the vectors of its bits, bit 0 e1 … bit 4 eo; blade_names lists them). "
                 "Operators: * geometric, ^ outer, | inner (Hestenes, no scalars), << left contraction, >> right "
                 "contraction, ~ reverse; + - with multivectors and numbers.")
      .def(py::init<>(), "zero")
      .def(py::init([](double s) {
             Mv x;
             x[0] = s;
             return x;
           }),
           py::arg("scalar"))
      .def(py::init(
               [](const py::array_t<double, py::array::c_style | py::array::forcecast>& v) { return from_values(v); }),
           py::arg("value"), "from 32 coefficients in blade order")
      .def_property(
          "value",
          [](py::object self) {
            auto& me = self.cast<Mv&>();
            return view(&me[0], {32}, self, true);
          },
          [](Mv& me, const py::handle& v) { me = from_values(v); },
          "the 32 float64 coefficients: a writable view of this multivector's storage (no copy)")
      .def(
          "__getitem__",
          [](const Mv& a, const py::handle& key) {
            if (py::isinstance<py::int_>(key)) {
              const int i = key.cast<int>();
              if (i < 0 || i >= 32) throw py::index_error("blade index out of range 0 … 31");
              return a[static_cast<std::size_t>(i)];
            }
            return a[blade_index(key.cast<std::string>())];
          },
          "coefficient of a blade, by index or name ('e1^einf')")
      .def("__add__", [](const Mv& a, const Mv& b) { return dense(a + b); })
      .def("__add__", [](const Mv& a, double s) { return dense(a + s); })
      .def("__radd__", [](const Mv& a, double s) { return dense(s + a); })
      .def("__sub__", [](const Mv& a, const Mv& b) { return dense(a - b); })
      .def("__sub__", [](const Mv& a, double s) { return dense(a + (-s)); })
      .def("__rsub__", [](const Mv& a, double s) { return dense(s + (-a)); })
      .def("__neg__", [](const Mv& a) { return dense(-a); })
      .def("__mul__", [](const Mv& a, const Mv& b) { return dense(a * b); })
      .def("__mul__", [](const Mv& a, double s) { return dense(a * s); })
      .def("__rmul__", [](const Mv& a, double s) { return dense(s * a); })
      .def("__truediv__", [](const Mv& a, double s) { return dense(a / s); })
      .def("__truediv__", [](const Mv& a, const Mv& b) { return dense(a * cga::inverse(b)); })
      .def("__xor__", [](const Mv& a, const Mv& b) { return dense(a ^ b); })
      .def("__or__", [](const Mv& a, const Mv& b) { return dense(a | b); })
      .def("__lshift__", [](const Mv& a, const Mv& b) { return dense(cga::left_contraction(a, b)); })
      .def("__rshift__", [](const Mv& a, const Mv& b) { return dense(cga::right_contraction(a, b)); })
      .def("__invert__", [](const Mv& a) { return cga::reverse(a); })
      .def("__eq__", [](const Mv& a, const Mv& b) { return a == b; })
      .def("reverse", [](const Mv& a) { return cga::reverse(a); })
      .def(
          "involution", [](const Mv& a) { return cga::involution(a); }, "grade involution")
      .def(
          "conjugate", [](const Mv& a) { return cga::conjugate(a); }, "Clifford conjugate")
      .def(
          "dual", [](const Mv& a) { return dense(cga::dual(a)); }, "−a I (I = e1^e2^e3^einf^eo)")
      .def("undual", [](const Mv& a) { return dense(cga::undual(a)); })
      .def(
          "inv", [](const Mv& a) { return cga::inverse(a); }, "the inverse (raises InvalidInputError if none)")
      .def("grade", &grade_of, py::arg("k"), "the grade-k part")
      .def(
          "scalar", [](const Mv& a) { return a[0]; }, "the scalar part")
      .def(
          "norm", [](const Mv& a) { return cga::norm(a); }, "sqrt(|<a ~a>_0|)")
      .def("__copy__", [](const Mv& a) { return a; })
      .def("__repr__", [](const Mv& a) {
        const auto names = blade_names();
        std::string out;
        for (BladeIndex b = 0; b < 32; ++b)
          if (a[b] != 0) {
            char buffer[48];
            std::snprintf(buffer, sizeof buffer, "%.6g", a[b]);
            out += (out.empty() ? "" : " + ") + std::string(buffer) + (b == 0 ? "" : " " + names[b]);
          }
        return "Multivector(" + (out.empty() ? std::string("0") : out) + ")";
      });

  m.attr("blade_names") = blade_names();
  m.attr("clifford_blade_names") = clifford_names();
  const auto basis = [](BladeIndex b) {
    Mv x;
    x[b] = 1;
    return x;
  };
  m.attr("e1") = basis(cga::blade::e1);
  m.attr("e2") = basis(cga::blade::e2);
  m.attr("e3") = basis(cga::blade::e3);
  m.attr("einf") = basis(cga::blade::einf);
  m.attr("eo") = basis(cga::blade::eo);
  m.attr("e4") = Mv(cga::e_plus<double>());
  m.attr("e5") = Mv(cga::e_minus<double>());
  m.attr("I") = basis(cga::blade::pseudoscalar);
  m.def(
      "blade", [basis](const std::string& name) { return basis(blade_index(name)); }, py::arg("name"),
      "the unit blade named as in blade_names");

  m.def(
      "up",
      [](const py::handle& x) -> py::object {
        const auto a = one_or_rows(x, 3, "points");
        if (a.ndim() == 1) return py::cast(dense(cga::up(vec3(a.data()))));
        return per_row<32>(a, [](const double* p, double* out) {
          const cga::Vector<double> v = cga::up(vec3(p));
          std::fill(out, out + 32, 0.0);
          for (std::size_t k = 0; k < 5; ++k) out[cga::Vector<double>::blades[k]] = v[k];
        });
      },
      py::arg("x"),
      "Conformal point x + ½|x|² einf + eo (eq. 2): x of shape (3,) → Multivector; #N×3 → #N×32 float64 "
      "(batched, GIL released).");
  m.def(
      "down",
      [](const py::handle& x) -> py::object {
        if (py::isinstance<Mv>(x)) {
          const auto v = cga::down(cga::project<cga::mask::vector>(x.cast<const Mv&>()));
          py::array_t<double> out(3);
          for (int c = 0; c < 3; ++c) out.mutable_at(c) = v[c];
          return out;
        }
        const auto a = one_or_rows(x, 32, "points");
        if (a.ndim() == 1) {
          const auto v = cga::down(cga::project<cga::mask::vector>(rows_to_mv(a.data())));
          py::array_t<double> out(3);
          for (int c = 0; c < 3; ++c) out.mutable_at(c) = v[c];
          return out;
        }
        return per_row<3>(a, [](const double* p, double* out) {
          const auto v = cga::down(cga::project<cga::mask::vector>(rows_to_mv(p)));
          for (int c = 0; c < 3; ++c) out[c] = v[c];
        });
      },
      py::arg("X"),
      "The Euclidean point of a conformal point (its vector part, any weight): Multivector → (3,) float64; "
      "#N×32 → #N×3. Raises InvalidInputError for a non-point.");
  m.def(
      "sphere", [](const py::handle& c, double r) { return dense(cga::sphere(vector3(c, "center"), r)); },
      py::arg("center"), py::arg("radius"), "The dual sphere up(c) − ½ r² einf.");
  m.def(
      "plane", [](const py::handle& n, double d) { return dense(cga::plane(vector3(n, "normal"), d)); },
      py::arg("normal"), py::arg("d"), "The plane n̂ + d einf of n·x = d (eq. 5; n normalised).");
  m.def(
      "rotor", [](const py::handle& axis, double angle) { return dense(cga::rotor(vector3(axis, "axis"), angle)); },
      py::arg("axis"), py::arg("angle"), "Rotation by `angle` radians about `axis` (eq. 8).");
  m.def(
      "translator", [](const py::handle& t) { return dense(cga::translator(vector3(t, "translation"))); }, py::arg("t"),
      "Translation by t (eq. 10).");
  m.def(
      "dilator", [](double s) { return dense(cga::dilator(s)); }, py::arg("s"),
      "Uniform scaling by s > 0 about the origin (eq. 12).");
  m.def(
      "exp", [](const Mv& b) { return dense(cga::exp(cga::project<cga::mask::bivector>(b))); }, py::arg("B"),
      "exp of the bivector part of B (closed form): a versor.");
  m.def(
      "log", [](const Mv& v) { return dense(cga::log(cga::project<cga::mask::versor>(v))); }, py::arg("V"),
      "Logarithm of a TRS versor (its even part): a bivector with exp(log(V)) = V (up to a positive factor).");
  m.def(
      "sandwich",
      [](const Mv& v, const py::handle& x) -> py::object {
        if (py::isinstance<Mv>(x)) return py::cast(dense(cga::sandwich(v, x.cast<const Mv&>())));
        const auto a = one_or_rows(x, 32, "X");
        if (a.ndim() == 1) return py::cast(dense(cga::sandwich(v, rows_to_mv(a.data()))));
        const Mv inv = cga::versor_inverse(v);
        return per_row<32>(a, [&](const double* p, double* out) { mv_to_row(dense(v * rows_to_mv(p) * inv), out); });
      },
      py::arg("V"), py::arg("X"),
      "V X V⁻¹: X a Multivector → Multivector; X #N×32 → #N×32 float64 (batched, GIL released).");
  m.def(
      "lerp", [](const Mv& a, const Mv& b, double alpha) { return cga::lerp(a, b, alpha); }, py::arg("a"), py::arg("b"),
      py::arg("alpha"), "(1 − alpha) a + alpha b.");
  m.def(
      "log_blend",
      [](const Mv& a, const Mv& b, double alpha) {
        return dense(cga::log_blend(cga::project<cga::mask::versor>(a), cga::project<cga::mask::versor>(b), alpha));
      },
      py::arg("a"), py::arg("b"), py::arg("alpha"),
      "a exp(alpha log(a⁻¹ b)) of unit TRS versors (the paper's blend of file keyframes).");
  m.def(
      "to_clifford", [](const py::handle& v) { return map_rows(clifford_maps()[0], v); }, py::arg("values"),
      "Coefficients (32,) or #N×32 in cgamesh's order → the `clifford` package's conformalize(Cl(3)) layout "
      "(blade order clifford_blade_names; e4 = e+, e5 = e−, einf = e4 + e5, eo = (e5 − e4)/2).");
  m.def(
      "from_clifford", [](const py::handle& v) { return map_rows(clifford_maps()[1], v); }, py::arg("values"),
      "The inverse of to_clifford.");
}

}  // namespace cgamesh::python
