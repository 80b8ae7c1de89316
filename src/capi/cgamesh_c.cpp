// The C ABI (include/cgamesh/cgamesh.h): handles over the library's types, every exception
// caught at the boundary and turned into a status and this thread's last error. The rules
// (which file a path becomes, which pose a request means, what an operation reports) are the
// library's own, as in the CLI and Python.
#include "cgamesh/cgamesh.h"

#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <span>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cgamesh/anim/morph.hpp"
#include "cgamesh/anim/pose_choice.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_info.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/io/surgery_stats.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/soft/tissue.hpp"
#include "cgamesh/surgery/cut.hpp"
#include "cgamesh/surgery/drill.hpp"
#include "cgamesh/surgery/live_model.hpp"
#include "cgamesh/surgery/placement.hpp"
#include "cgamesh/surgery/tear.hpp"

using namespace cgamesh;

struct cgamesh_model {
  anim::RiggedModel model;
  /// Per-frame skinning writes here before the caller's buffer (kept: no allocation per frame).
  mutable mesh::RowMatrixXf<3> positions, normals;
};

struct cgamesh_pose {
  anim::PoseRequest request;
  anim::Pose pose;
  std::vector<std::string> warnings;
  int joints = 0;  ///< of the skeleton the pose was made for
};

struct cgamesh_live {
  surgery::LiveModel live;
  std::optional<soft::Tissue> tissue;
  mutable mesh::RowMatrixXf<3> positions, normals;
};

struct cgamesh_change {
  std::vector<surgery::MeshChange> changes;
  nlohmann::ordered_json stats;
  /// Per change, the corners of its new faces (3 per face) as the operation left them.
  std::vector<std::vector<int32_t>> corners;
};

namespace {

thread_local std::string last_error;

/// Runs `f`, turning what it throws into a status and the last error.
template <class F>
cgamesh_status guarded(F&& f) noexcept {
  try {
    f();
    last_error.clear();
    return CGAMESH_OK;
  } catch (const FileError& e) {
    last_error = e.what();
    return CGAMESH_ERROR_FILE;
  } catch (const InvalidInputError& e) {
    last_error = e.what();
    return CGAMESH_ERROR_INVALID_ARGUMENT;
  } catch (const WriteError& e) {
    last_error = e.what();
    return CGAMESH_ERROR_WRITE;
  } catch (const TopologyError& e) {
    last_error = e.what();
    return CGAMESH_ERROR_TOPOLOGY;
  } catch (const SolverError& e) {
    last_error = e.what();
    return CGAMESH_ERROR_SOLVER;
  } catch (const PlatformError& e) {
    last_error = e.what();
    return CGAMESH_ERROR_PLATFORM;
  } catch (const std::bad_alloc&) {
    last_error = "out of memory";
    return CGAMESH_ERROR_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    last_error = std::string("internal error: ") + e.what();
    return CGAMESH_ERROR_INTERNAL;
  } catch (...) {
    last_error = "internal error: an unknown exception";
    return CGAMESH_ERROR_INTERNAL;
  }
}

template <class T>
T& need(T* p, const char* what) {
  if (p == nullptr) throw InvalidInputError(std::string(what) + " is NULL");
  return *p;
}

std::string need_text(const char* p, const char* what) { return need(p, what), std::string(p); }

char* copy_string(const std::string& s) {
  char* out = new char[s.size() + 1];
  std::memcpy(out, s.c_str(), s.size() + 1);
  return out;
}

const mesh::Mesh& mesh_of(const anim::RiggedModel& model, int32_t mesh) {
  if (mesh < 0 || mesh >= static_cast<int32_t>(model.meshes.size()))
    throw InvalidInputError("mesh " + std::to_string(mesh) + ": the model has " + std::to_string(model.meshes.size()) +
                            " meshes");
  return model.meshes[static_cast<std::size_t>(mesh)];
}

void check_count(std::size_t given, std::size_t needed, const char* what) {
  if (given != needed)
    throw InvalidInputError(std::string(what) + ": a buffer of " + std::to_string(given) + " elements where " +
                            std::to_string(needed) + " are needed");
}

Eigen::Vector3d vec3(const double* p, const char* what) {
  need(p, what);
  const Eigen::Vector3d v(p[0], p[1], p[2]);
  if (!v.allFinite()) throw InvalidInputError(std::string(what) + " is not finite");
  return v;
}

const anim::Pose& pose_for(const anim::RiggedModel& model, const cgamesh_pose* pose, std::optional<anim::Pose>& bind) {
  if (pose == nullptr) return bind.emplace(anim::rest_pose(model.skeleton));
  if (pose->joints != model.skeleton.size())
    throw InvalidInputError("the pose has " + std::to_string(pose->joints) + " joints, the model " +
                            std::to_string(model.skeleton.size()));
  return pose->pose;
}

anim::SkinningMode skinning_of(cgamesh_skinning mode) {
  switch (mode) {
    case CGAMESH_SKINNING_CGA: return anim::SkinningMode::cga;
    case CGAMESH_SKINNING_VERSOR: return anim::SkinningMode::versor;
    case CGAMESH_SKINNING_MATRIX: return anim::SkinningMode::matrix;
    case CGAMESH_SKINNING_DQS: return anim::SkinningMode::dqs;
    case CGAMESH_SKINNING_MAX_ENUM: break;
  }
  throw InvalidInputError("skinning mode " + std::to_string(static_cast<int>(mode)) + ": expected 0 to 3");
}

/// Mesh `mesh` of `model` skinned in `pose` into the caller's buffers, through `scratch` rows
/// kept from call to call; `tissue` (may be null) overlays the simulated rows.
void skin_to(const anim::RiggedModel& model, const cgamesh_pose* pose, int32_t mesh, cgamesh_skinning mode,
             float* positions, std::size_t position_count, float* normals, std::size_t normal_count,
             mesh::RowMatrixXf<3>& scratch, mesh::RowMatrixXf<3>& scratch_normals,
             const std::function<void(std::span<float>)>& overlay = {}) {
  const mesh::Mesh& m = mesh_of(model, mesh);
  need(positions, "positions");
  const auto rows = static_cast<std::size_t>(m.vertex_count());
  check_count(position_count, 3 * rows, "positions");
  if (normals != nullptr) {
    check_count(normal_count, 3 * rows, "normals");
    if (m.normals.rows() != m.vertex_count())
      throw InvalidInputError("mesh " + std::to_string(mesh) + " has no normals to skin");
  }
  std::optional<anim::Pose> bind;
  const anim::Pose& p = pose_for(model, pose, bind);
  const auto gv = anim::global_versors(model.skeleton, p);
  const auto gm = anim::global_matrices(model.skeleton, p);
  const anim::SkinningPalette palette = anim::make_palette(m, gv, gm, skinning_of(mode), anim::morph_weights(p, m));
  anim::skin_into(m, palette, scratch, normals != nullptr ? &scratch_normals : nullptr);
  std::memcpy(positions, scratch.data(), 3 * rows * sizeof(float));
  if (overlay) overlay(std::span<float>(positions, 3 * rows));
  if (normals != nullptr) std::memcpy(normals, scratch_normals.data(), 3 * rows * sizeof(float));
}

void mesh_size(const anim::RiggedModel& model, int32_t mesh, int32_t* vertices, int32_t* faces) {
  const mesh::Mesh& m = mesh_of(model, mesh);
  if (vertices == nullptr && faces == nullptr) throw InvalidInputError("vertices and faces are both NULL");
  if (vertices != nullptr) *vertices = static_cast<int32_t>(m.vertex_count());
  if (faces != nullptr) *faces = static_cast<int32_t>(m.face_count());
}

void copy_faces(const anim::RiggedModel& model, int32_t mesh, int32_t* out, std::size_t count) {
  const mesh::Mesh& m = mesh_of(model, mesh);
  need(out, "faces");
  check_count(count, 3 * static_cast<std::size_t>(m.face_count()), "faces");
  for (Eigen::Index f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k) out[3 * f + k] = m.faces(f, k);
}

void copy_positions(const anim::RiggedModel& model, int32_t mesh, float* out, std::size_t count) {
  const mesh::Mesh& m = mesh_of(model, mesh);
  need(out, "positions");
  check_count(count, 3 * static_cast<std::size_t>(m.vertex_count()), "positions");
  std::memcpy(out, m.positions.data(), count * sizeof(float));
}

/// Applies an edit (after the clip) and keeps it in the request, so that later samples keep it.
void add_edit(cgamesh_pose& pose, const anim::RiggedModel& model, anim::JointEdit e) {
  if (pose.joints != model.skeleton.size()) throw InvalidInputError("the pose is not one of this model");
  if (e.joint < 0 || e.joint >= pose.joints)
    throw InvalidInputError("joint " + std::to_string(e.joint) + ": the model has " + std::to_string(pose.joints) +
                            " joints");
  const std::vector<anim::JointEdit> one{e};
  anim::apply_edits(pose.pose, one);
  pose.request.edits.push_back(e);
}

cgamesh_change* make_change(std::vector<surgery::MeshChange> changes, nlohmann::ordered_json stats) {
  return new cgamesh_change{std::move(changes), std::move(stats), {}};
}

/// Runs an in-place operation on `live`; the tissue, when on, follows it and the change goes to
/// `*out` when asked for.
template <class Op>
void operate(cgamesh_live& live, cgamesh_change** out, Op&& op) {
  std::unique_ptr<cgamesh_change> change(op(live.live));
  for (const surgery::MeshChange& c : change->changes) {
    const mesh::Mesh& m = live.live.model().meshes[static_cast<std::size_t>(c.mesh)];
    std::vector<int32_t>& corners = change->corners.emplace_back();
    for (const int f : c.new_faces)
      for (int k = 0; k < 3; ++k) corners.push_back(m.faces(f, k));
  }
  if (live.tissue) live.tissue->follow(live.live, change->changes);
  if (out != nullptr) *out = change.release();
}

const surgery::MeshChange& change_at(const cgamesh_change* c, std::size_t index) {
  need(c, "change");
  if (index >= c->changes.size())
    throw InvalidInputError("change " + std::to_string(index) + ": the operation changed " +
                            std::to_string(c->changes.size()) + " meshes");
  return c->changes[index];
}

soft::TissueOptions tissue_options(const cgamesh_tissue_options& o) {
  soft::TissueOptions t;
  t.density = o.density;
  t.attachment_compliance = o.attachment_compliance;
  t.stretch_compliance = o.stretch_compliance;
  t.bend_compliance = o.bend_compliance;
  t.pretension = o.pretension;
  t.damping = o.damping;
  t.substep = o.substep;
  t.gravity = Eigen::Vector3d(o.gravity[0], o.gravity[1], o.gravity[2]);
  t.region_radius = o.region_radius;
  t.release_margin = o.release_margin;
  t.max_particles = o.max_particles;
  t.validate();
  return t;
}

}  // namespace

extern "C" {

const char* cgamesh_last_error(void) { return last_error.c_str(); }

const char* cgamesh_status_name(cgamesh_status status) {
  switch (status) {
    case CGAMESH_OK: return "CGAMESH_OK";
    case CGAMESH_ERROR_INVALID_ARGUMENT: return "CGAMESH_ERROR_INVALID_ARGUMENT";
    case CGAMESH_ERROR_FILE: return "CGAMESH_ERROR_FILE";
    case CGAMESH_ERROR_WRITE: return "CGAMESH_ERROR_WRITE";
    case CGAMESH_ERROR_TOPOLOGY: return "CGAMESH_ERROR_TOPOLOGY";
    case CGAMESH_ERROR_SOLVER: return "CGAMESH_ERROR_SOLVER";
    case CGAMESH_ERROR_PLATFORM: return "CGAMESH_ERROR_PLATFORM";
    case CGAMESH_ERROR_OUT_OF_MEMORY: return "CGAMESH_ERROR_OUT_OF_MEMORY";
    case CGAMESH_ERROR_INTERNAL: return "CGAMESH_ERROR_INTERNAL";
    case CGAMESH_STATUS_MAX_ENUM: break;
  }
  return "unknown status";
}

const char* cgamesh_version(void) { return CGAMESH_VERSION_STRING; }
int cgamesh_abi_version(void) { return CGAMESH_C_ABI_VERSION; }
void cgamesh_string_free(char* text) { delete[] text; }

// ---- Models ----

cgamesh_status cgamesh_model_load(const char* path, cgamesh_model** out) {
  return guarded([&] {
    need(out, "out");
    *out = new cgamesh_model{io::load_model(need_text(path, "path")), {}, {}};
  });
}

void cgamesh_model_free(cgamesh_model* model) { delete model; }

cgamesh_status cgamesh_model_save(const cgamesh_model* model, const char* path, const cgamesh_pose* pose) {
  return guarded([&] {
    const anim::RiggedModel& m = need(model, "model").model;
    const std::string p = need_text(path, "path");
    std::optional<anim::Pose> bind;
    const anim::Pose& chosen = pose_for(m, pose, bind);
    (void)io::write_model(m, p, [&]() -> mesh::WorldSurface { return io::posed_frame(m, chosen, anim::SkinningMode::cga); });
  });
}

cgamesh_status cgamesh_model_warning_count(const cgamesh_model* model, size_t* out) {
  return guarded([&] { need(out, "out") = need(model, "model").model.warnings.size(); });
}

cgamesh_status cgamesh_model_warning(const cgamesh_model* model, size_t index, const char** out) {
  return guarded([&] {
    const auto& w = need(model, "model").model.warnings;
    need(out, "out");
    if (index >= w.size())
      throw InvalidInputError("warning " + std::to_string(index) + ": there are " + std::to_string(w.size()));
    *out = w[index].c_str();
  });
}

cgamesh_status cgamesh_model_info_json(const cgamesh_model* model, char** out) {
  return guarded([&] {
    const anim::RiggedModel& m = need(model, "model").model;
    need(out, "out");
    *out = copy_string(io::model_info_json(m, io::model_info(m), ""));
  });
}

cgamesh_status cgamesh_model_counts_get(const cgamesh_model* model, cgamesh_model_counts* out) {
  return guarded([&] {
    const anim::RiggedModel& m = need(model, "model").model;
    need(out, "out") = {static_cast<int32_t>(m.meshes.size()), static_cast<int32_t>(m.skeleton.size()),
                        static_cast<int32_t>(m.clips.size())};
  });
}

cgamesh_status cgamesh_model_mesh_size(const cgamesh_model* model, int32_t mesh, int32_t* vertices, int32_t* faces) {
  return guarded([&] { mesh_size(need(model, "model").model, mesh, vertices, faces); });
}

cgamesh_status cgamesh_model_mesh_positions(const cgamesh_model* model, int32_t mesh, float* out, size_t count) {
  return guarded([&] { copy_positions(need(model, "model").model, mesh, out, count); });
}

cgamesh_status cgamesh_model_mesh_faces(const cgamesh_model* model, int32_t mesh, int32_t* out, size_t count) {
  return guarded([&] { copy_faces(need(model, "model").model, mesh, out, count); });
}

cgamesh_status cgamesh_model_mesh_uvs(const cgamesh_model* model, int32_t mesh, float* out, size_t count,
                                      int32_t* has_uvs) {
  return guarded([&] {
    const mesh::Mesh& m = mesh_of(need(model, "model").model, mesh);
    need(has_uvs, "has_uvs");
    const bool has = m.uvs.rows() == m.vertex_count() && m.vertex_count() > 0;
    if (has) {
      need(out, "uvs");
      check_count(count, 2 * static_cast<std::size_t>(m.vertex_count()), "uvs");
      std::memcpy(out, m.uvs.data(), count * sizeof(float));
    }
    *has_uvs = has ? 1 : 0;
  });
}

cgamesh_status cgamesh_model_joint_index(const cgamesh_model* model, const char* name, int32_t* out) {
  return guarded([&] { need(out, "out") = io::joint_index(need(model, "model").model.skeleton, need_text(name, "name")); });
}

cgamesh_status cgamesh_model_clip_index(const cgamesh_model* model, const char* name, int32_t* out) {
  return guarded([&] { need(out, "out") = io::clip_index(need(model, "model").model, need_text(name, "name")); });
}

cgamesh_status cgamesh_model_clip_duration(const cgamesh_model* model, int32_t clip, double* seconds) {
  return guarded([&] {
    const anim::RiggedModel& m = need(model, "model").model;
    need(seconds, "seconds");
    if (clip < 0 || clip >= static_cast<int32_t>(m.clips.size()))
      throw InvalidInputError("clip " + std::to_string(clip) + ": the model has " + std::to_string(m.clips.size()) +
                              " clips");
    *seconds = m.clips[static_cast<std::size_t>(clip)].duration;
  });
}

// ---- Poses ----

cgamesh_status cgamesh_pose_create(const cgamesh_model* model, cgamesh_pose** out) {
  return guarded([&] {
    const anim::RiggedModel& m = need(model, "model").model;
    need(out, "out");
    auto p = std::make_unique<cgamesh_pose>();
    p->pose = anim::rest_pose(m.skeleton);
    p->joints = m.skeleton.size();
    *out = p.release();
  });
}

void cgamesh_pose_free(cgamesh_pose* pose) { delete pose; }

cgamesh_status cgamesh_pose_sample(cgamesh_pose* pose, const cgamesh_model* model, int32_t clip, double time,
                                   cgamesh_blend blend) {
  return guarded([&] {
    cgamesh_pose& p = need(pose, "pose");
    const anim::RiggedModel& m = need(model, "model").model;
    if (p.joints != m.skeleton.size()) throw InvalidInputError("the pose is not one of this model");
    if (blend != CGAMESH_BLEND_FORMAT && blend != CGAMESH_BLEND_LINEAR && blend != CGAMESH_BLEND_LOG)
      throw InvalidInputError("blend " + std::to_string(static_cast<int>(blend)) + ": expected 0 to 2");
    if (std::isnan(time)) throw InvalidInputError("time is NaN");
    anim::PoseRequest r = p.request;
    r.clip = clip;
    r.time = time < 0 && clip < 0 ? std::nullopt : std::optional<double>(time);
    r.blend = static_cast<anim::BlendMode>(blend);
    anim::ChosenPose chosen = anim::choose_pose(m, r);
    p.request = std::move(r);
    p.pose = std::move(chosen.pose);
    p.warnings = std::move(chosen.warnings);
  });
}

cgamesh_status cgamesh_pose_rotate(cgamesh_pose* pose, const cgamesh_model* model, int32_t joint, const double axis[3],
                                   double degrees) {
  return guarded([&] {
    anim::JointEdit e;
    e.joint = joint;
    e.axis = vec3(axis, "axis");
    if (!std::isfinite(degrees)) throw InvalidInputError("degrees is not finite");
    if (e.axis.norm() == 0) throw InvalidInputError("axis is zero");
    e.axis.normalize();
    e.angle = degrees * std::numbers::pi / 180;
    add_edit(need(pose, "pose"), need(model, "model").model, e);
  });
}

cgamesh_status cgamesh_pose_translate(cgamesh_pose* pose, const cgamesh_model* model, int32_t joint,
                                      const double translation[3]) {
  return guarded([&] {
    anim::JointEdit e;
    e.joint = joint;
    e.translation = vec3(translation, "translation");
    const anim::RiggedModel& m = need(model, "model").model;
    if (e.translation.norm() > io::max_translation(m)) throw InvalidInputError("translation is out of the model's reach");
    add_edit(need(pose, "pose"), m, e);
  });
}

cgamesh_status cgamesh_pose_scale(cgamesh_pose* pose, const cgamesh_model* model, int32_t joint, double scale) {
  return guarded([&] {
    if (!(scale >= 1 / io::kMaxReach && scale <= io::kMaxReach))
      throw InvalidInputError("scale must lie in [1e-6, 1e6]");
    anim::JointEdit e;
    e.joint = joint;
    e.scale = scale;
    add_edit(need(pose, "pose"), need(model, "model").model, e);
  });
}

cgamesh_status cgamesh_pose_set_morph_weight(cgamesh_pose* pose, const cgamesh_model* model, const char* target,
                                             float weight) {
  return guarded([&] {
    cgamesh_pose& p = need(pose, "pose");
    const anim::RiggedModel& m = need(model, "model").model;
    if (p.joints != m.skeleton.size()) throw InvalidInputError("the pose is not one of this model");
    const anim::MorphSetting s{need_text(target, "target"), weight};
    if (!std::isfinite(weight)) throw InvalidInputError("weight is not finite");
    anim::set_morph_weight(p.pose, m.meshes, s.target, s.weight);
    p.request.morphs.push_back(s);
  });
}

cgamesh_status cgamesh_pose_clear_edits(cgamesh_pose* pose, const cgamesh_model* model) {
  return guarded([&] {
    cgamesh_pose& p = need(pose, "pose");
    const anim::RiggedModel& m = need(model, "model").model;
    if (p.joints != m.skeleton.size()) throw InvalidInputError("the pose is not one of this model");
    p.request.edits.clear();
    p.request.morphs.clear();
    anim::ChosenPose chosen = anim::choose_pose(m, p.request);
    p.pose = std::move(chosen.pose);
    p.warnings = std::move(chosen.warnings);
  });
}

cgamesh_status cgamesh_pose_warning_count(const cgamesh_pose* pose, size_t* out) {
  return guarded([&] { need(out, "out") = need(pose, "pose").warnings.size(); });
}

cgamesh_status cgamesh_pose_warning(const cgamesh_pose* pose, size_t index, const char** out) {
  return guarded([&] {
    const auto& w = need(pose, "pose").warnings;
    need(out, "out");
    if (index >= w.size())
      throw InvalidInputError("warning " + std::to_string(index) + ": there are " + std::to_string(w.size()));
    *out = w[index].c_str();
  });
}

// ---- Skinning ----

cgamesh_status cgamesh_model_skin(const cgamesh_model* model, const cgamesh_pose* pose, int32_t mesh,
                                  cgamesh_skinning mode, float* positions, size_t position_count, float* normals,
                                  size_t normal_count) {
  return guarded([&] {
    const cgamesh_model& m = need(model, "model");
    skin_to(m.model, pose, mesh, mode, positions, position_count, normals, normal_count, m.positions, m.normals);
  });
}

// ---- Surgery in place ----

cgamesh_status cgamesh_live_create(const cgamesh_model* model, const cgamesh_pose* pose, cgamesh_live** out) {
  return guarded([&] {
    const anim::RiggedModel& m = need(model, "model").model;
    need(out, "out");
    std::optional<anim::Pose> bind;
    const anim::Pose& p = pose_for(m, pose, bind);
    *out = new cgamesh_live{surgery::LiveModel(m, surgery::place(m, p)), std::nullopt, {}, {}};
  });
}

void cgamesh_live_free(cgamesh_live* live) { delete live; }

cgamesh_status cgamesh_live_model(const cgamesh_live* live, cgamesh_model** out) {
  return guarded([&] {
    const anim::RiggedModel& m = need(live, "live").live.model();
    need(out, "out");
    *out = new cgamesh_model{m, {}, {}};
  });
}

cgamesh_status cgamesh_live_mesh_size(const cgamesh_live* live, int32_t mesh, int32_t* vertices, int32_t* faces) {
  return guarded([&] { mesh_size(need(live, "live").live.model(), mesh, vertices, faces); });
}

cgamesh_status cgamesh_live_mesh_faces(const cgamesh_live* live, int32_t mesh, int32_t* out, size_t count) {
  return guarded([&] { copy_faces(need(live, "live").live.model(), mesh, out, count); });
}

cgamesh_status cgamesh_live_mesh_positions(const cgamesh_live* live, int32_t mesh, float* out, size_t count) {
  return guarded([&] { copy_positions(need(live, "live").live.model(), mesh, out, count); });
}

cgamesh_status cgamesh_live_skin(const cgamesh_live* live, const cgamesh_pose* pose, int32_t mesh,
                                 cgamesh_skinning mode, float* positions, size_t position_count, float* normals,
                                 size_t normal_count) {
  return guarded([&] {
    const cgamesh_live& l = need(live, "live");
    std::function<void(std::span<float>)> overlay;
    if (l.tissue) overlay = [&](std::span<float> rows) { l.tissue->overlay(l.live, mesh, rows); };
    skin_to(l.live.model(), pose, mesh, mode, positions, position_count, normals, normal_count, l.positions, l.normals,
            overlay);
  });
}

cgamesh_status cgamesh_live_cut(cgamesh_live* live, const double normal[3], double d, cgamesh_change** change) {
  return guarded([&] {
    cgamesh_live& l = need(live, "live");
    const cga::Vector<double> plane = surgery::cut_plane(vec3(normal, "normal"), d);
    operate(l, change, [&](surgery::LiveModel& m) {
      surgery::LiveCut c = surgery::cut(m, plane);
      nlohmann::ordered_json stats = nlohmann::ordered_json::parse(io::stats_json(c));
      stats["faces_out"] = c.faces_out;
      stats["warnings"] = c.warnings;
      return make_change(std::move(c.changes), std::move(stats));
    });
  });
}

cgamesh_status cgamesh_live_tear(cgamesh_live* live, const double* blades, size_t count, double open,
                                 cgamesh_change** change) {
  return guarded([&] {
    cgamesh_live& l = need(live, "live");
    need(blades, "blades");
    if (count < 2) throw InvalidInputError("a tear needs at least 2 positions of the blade");
    std::vector<surgery::Scalpel> scalpel;
    for (std::size_t i = 0; i < count; ++i)
      scalpel.push_back({vec3(blades + 6 * i, "blade handle"), vec3(blades + 6 * i + 3, "blade tip")});
    surgery::TearOptions options;
    if (!(open >= 0) || !std::isfinite(open)) throw InvalidInputError("open must be a finite number >= 0");
    options.open = open;
    operate(l, change, [&](surgery::LiveModel& m) {
      surgery::LiveTear t = surgery::tear(m, scalpel, options);
      nlohmann::ordered_json stats = nlohmann::ordered_json::parse(io::stats_json(t));
      stats["warnings"] = t.warnings;
      std::vector<surgery::MeshChange> changes;
      changes.push_back(std::move(t.change));
      return make_change(std::move(changes), std::move(stats));
    });
  });
}

cgamesh_status cgamesh_live_drill(cgamesh_live* live, const double tip[3], const double base[3], double radius,
                                  int32_t wall, cgamesh_change** change) {
  return guarded([&] {
    cgamesh_live& l = need(live, "live");
    surgery::DrillOptions options;
    options.wall = wall != 0;
    const Eigen::Vector3d a = vec3(tip, "tip"), b = vec3(base, "base");
    operate(l, change, [&](surgery::LiveModel& m) {
      surgery::LiveDrill r = surgery::drill(m, a, b, radius, options);
      nlohmann::ordered_json stats = nlohmann::ordered_json::parse(io::stats_json(r));
      stats["warnings"] = r.warnings;
      return make_change(std::move(r.changes), std::move(stats));
    });
  });
}

void cgamesh_change_free(cgamesh_change* change) { delete change; }

cgamesh_status cgamesh_change_json(const cgamesh_change* change, char** out) {
  return guarded([&] {
    const cgamesh_change& c = need(change, "change");
    need(out, "out");
    *out = copy_string(c.stats.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
  });
}

cgamesh_status cgamesh_change_mesh_count(const cgamesh_change* change, size_t* out) {
  return guarded([&] { need(out, "out") = need(change, "change").changes.size(); });
}

cgamesh_status cgamesh_change_mesh(const cgamesh_change* change, size_t index, cgamesh_mesh_change* out) {
  return guarded([&] {
    const surgery::MeshChange& c = change_at(change, index);
    need(out, "out") = {c.mesh,
                        c.first_new_vertex,
                        static_cast<int32_t>(c.origins.size()),
                        static_cast<int32_t>(c.new_faces.size()),
                        static_cast<int32_t>(c.moved_faces.size()),
                        c.removed_faces};
  });
}

cgamesh_status cgamesh_change_new_faces(const cgamesh_change* change, size_t index, int32_t* out, size_t count) {
  return guarded([&] {
    const surgery::MeshChange& c = change_at(change, index);
    need(out, "out");
    check_count(count, c.new_faces.size(), "new faces");
    std::memcpy(out, c.new_faces.data(), count * sizeof(int32_t));
  });
}

cgamesh_status cgamesh_change_new_face_corners(const cgamesh_change* change, size_t index, int32_t* out,
                                              size_t count) {
  return guarded([&] {
    (void)change_at(change, index);
    const std::vector<int32_t>& corners = change->corners[index];
    need(out, "out");
    check_count(count, corners.size(), "new face corners");
    std::memcpy(out, corners.data(), count * sizeof(int32_t));
  });
}

cgamesh_status cgamesh_change_moved_faces(const cgamesh_change* change, size_t index, int32_t* out, size_t count) {
  return guarded([&] {
    const surgery::MeshChange& c = change_at(change, index);
    need(out, "out");
    check_count(count, 2 * c.moved_faces.size(), "moved faces");
    for (std::size_t i = 0; i < c.moved_faces.size(); ++i) {
      out[2 * i] = c.moved_faces[i][0];
      out[2 * i + 1] = c.moved_faces[i][1];
    }
  });
}

cgamesh_status cgamesh_change_origins(const cgamesh_change* change, size_t index, int32_t* vertices, float* weights,
                                      size_t count) {
  return guarded([&] {
    const surgery::MeshChange& c = change_at(change, index);
    need(vertices, "vertices");
    need(weights, "weights");
    check_count(count, 3 * c.origins.size(), "origins");
    for (std::size_t i = 0; i < c.origins.size(); ++i)
      for (std::size_t k = 0; k < 3; ++k) {
        vertices[3 * i + k] = c.origins[i].vertex[k];
        weights[3 * i + k] = c.origins[i].weight[k];
      }
  });
}

// ---- Living tissue ----

cgamesh_status cgamesh_tissue_options_default(cgamesh_tissue_options* out) {
  return guarded([&] {
    const soft::TissueOptions t;
    need(out, "out") = {t.density,        t.attachment_compliance, t.stretch_compliance, t.bend_compliance,
                        t.pretension,     t.damping,               t.substep,            {t.gravity.x(), t.gravity.y(), t.gravity.z()},
                        t.region_radius,  t.release_margin,        t.max_particles};
  });
}

cgamesh_status cgamesh_live_set_tissue(cgamesh_live* live, const cgamesh_tissue_options* options) {
  return guarded([&] {
    cgamesh_live& l = need(live, "live");
    const soft::TissueOptions o = options != nullptr ? tissue_options(*options) : soft::TissueOptions{};
    if (l.tissue)
      l.tissue->set_options(l.live, o);
    else
      l.tissue.emplace(l.live, o);
  });
}

cgamesh_status cgamesh_live_clear_tissue(cgamesh_live* live) {
  return guarded([&] { need(live, "live").tissue.reset(); });
}

cgamesh_status cgamesh_live_step_tissue(cgamesh_live* live, const cgamesh_pose* pose, double dt) {
  return guarded([&] {
    cgamesh_live& l = need(live, "live");
    if (!l.tissue) throw InvalidInputError("the tissue is off (cgamesh_live_set_tissue)");
    std::optional<anim::Pose> bind;
    l.tissue->step(l.live, pose_for(l.live.model(), pose, bind), dt);
  });
}

cgamesh_status cgamesh_live_bake_tissue(cgamesh_live* live, const cgamesh_pose* pose) {
  return guarded([&] {
    cgamesh_live& l = need(live, "live");
    if (!l.tissue) throw InvalidInputError("the tissue is off (cgamesh_live_set_tissue)");
    std::optional<anim::Pose> bind;
    const anim::Pose& p = pose_for(l.live.model(), pose, bind);
    anim::RiggedModel baked = l.tissue->bake(l.live, p);
    const soft::TissueOptions o = l.tissue->options();
    l.live = surgery::LiveModel(baked, surgery::place(baked, p));
    l.tissue.emplace(l.live, o);
  });
}

// ---- Deformation ----

cgamesh_status cgamesh_model_deform(const cgamesh_model* model, const char* spec_json, cgamesh_model** out) {
  return guarded([&] {
    const anim::RiggedModel& m = need(model, "model").model;
    need(out, "out");
    const deform::DeformSpec spec = deform::parse_spec(need_text(spec_json, "spec_json"), "spec");
    const deform::BoundDeformer bound(spec, m);
    *out = new cgamesh_model{bound.deformed_model(m, bound.apply(bound.keys())), {}, {}};
  });
}

}  // extern "C"
