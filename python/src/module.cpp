// The extension module cgamesh._cgamesh; the package cgamesh (python/cgamesh) re-exports it.
#include "cgamesh/errors.hpp"

#include "bindings.hpp"

namespace cgamesh::python {

void add_errors(py::module_& m) {
  // Translators are tried last-registered first, so the most derived kinds come last.
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<InvalidInputError> invalid(m, "InvalidInputError", error.ptr());
  static py::exception<FileError> file(m, "FileError", invalid.ptr());
  static py::exception<WriteError> write(m, "WriteError", error.ptr());
  static py::exception<TopologyError> topology(m, "TopologyError", error.ptr());
  static py::exception<SolverError> solver(m, "SolverError", error.ptr());
  static py::exception<PlatformError> platform(m, "PlatformError", error.ptr());
  error.doc() = "Base of every error cgamesh raises (C++ cgamesh::Error); the message is the library's.";
  invalid.doc() = "An argument or input is unusable: NaN, a degenerate plane, an unknown joint, a bad spec.";
  file.doc() = "An input file cannot be read or does not hold a valid model (missing, truncated, corrupt).";
  write.doc() = "An output file could not be written (nothing is left behind).";
  topology.doc() = "The mesh's connectivity does not allow the operation (the tool misses, nothing to cut).";
  solver.doc() = "A numerical method failed (singular system, no convergence).";
  platform.doc() = "The machine cannot provide what was asked (no OpenGL context, no window system).";
  py::register_exception_translator([](std::exception_ptr p) {
    if (!p) return;
    try {
      std::rethrow_exception(p);
    } catch (const FileError& e) {
      PyErr_SetString(file.ptr(), e.what());
    } catch (const InvalidInputError& e) {
      PyErr_SetString(invalid.ptr(), e.what());
    } catch (const WriteError& e) {
      PyErr_SetString(write.ptr(), e.what());
    } catch (const TopologyError& e) {
      PyErr_SetString(topology.ptr(), e.what());
    } catch (const SolverError& e) {
      PyErr_SetString(solver.ptr(), e.what());
    } catch (const PlatformError& e) {
      PyErr_SetString(platform.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
}

}  // namespace cgamesh::python

PYBIND11_MODULE(_cgamesh, m) {
  using namespace cgamesh::python;
  m.doc() =
      "cgamesh: Conformal Geometric Algebra animation, surgery and deformation of rigged models "
      "(the C++ library, numpy in and out). Import the package `cgamesh`, not this module.";
  add_errors(m);
  add_model(m);
  add_surgery(m);
  add_deform(m);
  add_soft(m);
  py::module_ cga = m.def_submodule("cga", "The algebra G(4,1) of conformal geometric algebra");
  add_cga(cga);
}
