// cgamesh.Tissue: living tissue (soft/tissue.hpp) on a LiveModel, as the CLI's --soft and the
// viewer's tissue panel use it.
#include <array>
#include <string>
#include <vector>

#include "cgamesh/errors.hpp"
#include "cgamesh/soft/tissue.hpp"
#include "cgamesh/surgery/live_model.hpp"

#include "bindings.hpp"

namespace cgamesh::python {

namespace {

/// The MeshChange of a dict as LiveModel.cut/tear/drill return them (their "changes" entries).
/// @throws InvalidInputError for a missing key or arrays of the wrong shape.
surgery::MeshChange change_of(const py::handle& h) {
  if (!py::isinstance<py::dict>(h))
    throw InvalidInputError("a change must be a dict as LiveModel.cut, tear and drill return in 'changes'");
  const auto d = py::reinterpret_borrow<py::dict>(h);
  for (const char* key : {"mesh", "first_new_vertex", "origins", "new_faces", "moved_faces", "removed_faces"})
    if (!d.contains(key)) throw InvalidInputError(std::string("a change has no '") + key + "'");
  surgery::MeshChange c;
  c.mesh = d["mesh"].cast<int>();
  c.first_new_vertex = d["first_new_vertex"].cast<int>();
  c.removed_faces = d["removed_faces"].cast<int>();
  const py::dict origins = d["origins"].cast<py::dict>();
  const auto vertices = rows_of(origins["vertices"], 3, "origins['vertices']");
  const auto weights = rows_of(origins["weights"], 3, "origins['weights']", vertices.shape(0));
  for (py::ssize_t i = 0; i < vertices.shape(0); ++i) {
    mesh::VertexSource s;
    for (py::ssize_t k = 0; k < 3; ++k) {
      s.vertex[static_cast<std::size_t>(k)] = static_cast<int>(vertices.at(i, k));
      s.weight[static_cast<std::size_t>(k)] = static_cast<float>(weights.at(i, k));
    }
    c.origins.push_back(s);
  }
  for (const py::handle f : d["new_faces"].cast<py::array_t<int, py::array::forcecast>>()) c.new_faces.push_back(f.cast<int>());
  const auto moved = rows_of(d["moved_faces"], 2, "moved_faces");
  for (py::ssize_t i = 0; i < moved.shape(0); ++i)
    c.moved_faces.push_back({static_cast<int>(moved.at(i, 0)), static_cast<int>(moved.at(i, 1))});
  return c;
}

/// The changes of an operation's result dict (its "changes"), or of a list of change dicts.
std::vector<surgery::MeshChange> changes_of(const py::handle& result) {
  py::handle list = result;
  if (py::isinstance<py::dict>(result)) {
    const auto d = py::reinterpret_borrow<py::dict>(result);
    if (!d.contains("changes")) return {change_of(result)};
    list = d["changes"];
  }
  std::vector<surgery::MeshChange> out;
  for (const py::handle c : list) out.push_back(change_of(c));
  return out;
}

/// A Tissue with the LiveModel it is bound to, which it keeps alive: every call acts on that one.
struct PyTissue {
  py::object live_object;
  soft::Tissue tissue;
  [[nodiscard]] surgery::LiveModel& live() const { return live_object.cast<surgery::LiveModel&>(); }
};

py::dict settle_dict(const soft::SettleReport& r) {
  py::dict d;
  d["seconds"] = r.seconds;
  d["substeps"] = r.substeps;
  d["max_speed"] = r.max_speed;
  d["settled"] = r.settled;
  return d;
}

}  // namespace

void add_soft(py::module_& m) {
  py::class_<PyTissue>(m, "Tissue",
                       "Living tissue on a LiveModel (XPBD on the skinned surface): wounds made by the LiveModel's "
                       "cut, tear and drill open under the skin's tension and keep animating. Only a region around "
                       "the wounds is simulated; elsewhere positions are the skinned ones.")
      .def(py::init([](const py::object& live, double density, double attachment_compliance, double stretch_compliance,
                       double bend_compliance, double pretension, double damping, double substep,
                       const py::handle& gravity, double region_radius, double release_margin, int max_particles) {
             soft::TissueOptions o;
             o.density = density;
             o.attachment_compliance = attachment_compliance;
             o.stretch_compliance = stretch_compliance;
             o.bend_compliance = bend_compliance;
             o.pretension = pretension;
             o.damping = damping;
             o.substep = substep;
             o.gravity = vector3(gravity, "gravity");
             o.region_radius = region_radius;
             o.release_margin = release_margin;
             o.max_particles = max_particles;
             const surgery::LiveModel& l = live.cast<const surgery::LiveModel&>();
             return PyTissue{live, soft::Tissue(l, o)};
           }),
           py::arg("live"), py::arg("density") = soft::TissueOptions{}.density,
           py::arg("attachment_compliance") = soft::TissueOptions{}.attachment_compliance,
           py::arg("stretch_compliance") = soft::TissueOptions{}.stretch_compliance,
           py::arg("bend_compliance") = soft::TissueOptions{}.bend_compliance,
           py::arg("pretension") = soft::TissueOptions{}.pretension, py::arg("damping") = soft::TissueOptions{}.damping,
           py::arg("substep") = soft::TissueOptions{}.substep,
           py::arg("gravity") = std::array<double, 3>{0.0, -9.81, 0.0},
           py::arg("region_radius") = soft::TissueOptions{}.region_radius,
           py::arg("release_margin") = soft::TissueOptions{}.release_margin,
           py::arg("max_particles") = soft::TissueOptions{}.max_particles,
           "Binds tissue to `live` (kept alive). Options as soft::TissueOptions (units: model units, seconds, kg): "
           "density per area, compliances (inverse stiffness) of the attachment to the skin, of stretch and of "
           "bending, pretension (fraction in [0, 1)), damping per second, substep (s), gravity (3), region_radius "
           "and release_margin (0: 10 % of the diagonal, a quarter of the region), max_particles (the region's "
           "budget, 0: none). Raises InvalidInputError naming a bad option.")
      .def_property_readonly("live", [](const PyTissue& t) { return t.live_object; }, "the LiveModel it is bound to")
      .def(
          "follow",
          [](PyTissue& t, const py::handle& result) {
            const std::vector<surgery::MeshChange> changes = changes_of(result);
            py::gil_scoped_release release;
            t.tissue.follow(t.live(), changes);
          },
          py::arg("result"),
          "Follows an operation of the LiveModel: pass what its cut/tear/drill returned (or its 'changes'). "
          "Call it after each operation, before the next step.")
      .def(
          "select",
          [](PyTissue& t, int mesh, const py::handle& center, double radius) {
            t.tissue.select(t.live(), mesh, vector3(center, "center"), radius);
          },
          py::arg("mesh"), py::arg("center"), py::arg("radius"),
          "Adds the vertices of `mesh` within `radius` of `center` (placed) to the simulated region.")
      .def(
          "step",
          [](PyTissue& t, const anim::Pose& pose, double dt) {
            py::gil_scoped_release release;
            t.tissue.step(t.live(), pose, dt);
          },
          py::arg("pose"), py::arg("dt"),
          "Advances by dt seconds towards `pose` in fixed substeps. Raises SolverError when the state diverges "
          "(it is then as before).")
      .def(
          "settle",
          [](PyTissue& t, const anim::Pose& pose, double max_seconds, double tolerance) {
            soft::SettleReport r;
            {
              py::gil_scoped_release release;
              r = t.tissue.settle(t.live(), pose, max_seconds, tolerance);
            }
            return settle_dict(r);
          },
          py::arg("pose"), py::arg("max_seconds") = 5.0, py::arg("tolerance") = 1e-3,
          "Steps in `pose` until every particle is slower than tolerance × the diagonal per second; returns "
          "{'seconds', 'substeps', 'max_speed', 'settled'}.")
      .def(
          "positions",
          [](const PyTissue& t, const anim::Pose& pose) {
            std::vector<mesh::RowMatrixXf<3>> p;
            {
              py::gil_scoped_release release;
              p = t.tissue.positions(t.live(), pose);
            }
            py::list out;
            for (auto& x : p) out.append(adopt_rows<3>(std::move(x)));
            return out;
          },
          py::arg("pose"), "Per mesh, #V×3 float32 world positions: simulated in the region, skinned elsewhere.")
      .def(
          "bake",
          [](const PyTissue& t, const anim::Pose& pose) {
            anim::RiggedModel baked;
            {
              py::gil_scoped_release release;
              baked = t.tissue.bake(t.live(), pose);
            }
            return make_model(std::move(baked));
          },
          py::arg("pose"),
          "A Model whose rest positions hold the simulated surface (through the inverse of each vertex's "
          "skinning in `pose`): it animates with the wound as simulated.")
      .def_property_readonly("total_mass", [](const PyTissue& t) { return t.tissue.total_mass(); }, "kg")
      .def_property_readonly(
          "particles", [](const PyTissue& t) { return t.tissue.particles(); }, "particles of the region")
      .def_property_readonly(
          "free_particles", [](const PyTissue& t) { return t.tissue.free_particles(); }, "simulated particles")
      .def_property_readonly("links", [](const PyTissue& t) { return t.tissue.links(); }, "stretch and bending links");
}

}  // namespace cgamesh::python
