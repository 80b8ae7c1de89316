// cgamesh.deform, Deformer and harmonic_field: the deformation spec of `cgamesh deform`
// (deform/spec.hpp) and its building blocks.
#include <memory>

#include "cgamesh/deform/bspline_fit.hpp"
#include "cgamesh/deform/fabrik.hpp"
#include "cgamesh/deform/harmonic_field.hpp"
#include "cgamesh/deform/motor_blend.hpp"
#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/text_values.hpp"

#include "bindings.hpp"

namespace cgamesh::python {
namespace {

/// A bound spec, with the model it was bound to (deformed_model() and save() need it).
struct Deformer {
  ModelPtr model;
  std::unique_ptr<deform::BoundDeformer> bound;
  deform::DeformSpec spec;
};

/// The spec as JSON text: a dict (dumped by Python's json module) or the text itself.
std::string spec_text(const py::handle& spec) {
  if (py::isinstance<py::str>(spec)) return spec.cast<std::string>();
  return py::module_::import("json").attr("dumps")(spec).cast<std::string>();
}

/// Versors from a list of cga.Multivector or a #n×32 array of coefficients (their even parts).
std::vector<cga::Versor<double>> versor_list(const py::handle& keys) {
  std::vector<cga::Versor<double>> out;
  if (py::isinstance<py::array>(keys)) {
    const auto a = rows_of(keys, 32, "keys");
    for (py::ssize_t i = 0; i < a.shape(0); ++i) {
      cga::Dense<double> v;
      for (std::size_t c = 0; c < 32; ++c) v[c] = a.at(i, static_cast<py::ssize_t>(c));
      out.push_back(cga::project<cga::mask::versor>(v));
    }
    return out;
  }
  for (const py::handle k : keys) out.push_back(cga::project<cga::mask::versor>(k.cast<cga::Dense<double>>()));
  return out;
}

/// Versors as a #n×32 float64 array.
py::array_t<double> versor_array(std::span<const cga::Versor<double>> versors) {
  py::array_t<double> out({static_cast<py::ssize_t>(versors.size()), py::ssize_t{32}});
  for (std::size_t i = 0; i < versors.size(); ++i) {
    const cga::Dense<double> v(versors[i]);
    for (std::size_t c = 0; c < 32; ++c) out.mutable_at(i, c) = v[c];
  }
  return out;
}

/// Key versors: None (the spec's), or as versor_list() takes them.
std::vector<cga::Versor<double>> keys_of(const Deformer& d, const py::object& keys) {
  if (keys.is_none()) return d.bound->keys();
  return versor_list(keys);
}

/// #N×3 positions as float32 rows (the precision meshes store), N = rows unless −1.
mesh::RowMatrixXf<3> float_rows(const py::handle& positions, const char* what, py::ssize_t rows = -1) {
  const auto p = rows_of(positions, 3, what, rows);
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(p.data(), p.shape(0), 3)
      .cast<float>();
}

py::array_t<float> apply_keys(const Deformer& d, const py::object& keys) {
  const std::vector<cga::Versor<double>> k = keys_of(d, keys);
  mesh::RowMatrixXf<3> out;
  {
    py::gil_scoped_release release;
    d.bound->apply(k, out);
  }
  return adopt_rows<3>(std::move(out));
}

/// A Model, or a Mesh as a model of that one static mesh (its skin dropped: mesh space).
ModelPtr model_of(const py::handle& model_or_mesh) {
  if (py::isinstance<Model>(model_or_mesh)) return model_or_mesh.cast<ModelPtr>();
  anim::RiggedModel m;
  m.meshes.push_back(model_or_mesh.cast<const mesh::Mesh&>());
  m.meshes.back().skin = {};
  m.meshes.back().node = -1;
  m.meshes.back().material = -1;
  m.meshes.back().face_materials.resize(0);
  return make_model(std::move(m));
}

Deformer bind(const py::handle& model_or_mesh, const py::handle& spec) {
  Deformer d;
  d.model = model_of(model_or_mesh);
  const ModelPtr& model = d.model;
  const std::string text = spec_text(spec);
  d.spec = deform::parse_spec(text, "spec");
  py::gil_scoped_release release;
  d.bound = std::make_unique<deform::BoundDeformer>(d.spec, model->model);
  return d;
}

}  // namespace

void add_deform(py::module_& m) {
  py::class_<Deformer>(m, "Deformer",
                       "A deformation spec (the JSON of `cgamesh deform`, README 'Deformation specs') bound to one "
                       "mesh of a model: the harmonic solve and blend weights done once; apply() per frame.")
      .def(py::init(&bind), py::arg("model"), py::arg("spec"),
           "Parses `spec` (a dict, or JSON text) and binds it to the model (a Model, or a Mesh: a model of that "
           "static mesh) (as `cgamesh deform` does). Raises "
           "InvalidInputError naming the spec's field. Releases the GIL while binding.")
      .def_property_readonly(
          "mesh", [](const Deformer& d) { return d.bound->mesh_index(); }, "index of the deformed mesh")
      .def_property_readonly(
          "space", [](const Deformer& d) { return d.bound->space() == deform::DeformSpace::world ? "world" : "mesh"; },
          "'world' (bind pose, world space) or 'mesh'")
      .def_property_readonly("method",
                             [](const Deformer& d) { return std::string(deform::method_name(d.spec.method())); })
      .def_property_readonly(
          "rest_positions",
          [](py::object self) {
            const auto& r = self.cast<const Deformer&>().bound->rest_positions();
            return view(r.data(), {r.rows(), 3}, self);
          },
          "#V×3 float32 rest positions in `space` (a read-only view)")
      .def_property_readonly(
          "handles",
          [](const Deformer& d) {
            py::list out;
            for (const auto& h : d.bound->handles()) out.append(int_array(h));
            return out;
          },
          "per handle, the int32 vertex ids it selects")
      .def_property_readonly(
          "free_vertices", [](const Deformer& d) { return int_array(d.bound->free_vertices()); },
          "int32 ids of the vertices in parts without a handle")
      .def_property_readonly(
          "keys", [](const Deformer& d) { return versor_array(d.bound->keys()); },
          "#n×32 float64 the spec's key versors (cgamesh.cga coefficient order)")
      .def("apply", &apply_keys, py::arg("keys") = py::none(),
           "One frame: #V×3 float32 deformed positions in `space`. keys: None (the spec's), a list of "
           "cga.Multivector versors or a #n×32 array. Releases the GIL.")
      .def(
          "deformed_model",
          [](const Deformer& d, const py::handle& positions) {
            const mesh::RowMatrixXf<3> f = float_rows(positions, "positions", d.bound->vertex_count());
            return make_model(d.bound->deformed_model(d.model->model, f), d.model->file);
          },
          py::arg("positions"),
          "The model with the mesh's rest shape replaced by `positions` (#V×3 in `space`), skin and clips kept.")
      .def(
          "save",
          [](const Deformer& d, const std::filesystem::path& file, const py::object& positions) {
            const std::string path = file.string();
            mesh::RowMatrixXf<3> deformed;
            if (positions.is_none()) {
              py::gil_scoped_release release;
              d.bound->apply(d.bound->keys(), deformed);
            } else {
              deformed = float_rows(positions, "positions", d.bound->vertex_count());
            }
            py::gil_scoped_release release;
            (void)d.bound->write(d.model->model, deformed, path);
          },
          py::arg("path"), py::arg("positions") = py::none(),
          "Writes what `cgamesh deform --spec SPEC -o path` writes (positions: None for the spec's keys): .glb/.gltf "
          "the deformed rigged model, .obj/.ply every mesh in `space`, the deformed one changed. Atomic.");

  m.def(
      "deform",
      [](const py::handle& model, const py::handle& spec) {
        Deformer d = bind(model, spec);
        return apply_keys(d, py::none());
      },
      py::arg("model"), py::arg("spec"),
      "Deforms mesh spec['mesh'] of `model` (a Model, or a Mesh: then in mesh space) by a spec (dict or JSON text, as "
      "`cgamesh deform --spec` reads it) "
      "with the spec's keys: #V×3 float32 positions in the spec's space. Use Deformer to apply other keys or to "
      "save. Releases the GIL.");

  py::class_<deform::MotorBlend>(m, "MotorBlend",
                                 "Blends key versors per vertex (paper eq. 2): p_i = M_i p'_i ~M_i, M_i = exp(Σ_j "
                                 "w_ij log K_j).")
      .def(py::init([](const py::handle& rest, const py::handle& weights, const py::handle& rest_keys) {
             const mesh::RowMatrixXf<3> r = float_rows(rest, "rest");
             const auto w = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(weights);
             if (!w || w.ndim() != 2 || w.shape(0) != r.rows())
               throw InvalidInputError("weights: expected a #V×n array, one row per rest position");
             deform::WeightMatrix wm = Eigen::Map<const deform::WeightMatrix>(w.data(), w.shape(0), w.shape(1));
             const std::vector<cga::Versor<double>> k = versor_list(rest_keys);
             py::gil_scoped_release release;
             return deform::MotorBlend(r, std::move(wm), k);
           }),
           py::arg("rest"), py::arg("weights"), py::arg("rest_keys"),
           "Binds rest positions #V×3 with weights #V×n to the n rest key versors (list of cga.Multivector or "
           "#n×32).")
      .def_property_readonly("vertex_count", &deform::MotorBlend::vertex_count)
      .def_property_readonly("key_count", &deform::MotorBlend::key_count)
      .def(
          "deform",
          [](const deform::MotorBlend& b, const py::handle& keys) {
            const std::vector<cga::Versor<double>> k = versor_list(keys);
            mesh::RowMatrixXf<3> out;
            {
              py::gil_scoped_release release;
              b.deform(k, out);
            }
            return adopt_rows<3>(std::move(out));
          },
          py::arg("keys"), "One frame for the n posed key versors: #V×3 float32. Releases the GIL.");

  m.def(
      "fabrik",
      [](const py::handle& joints, const py::handle& target, double tolerance, int max_iterations) {
        const auto j = rows_of(joints, 3, "joints");
        std::vector<Eigen::Vector3d> chain;
        for (py::ssize_t i = 0; i < j.shape(0); ++i) chain.emplace_back(j.at(i, 0), j.at(i, 1), j.at(i, 2));
        const deform::FabrikResult r = deform::fabrik(chain, vector3(target, "target"),
                                                      {.tolerance = tolerance, .max_iterations = max_iterations});
        py::array_t<double> solved({static_cast<py::ssize_t>(r.joints.size()), py::ssize_t{3}});
        for (std::size_t i = 0; i < r.joints.size(); ++i)
          for (int c = 0; c < 3; ++c) solved.mutable_at(i, c) = r.joints[i][c];
        std::vector<cga::Versor<double>> motors(r.motors.begin(), r.motors.end());
        py::dict out;
        out["reached"] = r.reached;
        out["iterations"] = r.iterations;
        out["distance"] = r.distance;
        out["joints"] = solved;
        out["motors"] = versor_array(motors);
        return out;
      },
      py::arg("joints"), py::arg("target"), py::arg("tolerance") = 1e-6, py::arg("max_iterations") = 100,
      "FABRIK inverse kinematics (paper III.C) of the chain joints #J×3 (root first) towards target: {'reached', "
      "'iterations', 'distance', 'joints' #J×3 solved positions, 'motors' #J×32 motors from the rest chain}.");

  m.def(
      "fit_bspline_motors",
      [](const py::handle& keys, const py::handle& parameters, std::size_t control_count, int degree) {
        const std::vector<cga::Versor<double>> k = versor_list(keys);
        const std::vector<double> t = parameters.cast<std::vector<double>>();
        const deform::BsplineFit f = deform::fit_bspline_motors(k, t, control_count, {.degree = degree});
        py::dict out;
        out["control"] = versor_array(f.control);
        out["rms_residual"] = f.rms_residual;
        out["max_residual"] = f.max_residual;
        out["used_svd"] = f.used_svd;
        return out;
      },
      py::arg("keys"), py::arg("parameters"), py::arg("control_count"), py::arg("degree") = 3,
      "Least-squares B-spline fit (paper eqs. 3-5) of control versors to key versors at parameters in [0, 1]: "
      "{'control' #m×32, 'rms_residual', 'max_residual', 'used_svd'}.");

  struct HarmonicField {
    std::shared_ptr<deform::HarmonicPrecomputation> pre;
  };
  py::class_<HarmonicField>(m, "HarmonicField",
                            "The factorised Laplacian of a mesh with a constrained vertex set (harmonic_field()).")
      .def_property_readonly("vertex_count", [](const HarmonicField& h) { return h.pre->vertex_count(); })
      .def_property_readonly("constrained", [](const HarmonicField& h) { return int_array(h.pre->constrained); })
      .def(
          "solve",
          [](const HarmonicField& h, const py::handle& boundary) {
            const auto b = py::array_t<double, py::array::f_style | py::array::forcecast>::ensure(boundary);
            if (!b || b.ndim() < 1 || b.ndim() > 2 || b.shape(0) != h.pre->constrained_count())
              throw InvalidInputError("boundary: expected " + std::to_string(h.pre->constrained_count()) +
                                      " values (or a #C×k array), one row per constrained vertex");
            const bool flat = b.ndim() == 1;
            const Eigen::Index k = flat ? 1 : b.shape(1);
            const Eigen::MatrixXd values = Eigen::Map<const Eigen::MatrixXd>(b.data(), b.shape(0), k);
            Eigen::MatrixXd x;
            {
              py::gil_scoped_release release;
              x = deform::harmonic_solve(*h.pre, values);
            }
            using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
            const py::ssize_t n = x.rows();
            if (flat) return adopt(Rows(x), {n});
            return adopt(Rows(x), {n, static_cast<py::ssize_t>(k)});
          },
          py::arg("boundary"),
          "Fields with the given values at the constrained vertices: boundary #C (or #C×k) float64 → #V (or "
          "#V×k) float64. Releases the GIL.");

  m.def(
      "harmonic_field",
      [](const py::handle& positions, const py::handle& faces, const py::handle& constrained,
         const std::string& weights) {
        const auto f = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(faces);
        if (!f || f.ndim() != 2 || f.shape(1) != 3) throw InvalidInputError("faces: expected a #F×3 integer array");
        const auto c = py::array_t<int, py::array::c_style | py::array::forcecast>::ensure(constrained);
        if (!c || c.ndim() != 1) throw InvalidInputError("constrained: expected a 1-D array of vertex ids");
        mesh::Mesh me;
        me.positions = float_rows(positions, "positions");
        me.faces = Eigen::Map<const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>>(f.data(), f.shape(0), 3);
        deform::HarmonicOptions options;
        options.weights = io::value_by_name(deform::kLaplacianWeights, weights, "weights");
        const std::vector<int> ids(c.data(), c.data() + c.shape(0));
        HarmonicField h;
        py::gil_scoped_release release;
        h.pre = std::make_shared<deform::HarmonicPrecomputation>(deform::harmonic_precompute(me, ids, options));
        return h;
      },
      py::arg("positions"), py::arg("faces"), py::arg("constrained"), py::arg("weights") = "mean_value",
      "Precomputes harmonic fields (paper eq. 14) on the mesh positions #V×3 (float, stored as float32 as meshes "
      "are), faces #F×3 int, with Dirichlet values on the `constrained` vertex ids: a HarmonicField whose "
      "solve() gives the fields. Releases the GIL.");
}

}  // namespace cgamesh::python
