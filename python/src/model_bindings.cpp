// cgamesh.load, Model, Mesh, Skeleton, Clip, Pose: models in and out, posing and skinning.
#include <charconv>
#include <cmath>
#include <map>

#include "cgamesh/anim/keyframes.hpp"
#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/pose_choice.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_info.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/mesh/subdivide.hpp"

#include "bindings.hpp"

namespace cgamesh::python {
namespace {

/// `x` in the shortest text that reads back exactly.
std::string exact_text(double x) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, r.ptr);
}

std::string numbers_text(const py::handle& values, std::size_t count, const std::string& what) {
  std::vector<double> v;
  if (count == 1 && !py::isinstance<py::sequence>(values)) {
    v.push_back(values.cast<double>());
  } else {
    for (const py::handle x : values.cast<py::sequence>()) v.push_back(x.cast<double>());
  }
  if (v.size() != count)
    throw InvalidInputError(what + ": expected " + std::to_string(count) + " numbers, got " + std::to_string(v.size()));
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i == 0 ? "" : ",") + exact_text(v[i]);
  return out;
}

/// A joint edit as text ("JOINT:rotate=AX,AY,AZ,DEG", the CLI's --set), from a string or a dict
/// {"joint": name or index, "rotate": (ax, ay, az, degrees) | "translate": (x, y, z) | "scale": s}
/// (several kinds in one dict: one edit each, in the dict's order).
std::vector<std::string> edit_texts(const anim::Skeleton& skeleton, const py::handle& edit) {
  if (py::isinstance<py::str>(edit)) return {edit.cast<std::string>()};
  if (!py::isinstance<py::dict>(edit))
    throw InvalidInputError("edit: expected 'JOINT:rotate=AX,AY,AZ,DEG' text or a dict {'joint': ..., 'rotate': ...}");
  const auto d = edit.cast<py::dict>();
  if (!d.contains("joint")) throw InvalidInputError("edit: the dict has no 'joint'");
  const py::handle j = d["joint"];
  std::string joint;
  if (py::isinstance<py::int_>(j)) {
    const int i = j.cast<int>();
    if (i < 0 || i >= skeleton.size())
      throw InvalidInputError("edit: joint " + std::to_string(i) + " is outside the skeleton (" +
                              std::to_string(skeleton.size()) + " joints)");
    joint = skeleton.names()[static_cast<std::size_t>(i)];
  } else {
    joint = j.cast<std::string>();
  }
  std::vector<std::string> out;
  for (const auto& [key, value] : d) {
    const auto k = key.cast<std::string>();
    if (k == "joint") continue;
    if (k == "rotate")
      out.push_back(joint + ":rotate=" + numbers_text(value, 4, "rotate"));
    else if (k == "translate")
      out.push_back(joint + ":translate=" + numbers_text(value, 3, "translate"));
    else if (k == "scale")
      out.push_back(joint + ":scale=" + numbers_text(value, 1, "scale"));
    else
      throw InvalidInputError("edit: unknown key '" + k + "' (joint, rotate, translate, scale)");
  }
  if (out.empty()) throw InvalidInputError("edit: the dict has no rotate, translate or scale");
  return out;
}

/// The joint edits of `edits`, parsed as the CLI parses --set (io::parse_edit).
std::vector<anim::JointEdit> parse_edits(const anim::RiggedModel& model, const py::iterable& edits) {
  std::vector<std::string> texts;
  for (const py::handle e : edits)
    for (std::string& t : edit_texts(model.skeleton, e)) texts.push_back(std::move(t));
  std::vector<anim::JointEdit> out;
  if (texts.empty()) return out;
  const double reach = io::max_translation(model);
  for (const std::string& t : texts) out.push_back(io::parse_edit(model.skeleton, t, reach));
  return out;
}

/// Sets the morph weights `weights` gives in `pose`: {target name: weight} or {mesh index:
/// #targets weights}.
void set_morph_weights(anim::Pose& pose, const anim::RiggedModel& model, const py::dict& weights) {
  for (const auto& [key, value] : weights) {
    if (py::isinstance<py::str>(key)) {
      anim::set_morph_weight(pose, model.meshes, key.cast<std::string>(), value.cast<float>());
      continue;
    }
    const auto k = key.cast<std::size_t>();
    if (k >= model.meshes.size())
      throw InvalidInputError("morph_weights: mesh " + std::to_string(k) + ": the model has " +
                              std::to_string(model.meshes.size()) + " meshes");
    const auto w = value.cast<std::vector<float>>();
    const mesh::Mesh& me = model.meshes[k];
    if (w.size() != me.morph_targets.size())
      throw InvalidInputError("morph_weights: mesh " + std::to_string(k) + " ('" + me.name + "') has " +
                              std::to_string(me.morph_targets.size()) + " morph targets, not " +
                              std::to_string(w.size()));
    for (std::size_t t = 0; t < w.size(); ++t) anim::set_morph_weight(pose, me, t, w[t]);
  }
}

anim::Pose make_pose(const Model& self, const py::object& clip, const py::object& time, const std::string& blend,
                     const py::iterable& edits, const py::dict& morph_weights) {
  const anim::RiggedModel& model = self.model;
  anim::PoseRequest request;
  request.blend = io::value_by_name(io::kBlendModes, blend, "blend");
  if (!clip.is_none()) {
    request.clip = py::isinstance<py::int_>(clip) ? clip.cast<int>() : io::clip_index(model, clip.cast<std::string>());
    if (request.clip < 0)
      throw InvalidInputError("clip " + std::to_string(request.clip) + ": the model has " +
                              std::to_string(model.clips.size()) + " clips");
  }
  if (!time.is_none()) request.time = time.cast<double>();
  request.edits = parse_edits(model, edits);
  anim::ChosenPose chosen = anim::choose_pose(model, request);
  // As the CLI does, on stderr: Python's warnings module.
  for (const std::string& w : chosen.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
  set_morph_weights(chosen.pose, model, morph_weights);
  return std::move(chosen.pose);
}

/// Model.skin: the posed positions per mesh, and with `normals` the skinned normals too (one pass).
py::object skin_lists(const anim::RiggedModel& model, const anim::Pose& pose, const std::string& mode, bool normals) {
  const auto m = io::value_by_name(io::kSkinningModes, mode, "mode");
  io::PosedFrame frame;
  {
    py::gil_scoped_release release;
    if (normals)
      frame = io::posed_frame(model, pose, m);
    else
      frame.positions = io::posed_positions(model, pose, m);
  }
  py::list positions, turned;
  for (auto& p : frame.positions) positions.append(adopt_rows<3>(std::move(p)));
  if (!normals) return positions;
  for (auto& n : frame.normals) turned.append(adopt_rows<3>(std::move(n)));
  return py::make_tuple(positions, turned);
}

/// A property giving a read-only view (no copy) of the matrix `get` picks from a Mesh.
template <class Get>
auto matrix_view(Get get) {
  return [get](py::object self) {
    const auto& a = get(self.cast<const mesh::Mesh&>());
    return view(a.data(), {a.rows(), a.cols()}, self);
  };
}

/// Per transform, the N numbers `get` picks (translation, rotation coefficients x y z w, scale),
/// as a #J×N float64 array.
template <int N, class Get>
py::array_t<double> transform_rows(std::span<const anim::Transform> transforms, Get get) {
  py::array_t<double> out({static_cast<py::ssize_t>(transforms.size()), py::ssize_t{N}});
  for (std::size_t j = 0; j < transforms.size(); ++j)
    for (int c = 0; c < N; ++c) out.mutable_at(j, c) = get(transforms[j])[c];
  return out;
}

}  // namespace

void add_model(py::module_& m) {
  py::class_<mesh::Mesh>(m, "Mesh",
                         "One triangle mesh of a Model. Its arrays are read-only views of the model's memory (no "
                         "copy); they keep the model alive.")
      .def_property_readonly("name", [](const mesh::Mesh& me) { return me.name; })
      .def_property_readonly("positions", matrix_view([](const mesh::Mesh& me) -> const auto& { return me.positions; }),
                             "#V×3 float32 rest (bind-pose) positions in mesh space")
      .def_property_readonly("normals", matrix_view([](const mesh::Mesh& me) -> const auto& { return me.normals; }),
                             "#V×3 float32 unit normals (0×3 when the file has none)")
      .def_property_readonly("uvs", matrix_view([](const mesh::Mesh& me) -> const auto& { return me.uvs; }),
                             "#V×2 float32 texture coordinates (0×2 when none)")
      .def_property_readonly("faces", matrix_view([](const mesh::Mesh& me) -> const auto& { return me.faces; }),
                             "#F×3 int32 vertex indices")
      .def_property_readonly(
          "file_index",
          [](py::object self) {
            const auto& a = self.cast<const mesh::Mesh&>().file_index;
            return view(a.data(), {a.rows()}, self);
          },
          "#V int32 each vertex's number in its file (glTF accessor, PLY vertex element, OBJ `v` line from 0), -1 "
          "for a vertex an operation made; empty when the format's numbering is not kept (FBX, .x, ...)")
      .def_property_readonly("joints", matrix_view([](const mesh::Mesh& me) -> const auto& { return me.skin.joints; }),
                             "#V×4 uint16 skin joints, indices into `palette` (0×4 for a static mesh)")
      .def_property_readonly("weights",
                             matrix_view([](const mesh::Mesh& me) -> const auto& { return me.skin.weights; }),
                             "#V×4 float32 skin weights, rows sum to 1 (0×4 for a static mesh)")
      .def_property_readonly(
          "palette", [](const mesh::Mesh& me) { return int_array(me.skin.palette); },
          "#J int32 skeleton joint of each palette entry (a copy)")
      .def_property_readonly(
          "morph_targets",
          [](py::object self) {
            py::list out;
            for (mesh::MorphTarget& t : self.cast<mesh::Mesh&>().morph_targets)
              out.append(py::cast(&t, py::return_value_policy::reference_internal, self));
            return out;
          },
          "list of MorphTarget (blend shapes, views into this model), in the file's order")
      .def_property_readonly(
          "morph_weights",
          [](const mesh::Mesh& me) {
            return py::array_t<float>(static_cast<py::ssize_t>(me.morph_weights.size()), me.morph_weights.data());
          },
          "#targets float32 default morph weights (glTF mesh.weights or the node's; a copy)")
      .def_property_readonly("skinned", [](const mesh::Mesh& me) { return !me.skin.empty(); })
      .def_property_readonly(
          "node", [](const mesh::Mesh& me) { return me.node; }, "skeleton node the mesh hangs from, or -1")
      .def("__repr__", [](const mesh::Mesh& me) {
        return "<cgamesh.Mesh '" + me.name + "': " + std::to_string(me.vertex_count()) + " vertices, " +
               std::to_string(me.face_count()) + " faces>";
      });

  py::class_<mesh::MorphTarget>(m, "MorphTarget",
                               "A morph target (blend shape) of a Mesh: per-vertex displacements added, times its "
                               "weight, to the rest mesh before skinning (glTF's order).")
      .def_property_readonly("name", [](const mesh::MorphTarget& t) { return t.name; })
      .def_property_readonly(
          "positions",
          [](py::object self) {
            const auto& a = self.cast<const mesh::MorphTarget&>().positions;
            return view(a.data(), {a.rows(), a.cols()}, self);
          },
          "#V×3 float32 position displacements (read-only view)")
      .def_property_readonly(
          "normals",
          [](py::object self) {
            const auto& a = self.cast<const mesh::MorphTarget&>().normals;
            return view(a.data(), {a.rows(), a.cols()}, self);
          },
          "#V×3 float32 normal displacements (0×3 when the file has none; read-only view)")
      .def("__repr__", [](const mesh::MorphTarget& t) { return "<cgamesh.MorphTarget '" + t.name + "'>"; });

  py::class_<anim::Skeleton>(m, "Skeleton", "The joint hierarchy; parents come before children.")
      .def_property_readonly(
          "names", [](const anim::Skeleton& s) { return std::vector<std::string>(s.names().begin(), s.names().end()); })
      .def_property_readonly(
          "parents", [](const anim::Skeleton& s) { return int_array(s.parents()); },
          "#J int32 parent of each joint, -1 for a root")
      .def_property_readonly(
          "rest_translations",
          [](const anim::Skeleton& s) {
            return transform_rows<3>(s.rest(), [](const anim::Transform& t) { return t.translation; });
          },
          "#J×3 float64 local rest translations")
      .def_property_readonly(
          "rest_rotations",
          [](const anim::Skeleton& s) {
            return transform_rows<4>(s.rest(), [](const anim::Transform& t) { return t.rotation.coeffs(); });
          },
          "#J×4 float64 local rest rotations as quaternions (x, y, z, w), as glTF stores them")
      .def_property_readonly(
          "rest_scales",
          [](const anim::Skeleton& s) {
            return transform_rows<3>(s.rest(), [](const anim::Transform& t) { return t.scale; });
          },
          "#J×3 float64 local rest scales")
      .def("find", &anim::Skeleton::find, py::arg("name"), "index of the joint named `name`, or -1")
      .def("__len__", &anim::Skeleton::size);

  py::class_<anim::Clip>(m, "Clip", "An animation clip.")
      .def_property_readonly("name", [](const anim::Clip& c) { return c.name; })
      .def_property_readonly(
          "duration", [](const anim::Clip& c) { return c.duration; }, "seconds")
      .def_property_readonly(
          "channels", [](const anim::Clip& c) { return c.channels.size(); }, "number of animated TRS channels")
      .def("__repr__",
           [](const anim::Clip& c) { return "<cgamesh.Clip '" + c.name + "': " + std::to_string(c.duration) + " s>"; });

  py::class_<anim::Pose>(m, "Pose", "Local transform of every joint (from Model.pose()).")
      .def_property_readonly(
          "translations",
          [](const anim::Pose& p) {
            return transform_rows<3>(p.local, [](const anim::Transform& t) { return t.translation; });
          },
          "#J×3 float64 local translations")
      .def_property_readonly(
          "rotations",
          [](const anim::Pose& p) {
            return transform_rows<4>(p.local, [](const anim::Transform& t) { return t.rotation.coeffs(); });
          },
          "#J×4 float64 local rotations (x, y, z, w)")
      .def_property_readonly(
          "scales",
          [](const anim::Pose& p) {
            return transform_rows<3>(p.local, [](const anim::Transform& t) { return t.scale; });
          },
          "#J×3 float64 local scales")
      .def("__len__", [](const anim::Pose& p) { return p.local.size(); });

  py::class_<Model, ModelPtr>(m, "Model", "A rigged (or static) model: meshes, skeleton, clips (cgamesh.load()).")
      .def_property_readonly(
          "meshes",
          [](py::object self) {
            auto& me = self.cast<Model&>();
            py::list out;
            for (mesh::Mesh& mesh : me.model.meshes)
              out.append(py::cast(&mesh, py::return_value_policy::reference_internal, self));
            return out;
          },
          "list of Mesh (views into this model)")
      .def_property_readonly("skeleton",
                             [](py::object self) {
                               return py::cast(&self.cast<Model&>().model.skeleton,
                                               py::return_value_policy::reference_internal, self);
                             })
      .def_property_readonly("clips",
                             [](py::object self) {
                               py::list out;
                               for (anim::Clip& c : self.cast<Model&>().model.clips)
                                 out.append(py::cast(&c, py::return_value_policy::reference_internal, self));
                               return out;
                             })
      .def_property_readonly(
          "warnings", [](const Model& me) { return me.model.warnings; }, "what the loader approximated or dropped")
      .def_property_readonly(
          "file", [](const Model& me) { return me.file; }, "the file it was loaded from, or ''")
      .def(
          "info",
          [](const Model& me) {
            std::string text;
            {
              py::gil_scoped_release release;
              text = io::model_info_json(me.model, io::model_info(me.model), me.file);
            }
            return py::module_::import("json").attr("loads")(text);
          },
          "The summary `cgamesh info --json` prints, as a dict (bind-pose boxes in world space).")
      .def(
          "save",
          [](const Model& me, const std::filesystem::path& file, const py::object& pose) {
            const std::string path = file.string();
            if (io::is_rigged_format(path) && !pose.is_none())
              throw InvalidInputError(
                  "save: a glTF keeps the rig, not one pose (pose is for .obj/.ply; animate() "
                  "stores poses as a clip)");
            const anim::Pose p = pose_or_bind(me.model, pose);
            py::gil_scoped_release release;
            return io::write_model(me.model, path, [&]() -> mesh::WorldSurface {
              return io::posed_frame(me.model, p, anim::SkinningMode::cga);
            });
          },
          py::arg("path"), py::arg("pose") = py::none(),
          "Writes the model: .glb/.gltf as `cgamesh convert` (rigged: skin, skeleton, clips), .obj/.ply as "
          "`cgamesh pose` (world space, in `pose` or the bind pose, cga skinning, with skinned normals). Atomic: on "
          "an error nothing is written. Returns the writer's warnings (list of str). Releases the GIL.")
      .def("pose", &make_pose, py::arg("clip") = py::none(), py::arg("time") = py::none(), py::arg("blend") = "format",
           py::arg("edits") = py::list(), py::arg("morph_weights") = py::dict(),
           "A Pose, as the CLI's --anim/--time/--blend/--set choose it: the bind pose when clip and time are None; "
           "clip (index or name; the first clip when only time is given) sampled at time seconds with blend "
           "'format', 'linear' or 'log'; then edits, each 'JOINT:rotate=AX,AY,AZ,DEG' | 'JOINT:translate=X,Y,Z' | "
           "'JOINT:scale=S' or a dict {'joint': name or index, 'rotate': (ax, ay, az, degrees), 'translate': (x, y, "
           "z), 'scale': s}; then morph_weights, {target name: weight} (every mesh's target of that name) or {mesh "
           "index: sequence of one weight per target}, over the clip's or the file's weights. A time past the "
           "clip's end uses its last pose and warns (UserWarning), as the CLI does.")
      .def(
          "morph_weights",
          [](const Model& me, const py::object& pose) {
            const anim::Pose p = pose_or_bind(me.model, pose);
            py::list out;
            for (const mesh::Mesh& mesh : me.model.meshes) {
              const std::span<const float> w = anim::morph_weights(p, mesh);
              out.append(py::array_t<float>(static_cast<py::ssize_t>(w.size()), w.data()));
            }
            return out;
          },
          py::arg("pose") = py::none(),
          "The morph weights `pose` (None: the bind pose) gives each mesh: a list of #targets float32 arrays, "
          "what skin() applies before skinning.")
      .def(
          "skin",
          [](const Model& me, const py::object& pose, const std::string& mode, bool normals) {
            return skin_lists(me.model, pose_or_bind(me.model, pose), mode, normals);
          },
          py::arg("pose") = py::none(), py::arg("mode") = "cga", py::arg("normals") = false,
          "World-space posed positions: a list with one #V×3 float32 array per mesh (the arrays own their memory, "
          "no copy), as `cgamesh pose --skinning MODE` writes them. pose: a Pose, or None for the bind pose; mode: "
          "'cga', 'versor', 'matrix' or 'dqs'; normals: True for (positions, normals), the second list the skinned "
          "unit normals (#V×3, 0×3 for a mesh without normals) from the same pass. Releases the GIL.")
      .def(
          "animate",
          [](const Model& me, const py::iterable& keys, const std::string& blend, double fps, const std::string& name) {
            if (!(fps > 0) || !std::isfinite(fps)) throw InvalidInputError("fps must be a finite number > 0");
            const auto mode = io::value_by_name(io::kBlendModes, blend, "blend");
            std::map<double, anim::Keyframe> frames;
            for (const py::handle k : keys) {
              const auto pair = k.cast<py::sequence>();
              if (pair.size() != 2) throw InvalidInputError("animate: each key is (time, edit)");
              const double t = pair[0].cast<double>();
              if (!(t >= 0) || !std::isfinite(t)) throw InvalidInputError("animate: a key time must be >= 0");
              anim::Keyframe& f = frames[t];
              f.time = t;
              for (anim::JointEdit& e : parse_edits(me.model, py::make_tuple(pair[1]))) f.edits.push_back(e);
            }
            std::vector<anim::Keyframe> list;
            for (auto& [t, f] : frames) list.push_back(std::move(f));
            anim::RiggedModel out = me.model;
            out.clips.push_back(anim::generate_clip(out.skeleton, list, {.blend = mode, .fps = fps, .name = name}));
            return make_model(std::move(out), me.file);
          },
          py::arg("keys"), py::arg("blend") = "linear", py::arg("fps") = 30.0, py::arg("name") = "generated",
          "A copy with one more clip generated from keys [(time, edit), ...] as `cgamesh animate` makes it (edits as "
          "in pose(); blend 'linear' or 'log').")
      .def(
          "subdivided",
          [](const Model& me, int levels) {
            if (levels < 0 || levels > 8) throw InvalidInputError("subdivided: levels must be in [0, 8]");
            anim::RiggedModel out = me.model;
            {
              py::gil_scoped_release release;
              for (int l = 0; l < levels; ++l)
                for (mesh::Mesh& m : out.meshes) m = mesh::subdivide_midpoint(m);
            }
            return make_model(std::move(out), me.file);
          },
          py::arg("levels") = 1,
          "A copy with every mesh split 1 -> 4 at its edge midpoints `levels` times (0 to 8; each level about "
          "quadruples the faces): new vertices blend their edge's positions, normals, UVs and skin weights "
          "(mesh::subdivide_midpoint). Releases the GIL.")
      .def(
          "copy", [](const Model& me) { return std::make_shared<Model>(me); }, "A deep copy.")
      .def("__repr__", [](const Model& me) {
        return "<cgamesh.Model '" + me.file + "': " + std::to_string(me.model.meshes.size()) + " meshes, " +
               std::to_string(me.model.skeleton.size()) + " joints, " + std::to_string(me.model.clips.size()) +
               " clips>";
      });

  m.def(
      "load",
      [](const std::filesystem::path& file) {
            const std::string path = file.string();
        anim::RiggedModel model;
        {
          py::gil_scoped_release release;
          model = io::load_model(path);
        }
        return make_model(std::move(model), path);
      },
      py::arg("path"),
      "Loads a model (glTF/GLB, FBX, COLLADA, OBJ, PLY, ... as `cgamesh` reads them). Raises FileError for a "
      "missing, unreadable or corrupt file. Releases the GIL.");
}

}  // namespace cgamesh::python
