#include <cmath>

#include "cgamesh/errors.hpp"

#include "bindings.hpp"

namespace cgamesh::python {

py::array_t<std::int32_t> int_array(std::span<const int> values) {
  py::array_t<std::int32_t> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

py::dict origins_dict(std::span<const mesh::VertexSource> origins) {
  const auto n = static_cast<py::ssize_t>(origins.size());
  py::array_t<std::int32_t> vertices({n, py::ssize_t{3}});
  py::array_t<float> weights({n, py::ssize_t{3}});
  py::array_t<std::int8_t> kind(n);
  auto v = vertices.mutable_unchecked<2>();
  auto w = weights.mutable_unchecked<2>();
  auto k = kind.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const mesh::VertexSource& s = origins[static_cast<std::size_t>(i)];
    for (py::ssize_t c = 0; c < 3; ++c) {
      v(i, c) = s.vertex[static_cast<std::size_t>(c)];
      w(i, c) = s.weight[static_cast<std::size_t>(c)];
    }
    k(i) = static_cast<std::int8_t>(s.count());
  }
  py::dict out;
  out["vertices"] = vertices;
  out["weights"] = weights;
  out["kind"] = kind;
  return out;
}

py::array_t<double, py::array::c_style | py::array::forcecast> rows_of(const py::handle& a, py::ssize_t cols,
                                                                       const char* what, py::ssize_t rows) {
  auto arr = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!arr) throw InvalidInputError(std::string(what) + ": expected an array of numbers");
  const bool vector_ok = rows == 1 && arr.ndim() == 1 && arr.shape(0) == cols;
  if (!vector_ok && (arr.ndim() != 2 || arr.shape(1) != cols || (rows >= 0 && arr.shape(0) != rows)))
    throw InvalidInputError(std::string(what) + ": expected an array of shape (" +
                            (rows >= 0 ? std::to_string(rows) : std::string("N")) + ", " + std::to_string(cols) + ")");
  return arr;
}

Eigen::Vector3d vector3(const py::handle& a, const char* what) {
  const auto arr = rows_of(a, 3, what, 1);
  const double* d = arr.data();
  return {d[0], d[1], d[2]};
}

anim::Pose pose_or_bind(const anim::RiggedModel& model, const py::object& pose) {
  if (pose.is_none()) return anim::rest_pose(model.skeleton);
  const auto& p = pose.cast<const anim::Pose&>();
  if (static_cast<int>(p.local.size()) != model.skeleton.size())
    throw InvalidInputError("pose: it has " + std::to_string(p.local.size()) + " joints, the model's skeleton " +
                            std::to_string(model.skeleton.size()));
  return p;
}

ModelPtr make_model(anim::RiggedModel&& model, std::string file) {
  auto out = std::make_shared<Model>();
  out->model = std::move(model);
  out->file = std::move(file);
  return out;
}

}  // namespace cgamesh::python
