/*
 * cgamesh's C ABI: rigged models animated, cut, torn, drilled and deformed in Conformal
 * Geometric Algebra, for game engines (Unity through P/Invoke, Godot, Unreal) and every
 * language that speaks C. C99; link with -lcgamesh_c.
 *
 * Conventions
 *  - Handles are opaque; each is freed by its own *_free (NULL is accepted and ignored).
 *  - Every function but the *_free, cgamesh_version and cgamesh_last_error returns a
 *    cgamesh_status. On an error nothing was changed (no handle made, no buffer written
 *    beyond what the function says) and cgamesh_last_error() gives the message.
 *  - Arrays are caller-owned and sized in elements (floats, ints), never in bytes: positions
 *    and normals are #V*3 floats (x y z per vertex), faces #F*3 int32 vertex indices. A buffer
 *    of the wrong size is CGAMESH_ERROR_INVALID_ARGUMENT: ask the counts first.
 *  - Text is UTF-8. A string returned through char** is freed with cgamesh_string_free.
 *  - A handle may be used from one thread at a time; different handles from different
 *    threads. The calls that run per frame (cgamesh_pose_sample, cgamesh_*_skin,
 *    cgamesh_tissue_step) allocate nothing the caller sees.
 */
#ifndef CGAMESH_CGAMESH_H
#define CGAMESH_CGAMESH_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32) && defined(CGAMESH_C_BUILD)
#define CGAMESH_API __declspec(dllexport)
#elif defined(_WIN32)
#define CGAMESH_API __declspec(dllimport)
#elif defined(__GNUC__)
#define CGAMESH_API __attribute__((visibility("default")))
#else
#define CGAMESH_API
#endif

/** The version of this interface: changes when a function or struct changes. */
#define CGAMESH_C_ABI_VERSION 1

/* ---- Status and errors ---- */

/** What a call did. The error kinds are cgamesh::Error's (the CLI's exit codes and Python's
 *  exceptions map the same kinds). */
typedef enum cgamesh_status {
  CGAMESH_OK = 0,
  CGAMESH_ERROR_INVALID_ARGUMENT = 1, /**< a null handle or pointer, a wrong buffer size, NaN, a bad name or value */
  CGAMESH_ERROR_FILE = 2,             /**< an input file is missing, unreadable or no valid model */
  CGAMESH_ERROR_WRITE = 3,            /**< an output file could not be written (nothing was left behind) */
  CGAMESH_ERROR_TOPOLOGY = 4,         /**< the mesh does not allow the operation (the tool misses it, an open section) */
  CGAMESH_ERROR_SOLVER = 5,           /**< a numerical method failed (a singular system, a diverging tissue) */
  CGAMESH_ERROR_PLATFORM = 6,         /**< the machine cannot do what was asked */
  CGAMESH_ERROR_OUT_OF_MEMORY = 7,
  CGAMESH_ERROR_INTERNAL = 8,         /**< a bug: please report it with the message */
  CGAMESH_STATUS_MAX_ENUM = 0x7FFFFFFF /**< (makes the type 32 bits wide: any value may be passed) */
} cgamesh_status;

/** The message of the last error on this thread ("" when the last call succeeded); valid until
 *  the next call on this thread. */
CGAMESH_API const char* cgamesh_last_error(void);
/** The name of a status ("CGAMESH_ERROR_FILE"), or "unknown status". */
CGAMESH_API const char* cgamesh_status_name(cgamesh_status status);
/** The library's version ("0.1.0"). */
CGAMESH_API const char* cgamesh_version(void);
/** CGAMESH_C_ABI_VERSION of the library loaded (compare with the header's). */
CGAMESH_API int cgamesh_abi_version(void);
/** Frees a string the library returned. */
CGAMESH_API void cgamesh_string_free(char* text);

/* ---- Handles ---- */

/** A rigged model: meshes, skins, skeleton, clips, materials. */
typedef struct cgamesh_model cgamesh_model;
/** A pose of a model's skeleton: a clip sampled, joint edits, morph weights. */
typedef struct cgamesh_pose cgamesh_pose;
/** A model placed in a pose, cut, torn and drilled in place: each operation costs what it
 *  changes, and reports the change so that an engine updates its own buffers. */
typedef struct cgamesh_live cgamesh_live;
/** What one operation in place changed. */
typedef struct cgamesh_change cgamesh_change;

/* ---- Models ---- */

/** Loads every format the CLI reads (glTF, FBX, Collada, X, SMD, OBJ, PLY, ... through Assimp).
 *  @return CGAMESH_ERROR_FILE for a missing or corrupt file. */
CGAMESH_API cgamesh_status cgamesh_model_load(const char* path, cgamesh_model** out);
CGAMESH_API void cgamesh_model_free(cgamesh_model* model);
/** Writes by the extension, as the CLI does: .glb/.gltf rigged (skin, skeleton, clips),
 *  .obj/.ply the surface in `pose` (NULL: the bind pose) with cga skinning. All or nothing.
 *  @return CGAMESH_ERROR_INVALID_ARGUMENT for another extension, CGAMESH_ERROR_WRITE. */
CGAMESH_API cgamesh_status cgamesh_model_save(const cgamesh_model* model, const char* path,
                                              const cgamesh_pose* pose);
/** What loading or saving warned about (a count; then each by index, valid while the model is). */
CGAMESH_API cgamesh_status cgamesh_model_warning_count(const cgamesh_model* model, size_t* out);
CGAMESH_API cgamesh_status cgamesh_model_warning(const cgamesh_model* model, size_t index, const char** out);
/** `cgamesh info --json`'s document (meshes, joints, clips, bind-pose boxes, warnings).
 *  Free *out with cgamesh_string_free. */
CGAMESH_API cgamesh_status cgamesh_model_info_json(const cgamesh_model* model, char** out);

typedef struct cgamesh_model_counts {
  int32_t meshes, joints, clips;
} cgamesh_model_counts;
CGAMESH_API cgamesh_status cgamesh_model_counts_get(const cgamesh_model* model, cgamesh_model_counts* out);
/** Vertices and faces of mesh `mesh`. */
CGAMESH_API cgamesh_status cgamesh_model_mesh_size(const cgamesh_model* model, int32_t mesh, int32_t* vertices,
                                                   int32_t* faces);
/** Rest positions (#V*3 floats), faces (#F*3 ints) and UVs (#V*2 floats; *has_uvs 0 when the
 *  mesh has none and nothing is written) of mesh `mesh`. */
CGAMESH_API cgamesh_status cgamesh_model_mesh_positions(const cgamesh_model* model, int32_t mesh, float* out,
                                                        size_t count);
CGAMESH_API cgamesh_status cgamesh_model_mesh_faces(const cgamesh_model* model, int32_t mesh, int32_t* out,
                                                    size_t count);
CGAMESH_API cgamesh_status cgamesh_model_mesh_uvs(const cgamesh_model* model, int32_t mesh, float* out, size_t count,
                                                  int32_t* has_uvs);
/** The joint named `name`. @return CGAMESH_ERROR_INVALID_ARGUMENT naming the joints there are. */
CGAMESH_API cgamesh_status cgamesh_model_joint_index(const cgamesh_model* model, const char* name, int32_t* out);
/** The clip named or numbered `name` ("Walk", "0"). */
CGAMESH_API cgamesh_status cgamesh_model_clip_index(const cgamesh_model* model, const char* name, int32_t* out);
CGAMESH_API cgamesh_status cgamesh_model_clip_duration(const cgamesh_model* model, int32_t clip, double* seconds);

/* ---- Poses ---- */

typedef enum cgamesh_blend {
  CGAMESH_BLEND_FORMAT = 0, /**< as the file says (glTF: lerp/slerp, step, cubic spline) */
  CGAMESH_BLEND_LINEAR = 1, /**< linear blend of the key versors */
  CGAMESH_BLEND_LOG = 2,    /**< logarithmic blend of the key versors */
  CGAMESH_BLEND_MAX_ENUM = 0x7FFFFFFF
} cgamesh_blend;

/** A pose of `model`'s skeleton: the bind pose to begin with. */
CGAMESH_API cgamesh_status cgamesh_pose_create(const cgamesh_model* model, cgamesh_pose** out);
CGAMESH_API void cgamesh_pose_free(cgamesh_pose* pose);
/** The pose the CLI's --anim/--time/--blend choose: clip `clip` (−1 with time < 0: the bind
 *  pose; −1 with a time: the first clip) at `time` seconds, then the pose's edits and morph
 *  weights again. A time past the clip's end uses its last pose and warns
 *  (cgamesh_pose_warning). Allocates nothing after the first call. */
CGAMESH_API cgamesh_status cgamesh_pose_sample(cgamesh_pose* pose, const cgamesh_model* model, int32_t clip,
                                               double time, cgamesh_blend blend);
/** Edits of joint `joint`, kept over later samples (in the joint's frame, after the clip):
 *  a rotation by `degrees` about `axis`, a translation, a uniform scale (a dilator, > 0). */
CGAMESH_API cgamesh_status cgamesh_pose_rotate(cgamesh_pose* pose, const cgamesh_model* model, int32_t joint,
                                               const double axis[3], double degrees);
CGAMESH_API cgamesh_status cgamesh_pose_translate(cgamesh_pose* pose, const cgamesh_model* model, int32_t joint,
                                                  const double translation[3]);
CGAMESH_API cgamesh_status cgamesh_pose_scale(cgamesh_pose* pose, const cgamesh_model* model, int32_t joint,
                                              double scale);
/** Morph target `target` (every mesh's of that name) at `weight`, over the clip's. */
CGAMESH_API cgamesh_status cgamesh_pose_set_morph_weight(cgamesh_pose* pose, const cgamesh_model* model,
                                                         const char* target, float weight);
/** Drops the edits and morph weights. */
CGAMESH_API cgamesh_status cgamesh_pose_clear_edits(cgamesh_pose* pose, const cgamesh_model* model);
/** What the last sample warned about. */
CGAMESH_API cgamesh_status cgamesh_pose_warning_count(const cgamesh_pose* pose, size_t* out);
CGAMESH_API cgamesh_status cgamesh_pose_warning(const cgamesh_pose* pose, size_t index, const char** out);

/* ---- Skinning (eq. 17) ---- */

typedef enum cgamesh_skinning {
  CGAMESH_SKINNING_CGA = 0,    /**< versors of the bones, exact for any rig (the default) */
  CGAMESH_SKINNING_VERSOR = 1, /**< blended versors */
  CGAMESH_SKINNING_MATRIX = 2, /**< linear blend of matrices */
  CGAMESH_SKINNING_DQS = 3,    /**< dual quaternions */
  CGAMESH_SKINNING_MAX_ENUM = 0x7FFFFFFF
} cgamesh_skinning;

/** Mesh `mesh` of `model` in `pose`, world space: #V*3 positions into `positions`, and when
 *  `normals` is not NULL #V*3 unit normals (a mesh without normals: *normals untouched and
 *  CGAMESH_ERROR_INVALID_ARGUMENT). No allocation after the first call for a mesh size. */
CGAMESH_API cgamesh_status cgamesh_model_skin(const cgamesh_model* model, const cgamesh_pose* pose, int32_t mesh,
                                              cgamesh_skinning mode, float* positions, size_t position_count,
                                              float* normals, size_t normal_count);

/* ---- Surgery in place ---- */

/** Copies `model` and places it in `pose` (NULL: the bind pose). */
CGAMESH_API cgamesh_status cgamesh_live_create(const cgamesh_model* model, const cgamesh_pose* pose,
                                               cgamesh_live** out);
CGAMESH_API void cgamesh_live_free(cgamesh_live* live);
/** The model as it is now (a copy, to save or to keep). */
CGAMESH_API cgamesh_status cgamesh_live_model(const cgamesh_live* live, cgamesh_model** out);
CGAMESH_API cgamesh_status cgamesh_live_mesh_size(const cgamesh_live* live, int32_t mesh, int32_t* vertices,
                                                  int32_t* faces);
/** Current faces (#F*3) and rest positions (#V*3) of mesh `mesh`. */
CGAMESH_API cgamesh_status cgamesh_live_mesh_faces(const cgamesh_live* live, int32_t mesh, int32_t* out,
                                                   size_t count);
CGAMESH_API cgamesh_status cgamesh_live_mesh_positions(const cgamesh_live* live, int32_t mesh, float* out,
                                                       size_t count);
/** As cgamesh_model_skin, on the model as it is now; with living tissue on, the simulated
 *  surface where it is simulated (cgamesh_live_set_tissue). */
CGAMESH_API cgamesh_status cgamesh_live_skin(const cgamesh_live* live, const cgamesh_pose* pose, int32_t mesh,
                                             cgamesh_skinning mode, float* positions, size_t position_count,
                                             float* normals, size_t normal_count);
/** Cuts every mesh by the plane n·x = d (placed coordinates); both sides stay in their meshes,
 *  split along the section. `change` may be NULL. */
CGAMESH_API cgamesh_status cgamesh_live_cut(cgamesh_live* live, const double normal[3], double d,
                                            cgamesh_change** change);
/** Tears along the path a scalpel sweeps: `blades` holds `count` >= 2 positions of the blade,
 *  6 doubles each (handle x y z, tip x y z); `open` widens the wound (model units, 0: none).
 *  @return CGAMESH_ERROR_TOPOLOGY when the blade misses the surface. */
CGAMESH_API cgamesh_status cgamesh_live_tear(cgamesh_live* live, const double* blades, size_t count, double open,
                                             cgamesh_change** change);
/** Drills a hole of `radius` from `base` towards `tip`; `wall` != 0 lines it with a tube. */
CGAMESH_API cgamesh_status cgamesh_live_drill(cgamesh_live* live, const double tip[3], const double base[3],
                                              double radius, int32_t wall, cgamesh_change** change);

CGAMESH_API void cgamesh_change_free(cgamesh_change* change);
/** The operation's counts and warnings, as the CLI's --json reports them. */
CGAMESH_API cgamesh_status cgamesh_change_json(const cgamesh_change* change, char** out);
/** How many meshes changed. */
CGAMESH_API cgamesh_status cgamesh_change_mesh_count(const cgamesh_change* change, size_t* out);

/** What changed in one mesh. Vertices keep their ids and are never removed (one cut away is left
 *  unused); new ones are first_new_vertex ... first_new_vertex + new_vertices − 1. New faces
 *  have the ids cgamesh_change_new_faces gives; other faces keep theirs, except the moved ones
 *  (cgamesh_change_moved_faces), which filled the slots of removed faces. */
typedef struct cgamesh_mesh_change {
  int32_t mesh;
  int32_t first_new_vertex;
  int32_t new_vertices;
  int32_t new_faces;
  int32_t moved_faces;
  int32_t removed_faces;
} cgamesh_mesh_change;
CGAMESH_API cgamesh_status cgamesh_change_mesh(const cgamesh_change* change, size_t index, cgamesh_mesh_change* out);
/** Ids of the new faces (new_faces ints). */
CGAMESH_API cgamesh_status cgamesh_change_new_faces(const cgamesh_change* change, size_t index, int32_t* out,
                                                    size_t count);
/** The vertices of the new faces, in the order of cgamesh_change_new_faces (3*new_faces ints):
 *  with them and the moved faces an engine brings its index buffer up to date without reading
 *  every face again. */
CGAMESH_API cgamesh_status cgamesh_change_new_face_corners(const cgamesh_change* change, size_t index, int32_t* out,
                                                           size_t count);
/** (id before, id after) of each moved face (2*moved_faces ints). */
CGAMESH_API cgamesh_status cgamesh_change_moved_faces(const cgamesh_change* change, size_t index, int32_t* out,
                                                      size_t count);
/** Per new vertex, where it comes from: up to 3 old vertices (−1: unused) and their barycentric
 *  weights (3*new_vertices ints and floats), for an engine's own attributes. */
CGAMESH_API cgamesh_status cgamesh_change_origins(const cgamesh_change* change, size_t index, int32_t* vertices,
                                                  float* weights, size_t count);

/* ---- Living tissue (XPBD soft body on the skinned surface) ---- */

/** The options of soft/tissue_options.hpp, with their units; cgamesh_tissue_options_default
 *  fills the defaults. */
typedef struct cgamesh_tissue_options {
  double density;               /**< kg per square model unit */
  double attachment_compliance; /**< of each particle to its skinned target */
  double stretch_compliance;
  double bend_compliance;
  double pretension;            /**< rest lengths this fraction shorter than skinned, in [0, 1) */
  double damping;               /**< per second */
  double substep;               /**< seconds, > 0 */
  double gravity[3];            /**< model units per second² */
  double region_radius;         /**< around each wound; 0: a tenth of the model's diagonal */
  double release_margin;        /**< released from attachment; 0: a quarter of the region radius */
  int32_t max_particles;        /**< budget of simulated particles; 0: none */
} cgamesh_tissue_options;
CGAMESH_API cgamesh_status cgamesh_tissue_options_default(cgamesh_tissue_options* out);
/** Turns living tissue on (`options` NULL: the defaults), or changes its options. Every later
 *  cut, tear and drill of `live` opens as the tissue responds. */
CGAMESH_API cgamesh_status cgamesh_live_set_tissue(cgamesh_live* live, const cgamesh_tissue_options* options);
/** Turns it off. */
CGAMESH_API cgamesh_status cgamesh_live_clear_tissue(cgamesh_live* live);
/** Advances the tissue by `dt` seconds towards `pose`. */
CGAMESH_API cgamesh_status cgamesh_live_step_tissue(cgamesh_live* live, const cgamesh_pose* pose, double dt);
/** Writes the simulated surface back as rest positions (it then animates as simulated). */
CGAMESH_API cgamesh_status cgamesh_live_bake_tissue(cgamesh_live* live, const cgamesh_pose* pose);

/* ---- Deformation ---- */

/** Deforms `model` by a spec given as JSON text (the CLI's `deform --spec`, docs/deform.md) at
 *  the spec's keys, and returns the deformed model (it re-animates). */
CGAMESH_API cgamesh_status cgamesh_model_deform(const cgamesh_model* model, const char* spec_json,
                                                cgamesh_model** out);

#ifdef __cplusplus
}
#endif

#endif /* CGAMESH_CGAMESH_H */
