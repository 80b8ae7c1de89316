#pragma once
// What the binding files of the Python module share: numpy views and conversions, the Model
// the module hands out, and the functions that add each part to the module. The bindings are a
// thin front end: every result comes from the library functions the CLI calls.

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/mesh/mesh.hpp"
#include "cgamesh/mesh/vertex_source.hpp"

namespace cgamesh::python {

namespace py = pybind11;

/// A model as Python holds it: the rigged model and the file it was read from ("" when made).
struct Model {
  anim::RiggedModel model;
  std::string file;
};
using ModelPtr = std::shared_ptr<Model>;

/// A numpy array over `data` (row-major, `shape`), no copy: `owner` is kept alive as the array's
/// base. Read-only unless `writable`.
template <class T>
py::array_t<T> view(const T* data, std::vector<py::ssize_t> shape, py::handle owner, bool writable = false) {
  py::array_t<T> a(std::move(shape), data, owner);
  if (!writable) py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// `value` moved to the heap and returned as a numpy array over its storage (no copy): a capsule
/// owns it. `shape` must fit its size.
template <class Matrix>
py::array_t<typename Matrix::Scalar> adopt(Matrix&& value, std::vector<py::ssize_t> shape) {
  auto* heap = new Matrix(std::forward<Matrix>(value));
  py::capsule owner(heap, [](void* p) { delete static_cast<Matrix*>(p); });
  return py::array_t<typename Matrix::Scalar>(std::move(shape), heap->data(), owner);
}

/// A #rows×Cols row-major float matrix as a numpy array (no copy).
template <int Cols>
py::array_t<float> adopt_rows(mesh::RowMatrixXf<Cols>&& m) {
  const py::ssize_t rows = m.rows();
  return adopt(std::move(m), {rows, Cols});
}

/// A vector of ints as an int32 array (copied).
py::array_t<std::int32_t> int_array(std::span<const int> values);

/// Per vertex origins as numpy arrays: {"vertices": #V×3 int32 (old vertex ids, −1 for unused
/// slots), "weights": #V×3 float32 (barycentric weights), "kind": #V int8 (1 copy of an old
/// vertex, 2 point on an old edge, 3 point inside an old face)}.
py::dict origins_dict(std::span<const mesh::VertexSource> origins);

/// `a` as a C-contiguous double array of shape (rows, cols) (rows −1: any); a copy only when
/// its dtype or layout differs.
/// @throws InvalidInputError naming `what` for another shape.
py::array_t<double, py::array::c_style | py::array::forcecast> rows_of(const py::handle& a, py::ssize_t cols,
                                                                       const char* what, py::ssize_t rows = -1);

/// Exactly three numbers.
/// @throws InvalidInputError naming `what` otherwise.
Eigen::Vector3d vector3(const py::handle& a, const char* what);

/// The pose argument of a function: a Pose, or None for the bind pose of `model`.
anim::Pose pose_or_bind(const anim::RiggedModel& model, const py::object& pose);

/// A Model Python owns, from `model` (moved).
ModelPtr make_model(anim::RiggedModel&& model, std::string file = {});

void add_errors(py::module_& m);
void add_model(py::module_& m);
void add_surgery(py::module_& m);
void add_deform(py::module_& m);
void add_soft(py::module_& m);
void add_cga(py::module_& m);

}  // namespace cgamesh::python
