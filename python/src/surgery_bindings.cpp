// cgamesh.cut, tear, drill and LiveModel: the surgery of the CLI's cut/tear/drill commands.
#include <cmath>

#include "cgamesh/cga/geometry.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/io/surgery_stats.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/tear.hpp"

#include "bindings.hpp"

namespace cgamesh::python {
namespace {

/// One model a surgery operation made, with where its vertices come from.
struct SurgeryResult {
  ModelPtr model;
  std::vector<int> source_mesh;                          ///< per mesh: the input mesh
  std::vector<std::vector<mesh::VertexSource>> origins;  ///< per mesh, per vertex
  std::vector<mesh::RowMatrixXf<3>> placed;              ///< per mesh, #V×3 placed positions
  anim::Pose pose;                                       ///< the pose the tool was placed against
  py::dict stats;
};

surgery::RestPosition rest_of(const std::string& rest) { return io::value_by_name(io::kRestPositions, rest, "rest"); }

surgery::Predicates predicates_of(const std::string& p) { return io::value_by_name(io::kPredicates, p, "predicates"); }

cga::Vector<double> plane_of(const py::handle& plane) {
  const auto p = rows_of(plane, 4, "plane (nx, ny, nz, d)", 1);
  const double* d = p.data();
  return surgery::cut_plane({d[0], d[1], d[2]}, d[3]);
}

std::vector<surgery::Scalpel> scalpel_of(const py::handle& steps) {
  const auto a = rows_of(steps, 6, "scalpel_steps (handle xyz, tip xyz per step)");
  std::vector<surgery::Scalpel> out;
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    const double* r = a.data(i, 0);
    out.push_back({{r[0], r[1], r[2]}, {r[3], r[4], r[5]}});
  }
  return out;
}

py::dict change_dict(const surgery::MeshChange& c) {
  py::dict d;
  d["mesh"] = c.mesh;
  d["first_new_vertex"] = c.first_new_vertex;
  d["origins"] = origins_dict(c.origins);
  d["new_faces"] = int_array(c.new_faces);
  py::array_t<std::int32_t> moved({static_cast<py::ssize_t>(c.moved_faces.size()), py::ssize_t{2}});
  for (std::size_t i = 0; i < c.moved_faces.size(); ++i)
    for (std::size_t k = 0; k < 2; ++k) moved.mutable_at(i, k) = c.moved_faces[i][k];
  d["moved_faces"] = moved;
  d["removed_faces"] = c.removed_faces;
  return d;
}

void copy_origins(std::vector<std::vector<mesh::VertexSource>>& out, const anim::RiggedModel& model) {
  for (const mesh::Mesh& me : model.meshes) {
    std::vector<mesh::VertexSource> o;
    for (int v = 0; v < me.vertex_count(); ++v) o.push_back(mesh::VertexSource::copy(v));
    out.push_back(std::move(o));
  }
}

/// Options of a tool with the choices every tool takes.
template <class Options>
Options tool_options(const std::string& rest, const std::string& predicates) {
  Options o;
  o.rest = rest_of(rest);
  o.predicates = predicates_of(predicates);
  return o;
}

/// The counts of an operation as a dict, with the keys the CLI's --json reports
/// (io::stats_json), and its warnings.
template <class Stats>
py::dict stats_dict(const Stats& s) {
  py::dict d = py::module_::import("json").attr("loads")(io::stats_json(s));
  d["warnings"] = s.warnings;
  return d;
}

py::dict cut_stats(const surgery::CutStats& c) { return stats_dict(c); }

/// With the path as #P×3 float64.
py::dict tear_stats(const surgery::TearStats& t) {
  py::dict d = stats_dict(t);
  py::array_t<double> path({static_cast<py::ssize_t>(t.path.size()), py::ssize_t{3}});
  for (std::size_t i = 0; i < t.path.size(); ++i)
    for (int c = 0; c < 3; ++c) path.mutable_at(i, c) = t.path[i][c];
  d["path"] = path;
  return d;
}

py::dict drill_stats(const surgery::DrillStats& r) { return stats_dict(r); }

const char* kCommonOptions =
    " pose: a Pose (Model.pose()) the tool is placed against, or None for the bind pose; rest: 'exact' or "
    "'parametric' rest positions of new vertices; predicates: 'cga' or 'euclidean' (same result). Releases the GIL.";

}  // namespace

void add_surgery(py::module_& m) {
  py::class_<SurgeryResult>(m, "SurgeryResult", "A model made by cut, tear or drill, with the origin of every vertex.")
      .def_readonly("model", &SurgeryResult::model, "the new Model (skin, skeleton and clips kept)")
      .def_property_readonly(
          "source_mesh", [](const SurgeryResult& r) { return int_array(r.source_mesh); },
          "int32 per mesh: the input mesh it came from")
      .def_property_readonly(
          "origins",
          [](const SurgeryResult& r) {
            py::list out;
            for (const auto& o : r.origins) out.append(origins_dict(o));
            return out;
          },
          "per mesh, a dict of arrays: 'vertices' #V×3 int32 input vertex ids (-1 unused), 'weights' #V×3 float32 "
          "barycentric weights, 'kind' #V int8 (1 copy, 2 point on an edge, 3 point in a face)")
      .def_property_readonly(
          "placed",
          [](py::object self) {
            const auto& r = self.cast<const SurgeryResult&>();
            py::list out;
            for (const auto& p : r.placed) out.append(view(p.data(), {p.rows(), 3}, self));
            return out;
          },
          "per mesh, #V×3 float32 positions as placed (the pose the tool was used in); read-only views")
      .def_readonly("stats", &SurgeryResult::stats, "the counts the CLI's --json reports")
      .def(
          "save",
          [](const SurgeryResult& r, const std::filesystem::path& file) {
            const std::string path = file.string();
            py::gil_scoped_release release;
            (void)io::write_model(r.model->model, path, [&] {
              return mesh::WorldSurface{r.placed, surgery::placed_normals(r.model->model, r.pose)};
            });
          },
          py::arg("path"),
          "Writes the result as the CLI does: .glb/.gltf rigged, .obj/.ply the surface as placed, with its normals "
          "skinned into that pose. Atomic.");

  m.def(
      "cut",
      [](const Model& model, const py::handle& plane, const py::object& pose, bool cap, bool own_side_influences,
         const std::string& rest, const std::string& predicates) {
        const cga::Vector<double> pi = plane_of(plane);
        auto options = tool_options<surgery::CutOptions>(rest, predicates);
        options.cap = cap;
        options.own_side_influences = own_side_influences;
        const anim::Pose p = pose_or_bind(model.model, pose);
        surgery::ModelCut c;
        {
          py::gil_scoped_release release;
          c = surgery::cut(model.model, surgery::place(model.model, p), pi, options);
        }
        py::dict stats = cut_stats(c);
        stats["faces_out"] = py::make_tuple(c.faces_out[0], c.faces_out[1]);
        std::array<SurgeryResult, 2> out;
        for (std::size_t k = 0; k < 2; ++k) {
          out[k].model = make_model(std::move(c.pieces[k]));
          out[k].source_mesh = std::move(c.source_mesh[k]);
          out[k].origins = std::move(c.origins[k]);
          out[k].placed = std::move(c.placed[k]);
          out[k].pose = p;
          out[k].stats = stats;
        }
        return py::make_tuple(std::move(out[0]), std::move(out[1]));
      },
      py::arg("model"), py::arg("plane"), py::arg("pose") = py::none(), py::arg("cap") = false,
      py::arg("own_side_influences") = false, py::arg("rest") = "exact", py::arg("predicates") = "cga",
      (std::string("Cuts the model with the plane n·x = d, plane = (nx, ny, nz, d), as `cgamesh cut`: returns "
                   "(piece_a, piece_b), two SurgeryResult; piece A is the side n·x > d. cap: close each piece; "
                   "own_side_influences: new vertices take influences from their side only.") +
       kCommonOptions)
          .c_str());

  m.def(
      "tear",
      [](const Model& model, const py::handle& scalpel_steps, const py::object& pose, double open,
         bool own_side_influences, const std::string& rest, const std::string& predicates) {
        const std::vector<surgery::Scalpel> steps = scalpel_of(scalpel_steps);
        auto options = tool_options<surgery::TearOptions>(rest, predicates);
        options.open = open;
        options.own_side_influences = own_side_influences;
        const anim::Pose p = pose_or_bind(model.model, pose);
        surgery::ModelTear t;
        surgery::Placement placement;
        {
          py::gil_scoped_release release;
          placement = surgery::place(model.model, p);
          t = surgery::tear(model.model, placement, steps, options);
        }
        SurgeryResult r;
        for (std::size_t i = 0; i < t.model.meshes.size(); ++i) r.source_mesh.push_back(static_cast<int>(i));
        copy_origins(r.origins, model.model);
        r.origins[static_cast<std::size_t>(t.mesh)] = std::move(t.origins);
        r.placed = std::move(placement.positions);
        r.placed[static_cast<std::size_t>(t.mesh)] = std::move(t.placed);
        r.pose = p;
        py::array_t<std::int8_t> side(static_cast<py::ssize_t>(t.side.size()));
        std::copy(t.side.begin(), t.side.end(), side.mutable_data());
        r.stats = tear_stats(t);
        r.stats["mesh"] = t.mesh;
        r.stats["side"] = side;
        r.model = make_model(std::move(t.model));
        return r;
      },
      py::arg("model"), py::arg("scalpel_steps"), py::arg("pose") = py::none(), py::arg("open") = 0.0,
      py::arg("own_side_influences") = false, py::arg("rest") = "exact", py::arg("predicates") = "cga",
      (std::string("Tears the model along the path a scalpel sweeps, as `cgamesh tear`: scalpel_steps is #S×6 "
                   "(handle xyz, tip xyz per time step, S >= 2, world space as placed); open: the opening width. "
                   "Returns a SurgeryResult (stats: path #P×3, side #V int8 of the torn mesh).") +
       kCommonOptions)
          .c_str());

  m.def(
      "drill",
      [](const Model& model, const py::handle& tip, const py::handle& base, double radius, const py::object& pose,
         bool wall, int min_rim_points, int max_refinements, int max_region_faces, const std::string& rest,
         const std::string& predicates) {
        const Eigen::Vector3d a = vector3(tip, "tip"), b = vector3(base, "base");
        auto options = tool_options<surgery::DrillOptions>(rest, predicates);
        options.wall = wall;
        options.min_rim_points = min_rim_points;
        options.max_refinements = max_refinements;
        options.max_region_faces = max_region_faces;
        const anim::Pose p = pose_or_bind(model.model, pose);
        surgery::ModelDrill d;
        {
          py::gil_scoped_release release;
          d = surgery::drill(model.model, surgery::place(model.model, p), a, b, radius, options);
        }
        if (d.model.meshes.empty()) throw TopologyError("drill: the drill removes the whole model");
        SurgeryResult r;
        r.source_mesh = std::move(d.source_mesh);
        r.origins = std::move(d.origins);
        r.placed = std::move(d.placed);
        r.pose = p;
        r.stats = drill_stats(d);
        r.model = make_model(std::move(d.model));
        return r;
      },
      py::arg("model"), py::arg("tip"), py::arg("base"), py::arg("radius"), py::arg("pose") = py::none(),
      py::arg("wall") = false, py::arg("min_rim_points") = 6, py::arg("max_refinements") = 6,
      py::arg("max_region_faces") = 20000, py::arg("rest") = "exact", py::arg("predicates") = "cga",
      (std::string("Drills a hole with the cylinder of `radius` from base to tip (world space, as placed), as "
                   "`cgamesh drill`; wall: line each hole with a tube. Returns a SurgeryResult. Raises TopologyError "
                   "when the drill misses.") +
       kCommonOptions)
          .c_str());

  py::class_<surgery::LiveModel>(m, "LiveModel",
                                 "A model placed in one pose that cut/tear/drill edit in place, at the cost of the "
                                 "edited region; each returns what changed as arrays.")
      .def(py::init([](const Model& model, const py::object& pose) {
             const anim::Pose p = pose_or_bind(model.model, pose);
             py::gil_scoped_release release;
             surgery::Placement placement = surgery::place(model.model, p);
             return surgery::LiveModel(model.model, std::move(placement));
           }),
           py::arg("model"), py::arg("pose") = py::none(),
           "Copies `model`, places it in `pose` (None: the bind pose) and indexes its surface.")
      .def_property_readonly(
          "model", [](const surgery::LiveModel& l) { return make_model(anim::RiggedModel(l.model())); },
          "a copy of the edited model (a snapshot: later operations do not change it)")
      .def(
          "placed_positions",
          [](const surgery::LiveModel& l) {
            py::list out;
            for (const auto& p : l.placement().positions) out.append(adopt_rows<3>(mesh::RowMatrixXf<3>(p)));
            return out;
          },
          "per mesh, a copy of the #V×3 float32 placed positions")
      .def(
          "cut",
          [](surgery::LiveModel& l, const py::handle& plane, bool own_side_influences, const std::string& rest,
             const std::string& predicates) {
            const cga::Vector<double> pi = plane_of(plane);
            auto options = tool_options<surgery::CutOptions>(rest, predicates);
            options.own_side_influences = own_side_influences;
            surgery::LiveCut c;
            {
              py::gil_scoped_release release;
              c = surgery::cut(l, pi, options);
            }
            py::dict out = cut_stats(c);
            py::list changes, pieces;
            for (const auto& ch : c.changes) changes.append(change_dict(ch));
            for (const auto& p : c.piece_of_new_face) {
              py::array_t<std::int8_t> a(static_cast<py::ssize_t>(p.size()));
              std::copy(p.begin(), p.end(), a.mutable_data());
              pieces.append(a);
            }
            out["changes"] = changes;
            out["piece_of_new_face"] = pieces;
            out["faces_out"] = c.faces_out;
            return out;
          },
          py::arg("plane"), py::arg("own_side_influences") = false, py::arg("rest") = "exact",
          py::arg("predicates") = "cga",
          "Cuts in place with the plane (nx, ny, nz, d); returns {'changes': [MeshChange dicts], "
          "'piece_of_new_face': [#new int8 per change], counts...}. A MeshChange dict: mesh, first_new_vertex, "
          "origins (as SurgeryResult.origins, per new vertex), new_faces int32, moved_faces #K×2 int32 (before, "
          "after), removed_faces.")
      .def(
          "tear",
          [](surgery::LiveModel& l, const py::handle& scalpel_steps, double open, bool own_side_influences,
             const std::string& rest, const std::string& predicates) {
            const std::vector<surgery::Scalpel> steps = scalpel_of(scalpel_steps);
            auto options = tool_options<surgery::TearOptions>(rest, predicates);
            options.open = open;
            options.own_side_influences = own_side_influences;
            surgery::LiveTear t;
            {
              py::gil_scoped_release release;
              t = surgery::tear(l, steps, options);
            }
            py::dict out = tear_stats(t);
            out["changes"] = py::make_tuple(change_dict(t.change));
            return out;
          },
          py::arg("scalpel_steps"), py::arg("open") = 0.0, py::arg("own_side_influences") = false,
          py::arg("rest") = "exact", py::arg("predicates") = "cga",
          "Tears in place (as cgamesh.tear); returns {'changes': (MeshChange dict,), counts...}.")
      .def(
          "drill",
          [](surgery::LiveModel& l, const py::handle& tip, const py::handle& base, double radius, bool wall,
             const std::string& rest, const std::string& predicates) {
            const Eigen::Vector3d a = vector3(tip, "tip"), b = vector3(base, "base");
            auto options = tool_options<surgery::DrillOptions>(rest, predicates);
            options.wall = wall;
            surgery::LiveDrill d;
            {
              py::gil_scoped_release release;
              d = surgery::drill(l, a, b, radius, options);
            }
            py::dict out = drill_stats(d);
            py::list changes;
            for (const auto& ch : d.changes) changes.append(change_dict(ch));
            out["changes"] = changes;
            return out;
          },
          py::arg("tip"), py::arg("base"), py::arg("radius"), py::arg("wall") = false, py::arg("rest") = "exact",
          py::arg("predicates") = "cga", "Drills in place (as cgamesh.drill); returns {'changes': [...], counts...}.");
}

}  // namespace cgamesh::python
