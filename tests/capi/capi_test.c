/*
 * The C ABI (include/cgamesh/cgamesh.h), tested from C99: every function, its error paths (null
 * handles, wrong sizes, missing files, tools that miss), and results equal to the CLI's (the
 * same skinned positions, the same counts, the same file). Run as `capi_test NAME`, one ctest
 * per test; `capi_test` alone runs them all.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cgamesh/cgamesh.h"

static int failures = 0;

#define CHECK(cond)                                                                        \
  do {                                                                                     \
    if (!(cond)) {                                                                         \
      fprintf(stderr, "%s:%d: CHECK failed: %s (last error: %s)\n", __FILE__, __LINE__, #cond, \
              cgamesh_last_error());                                                       \
      ++failures;                                                                          \
    }                                                                                      \
  } while (0)
#define CHECK_OK(call) CHECK((call) == CGAMESH_OK)
#define CHECK_STATUS(call, status)                                                         \
  do {                                                                                     \
    const cgamesh_status got_ = (call);                                                    \
    if (got_ != (status)) {                                                                \
      fprintf(stderr, "%s:%d: %s gave %s, expected %s (%s)\n", __FILE__, __LINE__, #call,  \
              cgamesh_status_name(got_), cgamesh_status_name(status), cgamesh_last_error()); \
      ++failures;                                                                          \
    } else if ((status) != CGAMESH_OK && cgamesh_last_error()[0] == '\0') {                \
      fprintf(stderr, "%s:%d: %s failed without a message\n", __FILE__, __LINE__, #call);  \
      ++failures;                                                                          \
    }                                                                                      \
  } while (0)

static const char* model_path(void) { return CGAMESH_DATA_DIR "/CesiumMan.glb"; }

static char* temp_path(const char* name) {
  static char buffers[8][512];
  static int next = 0;
  char* out = buffers[next++ % 8];
  const char* dir = getenv("TMPDIR");
  snprintf(out, 512, "%s/cgamesh_capi_%ld_%s", dir != NULL ? dir : "/tmp", (long)getpid(), name);
  return out;
}

static char* read_file(const char* path, size_t* size) {
  FILE* f = fopen(path, "rb");
  if (f == NULL) return NULL;
  fseek(f, 0, SEEK_END);
  const long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char* data = (char*)malloc((size_t)n + 1);
  if (data != NULL && fread(data, 1, (size_t)n, f) != (size_t)n) {
    free(data);
    data = NULL;
  }
  fclose(f);
  if (data != NULL) {
    data[n] = '\0';
    if (size != NULL) *size = (size_t)n;
  }
  return data;
}

/* Runs the CLI with `args`, its stdout into `out_path`; its exit status. */
static int run_cli(const char* args, const char* out_path) {
  char command[2048];
  snprintf(command, sizeof command, "'%s' %s > '%s'", CGAMESH_CLI, args, out_path);
  return system(command);
}

/* The integer after "key": in a JSON text (the first one), or -1. */
static long json_int(const char* text, const char* key) {
  char pattern[128];
  snprintf(pattern, sizeof pattern, "\"%s\":", key);
  const char* at = strstr(text, pattern);
  return at == NULL ? -1 : strtol(at + strlen(pattern), NULL, 10);
}

/* The `v` lines of an OBJ text into out (at most max rows); the row count. */
static int obj_vertices(const char* text, float* out, int max) {
  int row = 0;
  for (const char* line = text; line != NULL && *line != '\0';) {
    const char* next = strchr(line, '\n');
    if (line[0] == 'v' && line[1] == ' ') {
      if (row < max && sscanf(line + 2, "%f %f %f", &out[3 * row], &out[3 * row + 1], &out[3 * row + 2]) != 3) return -1;
      ++row;
    }
    line = next != NULL ? next + 1 : NULL;
  }
  return row;
}

static cgamesh_model* load(void) {
  cgamesh_model* m = NULL;
  CHECK_OK(cgamesh_model_load(model_path(), &m));
  CHECK(m != NULL);
  return m;
}

static int mesh_vertices(const cgamesh_model* m) {
  int32_t v = 0;
  CHECK_OK(cgamesh_model_mesh_size(m, 0, &v, NULL));
  return v;
}

/* ---- tests ---- */

static void test_version_and_status(void) {
  CHECK(strcmp(cgamesh_version(), CGAMESH_VERSION_STRING) == 0);
  CHECK(cgamesh_abi_version() == CGAMESH_C_ABI_VERSION);
  CHECK(strcmp(cgamesh_status_name(CGAMESH_ERROR_FILE), "CGAMESH_ERROR_FILE") == 0);
  CHECK(strcmp(cgamesh_status_name((cgamesh_status)99), "unknown status") == 0);
  cgamesh_string_free(NULL);
  cgamesh_model_free(NULL);
  cgamesh_pose_free(NULL);
  cgamesh_live_free(NULL);
  cgamesh_change_free(NULL);
}

static void test_load_and_inspect(void) {
  cgamesh_model* m = load();
  cgamesh_model_counts counts;
  CHECK_OK(cgamesh_model_counts_get(m, &counts));
  CHECK(counts.meshes == 1 && counts.joints == 22 && counts.clips == 1);
  int32_t v = 0, f = 0;
  CHECK_OK(cgamesh_model_mesh_size(m, 0, &v, &f));
  CHECK(v == 3273 && f == 4672);
  float* positions = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  int32_t* faces = (int32_t*)malloc(sizeof(int32_t) * 3 * (size_t)f);
  float* uvs = (float*)malloc(sizeof(float) * 2 * (size_t)v);
  CHECK_OK(cgamesh_model_mesh_positions(m, 0, positions, 3 * (size_t)v));
  CHECK_OK(cgamesh_model_mesh_faces(m, 0, faces, 3 * (size_t)f));
  int32_t has_uvs = -1;
  CHECK_OK(cgamesh_model_mesh_uvs(m, 0, uvs, 2 * (size_t)v, &has_uvs));
  CHECK(has_uvs == 1);
  int32_t lo = v, hi = -1;
  for (size_t i = 0; i < 3 * (size_t)f; ++i) {
    lo = faces[i] < lo ? faces[i] : lo;
    hi = faces[i] > hi ? faces[i] : hi;
  }
  CHECK(lo == 0 && hi == v - 1);
  /* The mesh-space box of `info`: z from 0 to 1.50655. */
  float zmax = -1;
  for (int32_t i = 0; i < v; ++i) zmax = positions[3 * i + 2] > zmax ? positions[3 * i + 2] : zmax;
  CHECK(fabsf(zmax - 1.50655f) < 1e-4f);
  CHECK_STATUS(cgamesh_model_mesh_positions(m, 0, positions, 3 * (size_t)v - 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_mesh_faces(m, 1, faces, 3 * (size_t)f), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_mesh_faces(m, 0, NULL, 3 * (size_t)f), CGAMESH_ERROR_INVALID_ARGUMENT);

  int32_t joint = -1, clip = -1;
  double duration = 0;
  CHECK_STATUS(cgamesh_model_joint_index(m, "no such joint", &joint), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cgamesh_last_error(), "no such joint") != NULL);
  CHECK_OK(cgamesh_model_clip_index(m, "0", &clip));
  CHECK(clip == 0);
  CHECK_STATUS(cgamesh_model_clip_index(m, "Dance", &clip), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_OK(cgamesh_model_clip_duration(m, 0, &duration));
  CHECK(fabs(duration - 2.0) < 0.1);
  CHECK_STATUS(cgamesh_model_clip_duration(m, 1, &duration), CGAMESH_ERROR_INVALID_ARGUMENT);

  char* info = NULL;
  CHECK_OK(cgamesh_model_info_json(m, &info));
  CHECK(info != NULL && strstr(info, "Cesium_Man") != NULL && json_int(info, "vertices") == 3273);
  /* The same document as `cgamesh info --json`. */
  const char* out = temp_path("info.json");
  char args[1024];
  snprintf(args, sizeof args, "info '%s' --json", model_path());
  CHECK(run_cli(args, out) == 0);
  char* cli = read_file(out, NULL);
  CHECK(cli != NULL && info != NULL && json_int(cli, "triangles") == json_int(info, "triangles") &&
        json_int(cli, "skinned_joints") == json_int(info, "skinned_joints"));
  free(cli);
  remove(out);
  cgamesh_string_free(info);
  size_t warnings = 99;
  CHECK_OK(cgamesh_model_warning_count(m, &warnings));
  const char* w = NULL;
  CHECK_STATUS(cgamesh_model_warning(m, warnings, &w), CGAMESH_ERROR_INVALID_ARGUMENT);
  free(positions);
  free(faces);
  free(uvs);
  cgamesh_model_free(m);
}

static void test_bad_files_and_null_handles(void) {
  cgamesh_model* m = (cgamesh_model*)0x1;
  CHECK_STATUS(cgamesh_model_load("/no/such/file.glb", &m), CGAMESH_ERROR_FILE);
  CHECK(m == (cgamesh_model*)0x1); /* untouched on error */
  CHECK(strstr(cgamesh_last_error(), "/no/such/file.glb") != NULL);
  const char* junk = temp_path("junk.glb");
  FILE* f = fopen(junk, "wb");
  fputs("glTF but not really", f);
  fclose(f);
  CHECK_STATUS(cgamesh_model_load(junk, &m), CGAMESH_ERROR_FILE);
  remove(junk);
  CHECK_STATUS(cgamesh_model_load(NULL, &m), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_load(model_path(), NULL), CGAMESH_ERROR_INVALID_ARGUMENT);

  /* Every function with a null handle is refused, with a message. */
  cgamesh_model_counts counts;
  int32_t i32 = 0;
  size_t n = 0;
  char* text = NULL;
  const char* ctext = NULL;
  float buffer[3];
  double d3[3] = {0, 1, 0};
  cgamesh_pose* pose = NULL;
  cgamesh_live* live = NULL;
  cgamesh_change* change = NULL;
  cgamesh_mesh_change mc;
  cgamesh_tissue_options options;
  CHECK_STATUS(cgamesh_model_save(NULL, "x.glb", NULL), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_warning_count(NULL, &n), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_warning(NULL, 0, &ctext), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_info_json(NULL, &text), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_counts_get(NULL, &counts), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_mesh_size(NULL, 0, &i32, &i32), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_mesh_positions(NULL, 0, buffer, 3), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_mesh_faces(NULL, 0, &i32, 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_mesh_uvs(NULL, 0, buffer, 2, &i32), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_joint_index(NULL, "a", &i32), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_clip_index(NULL, "0", &i32), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_clip_duration(NULL, 0, d3), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_create(NULL, &pose), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_sample(NULL, NULL, 0, 0, CGAMESH_BLEND_FORMAT), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_rotate(NULL, NULL, 0, d3, 10), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_translate(NULL, NULL, 0, d3), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_scale(NULL, NULL, 0, 2), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_set_morph_weight(NULL, NULL, "a", 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_clear_edits(NULL, NULL), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_warning_count(NULL, &n), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_warning(NULL, 0, &ctext), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_skin(NULL, NULL, 0, CGAMESH_SKINNING_CGA, buffer, 3, NULL, 0),
               CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_create(NULL, NULL, &live), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_model(NULL, &m), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_mesh_size(NULL, 0, &i32, &i32), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_mesh_faces(NULL, 0, &i32, 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_mesh_positions(NULL, 0, buffer, 3), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_skin(NULL, NULL, 0, CGAMESH_SKINNING_CGA, buffer, 3, NULL, 0),
               CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_cut(NULL, d3, 0, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_tear(NULL, d3, 1, 0, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_drill(NULL, d3, d3, 1, 0, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_json(NULL, &text), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_mesh_count(NULL, &n), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_mesh(NULL, 0, &mc), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_new_faces(NULL, 0, &i32, 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_new_face_corners(NULL, 0, &i32, 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_moved_faces(NULL, 0, &i32, 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_origins(NULL, 0, &i32, buffer, 3), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_tissue_options_default(NULL), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_set_tissue(NULL, &options), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_clear_tissue(NULL), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_step_tissue(NULL, NULL, 0.01), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_bake_tissue(NULL, NULL), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_deform(NULL, "{}", &m), CGAMESH_ERROR_INVALID_ARGUMENT);
  /* A success clears the last error. */
  CHECK_OK(cgamesh_tissue_options_default(&options));
  CHECK(cgamesh_last_error()[0] == '\0');
}

/* Skinned positions equal the CLI's `pose` OBJ (9 significant digits: float exact). */
static void compare_with_cli_pose(const cgamesh_model* m, const cgamesh_pose* pose, const char* cli_args) {
  const int v = mesh_vertices(m);
  float* mine = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  CHECK_OK(cgamesh_model_skin(m, pose, 0, CGAMESH_SKINNING_CGA, mine, 3 * (size_t)v, NULL, 0));
  const char* obj = temp_path("pose.obj");
  const char* log = temp_path("pose.log");
  char args[1024];
  snprintf(args, sizeof args, "pose '%s' %s -o '%s'", model_path(), cli_args, obj);
  CHECK(run_cli(args, log) == 0);
  char* text = read_file(obj, NULL);
  CHECK(text != NULL);
  float* cli = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  CHECK(text != NULL && obj_vertices(text, cli, v) == v);
  CHECK(memcmp(cli, mine, sizeof(float) * 3 * (size_t)v) == 0);
  free(cli);
  free(text);
  free(mine);
  remove(obj);
  remove(log);
}

static void test_pose_and_skin_equal_the_cli(void) {
  cgamesh_model* m = load();
  cgamesh_pose* pose = NULL;
  CHECK_OK(cgamesh_pose_create(m, &pose));
  compare_with_cli_pose(m, pose, "");
  CHECK_OK(cgamesh_pose_sample(pose, m, 0, 0.75, CGAMESH_BLEND_LOG));
  compare_with_cli_pose(m, pose, "--anim 0 --time 0.75 --blend log");
  int32_t joint = -1;
  const double axis[3] = {0, 0, 1}, move[3] = {0, 0.05, 0};
  CHECK_OK(cgamesh_model_joint_index(m, "nodes[13]", &joint));
  CHECK_OK(cgamesh_pose_rotate(pose, m, joint, axis, 30));
  CHECK_OK(cgamesh_pose_translate(pose, m, joint, move));
  CHECK_OK(cgamesh_pose_scale(pose, m, joint, 1.5));
  compare_with_cli_pose(m, pose,
                        "--anim 0 --time 0.75 --blend log --set 'nodes[13]:rotate=0,0,1,30' "
                        "--set 'nodes[13]:translate=0,0.05,0' --set 'nodes[13]:scale=1.5'");
  /* Edits stay over later samples, and go with clear_edits. */
  CHECK_OK(cgamesh_pose_sample(pose, m, 0, 0.25, CGAMESH_BLEND_FORMAT));
  compare_with_cli_pose(m, pose,
                        "--time 0.25 --set 'nodes[13]:rotate=0,0,1,30' "
                        "--set 'nodes[13]:translate=0,0.05,0' --set 'nodes[13]:scale=1.5'");
  CHECK_OK(cgamesh_pose_clear_edits(pose, m));
  compare_with_cli_pose(m, pose, "--time 0.25");

  /* Past the end: the last pose, and a warning, as the CLI says. */
  size_t n = 9;
  const char* w = NULL;
  CHECK_OK(cgamesh_pose_warning_count(pose, &n));
  CHECK(n == 0);
  CHECK_OK(cgamesh_pose_sample(pose, m, -1, 40, CGAMESH_BLEND_FORMAT));
  CHECK_OK(cgamesh_pose_warning_count(pose, &n));
  CHECK(n == 1);
  CHECK_OK(cgamesh_pose_warning(pose, 0, &w));
  CHECK(w != NULL && strstr(w, "past the end of clip") != NULL);
  compare_with_cli_pose(m, pose, "--time 40");

  /* Bad requests leave the pose as it was. */
  CHECK_STATUS(cgamesh_pose_sample(pose, m, 3, 0, CGAMESH_BLEND_FORMAT), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_sample(pose, m, 0, NAN, CGAMESH_BLEND_FORMAT), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_sample(pose, m, 0, 1, (cgamesh_blend)7), CGAMESH_ERROR_INVALID_ARGUMENT);
  const double zero[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 0};
  CHECK_STATUS(cgamesh_pose_rotate(pose, m, joint, zero, 30), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_translate(pose, m, joint, nan3), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_scale(pose, m, joint, 0), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_scale(pose, m, 99, 2), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_pose_set_morph_weight(pose, m, "no target", 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  compare_with_cli_pose(m, pose, "--time 40");

  /* Wrong buffer sizes; normals in one pass; every mode. */
  const int v = mesh_vertices(m);
  float* p = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  float* nrm = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  CHECK_STATUS(cgamesh_model_skin(m, pose, 0, CGAMESH_SKINNING_CGA, p, 3 * (size_t)v + 3, NULL, 0),
               CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_skin(m, pose, 0, CGAMESH_SKINNING_CGA, p, 3 * (size_t)v, nrm, 3),
               CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_skin(m, pose, 0, (cgamesh_skinning)9, p, 3 * (size_t)v, NULL, 0),
               CGAMESH_ERROR_INVALID_ARGUMENT);
  for (int mode = 0; mode < 4; ++mode) {
    CHECK_OK(cgamesh_model_skin(m, pose, 0, (cgamesh_skinning)mode, p, 3 * (size_t)v, nrm, 3 * (size_t)v));
    double worst = 0;
    for (int i = 0; i < v; ++i) {
      const double len = sqrt(nrm[3 * i] * nrm[3 * i] + nrm[3 * i + 1] * nrm[3 * i + 1] + nrm[3 * i + 2] * nrm[3 * i + 2]);
      worst = fabs(len - 1) > worst ? fabs(len - 1) : worst;
    }
    CHECK(worst < 1e-4);
  }
  free(p);
  free(nrm);
  cgamesh_pose_free(pose);
  cgamesh_model_free(m);
}

static void test_save_equals_the_cli(void) {
  cgamesh_model* m = load();
  const char* mine = temp_path("mine.glb");
  const char* cli = temp_path("cli.glb");
  const char* log = temp_path("convert.log");
  CHECK_OK(cgamesh_model_save(m, mine, NULL));
  char args[1024];
  snprintf(args, sizeof args, "convert '%s' -o '%s'", model_path(), cli);
  CHECK(run_cli(args, log) == 0);
  size_t a = 0, b = 0;
  char* x = read_file(mine, &a);
  char* y = read_file(cli, &b);
  CHECK(x != NULL && y != NULL && a == b && memcmp(x, y, a) == 0);
  free(x);
  free(y);
  /* Another extension, or a directory that does not exist: refused, nothing written. */
  CHECK_STATUS(cgamesh_model_save(m, temp_path("out.fbx"), NULL), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK(read_file(temp_path("out.fbx"), NULL) == NULL);
  CHECK_STATUS(cgamesh_model_save(m, "/no/such/dir/out.glb", NULL), CGAMESH_ERROR_WRITE);
  /* An OBJ in a pose: the CLI's pose. */
  cgamesh_pose* pose = NULL;
  CHECK_OK(cgamesh_pose_create(m, &pose));
  CHECK_OK(cgamesh_pose_sample(pose, m, 0, 0.5, CGAMESH_BLEND_FORMAT));
  const char* obj = temp_path("mine.obj");
  const char* cli_obj = temp_path("cli.obj");
  CHECK_OK(cgamesh_model_save(m, obj, pose));
  snprintf(args, sizeof args, "pose '%s' --time 0.5 -o '%s'", model_path(), cli_obj);
  CHECK(run_cli(args, log) == 0);
  x = read_file(obj, &a);
  y = read_file(cli_obj, &b);
  CHECK(x != NULL && y != NULL && a == b && memcmp(x, y, a) == 0);
  free(x);
  free(y);
  remove(mine);
  remove(cli);
  remove(obj);
  remove(cli_obj);
  remove(log);
  cgamesh_pose_free(pose);
  cgamesh_model_free(m);
}

/* Brings `faces` (#F*3, as before the change) up to date from the change alone, as an engine
 * would, and checks it equals the live mesh's faces. */
static void check_incremental_update(const cgamesh_live* live, const cgamesh_change* change, int32_t* faces,
                                     int32_t faces_before, int32_t vertices_before) {
  size_t meshes = 0;
  CHECK_OK(cgamesh_change_mesh_count(change, &meshes));
  CHECK(meshes == 1);
  cgamesh_mesh_change c;
  CHECK_OK(cgamesh_change_mesh(change, 0, &c));
  CHECK(c.mesh == 0 && c.first_new_vertex == vertices_before);
  int32_t v = 0, f = 0;
  CHECK_OK(cgamesh_live_mesh_size(live, 0, &v, &f));
  CHECK(v == vertices_before + c.new_vertices);
  CHECK(f == faces_before - c.removed_faces + c.new_faces);
  int32_t* after = (int32_t*)malloc(sizeof(int32_t) * 3 * (size_t)f);
  memcpy(after, faces, sizeof(int32_t) * 3 * (size_t)(f < faces_before ? f : faces_before));
  int32_t* moved = (int32_t*)malloc(sizeof(int32_t) * (2 * (size_t)c.moved_faces + 1));
  int32_t* ids = (int32_t*)malloc(sizeof(int32_t) * ((size_t)c.new_faces + 1));
  int32_t* corners = (int32_t*)malloc(sizeof(int32_t) * (3 * (size_t)c.new_faces + 1));
  CHECK_OK(cgamesh_change_moved_faces(change, 0, moved, 2 * (size_t)c.moved_faces));
  CHECK_OK(cgamesh_change_new_faces(change, 0, ids, (size_t)c.new_faces));
  CHECK_OK(cgamesh_change_new_face_corners(change, 0, corners, 3 * (size_t)c.new_faces));
  CHECK_STATUS(cgamesh_change_new_faces(change, 0, ids, (size_t)c.new_faces + 1), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_change_mesh(change, 1, &c), CGAMESH_ERROR_INVALID_ARGUMENT);
  for (int32_t i = 0; i < c.moved_faces; ++i) memcpy(after + 3 * moved[2 * i + 1], faces + 3 * moved[2 * i], 3 * sizeof(int32_t));
  for (int32_t i = 0; i < c.new_faces; ++i) memcpy(after + 3 * ids[i], corners + 3 * i, 3 * sizeof(int32_t));
  int32_t* now = (int32_t*)malloc(sizeof(int32_t) * 3 * (size_t)f);
  CHECK_OK(cgamesh_live_mesh_faces(live, 0, now, 3 * (size_t)f));
  CHECK(memcmp(after, now, sizeof(int32_t) * 3 * (size_t)f) == 0);
  /* Origins: old vertices with barycentric weights. */
  int32_t* ov = (int32_t*)malloc(sizeof(int32_t) * (3 * (size_t)c.new_vertices + 1));
  float* ow = (float*)malloc(sizeof(float) * (3 * (size_t)c.new_vertices + 1));
  CHECK_OK(cgamesh_change_origins(change, 0, ov, ow, 3 * (size_t)c.new_vertices));
  int bad = 0;
  for (int32_t i = 0; i < c.new_vertices; ++i) {
    const float sum = ow[3 * i] + ow[3 * i + 1] + ow[3 * i + 2];
    bad += fabsf(sum - 1) > 1e-5f || ov[3 * i] < 0 || ov[3 * i] >= vertices_before;
  }
  CHECK(bad == 0);
  free(ov);
  free(ow);
  free(after);
  free(moved);
  free(ids);
  free(corners);
  free(now);
}

static void run_surgery(const char* cli_args, int kind) {
  cgamesh_model* m = load();
  cgamesh_live* live = NULL;
  CHECK_OK(cgamesh_live_create(m, NULL, &live));
  int32_t v = 0, f = 0;
  CHECK_OK(cgamesh_live_mesh_size(live, 0, &v, &f));
  int32_t* faces = (int32_t*)malloc(sizeof(int32_t) * 3 * (size_t)f);
  CHECK_OK(cgamesh_live_mesh_faces(live, 0, faces, 3 * (size_t)f));
  cgamesh_change* change = NULL;
  if (kind == 0) {
    const double n[3] = {0, 1, 0};
    CHECK_OK(cgamesh_live_cut(live, n, 0.8, &change));
  } else if (kind == 1) {
    const double blades[12] = {0.5, 1.2, -0.06, 0, 1.2, -0.06, 0.5, 1.25, 0.06, 0, 1.25, 0.06};
    CHECK_OK(cgamesh_live_tear(live, blades, 2, 0, &change));
  } else {
    const double tip[3] = {-0.5, 1.2, 0}, base[3] = {0.5, 1.2, 0};
    CHECK_OK(cgamesh_live_drill(live, tip, base, 0.04, 0, &change));
  }
  CHECK(change != NULL);
  if (change != NULL) {
    check_incremental_update(live, change, faces, f, v);
    /* The counts the CLI reports for the same operation. */
    char* mine = NULL;
    CHECK_OK(cgamesh_change_json(change, &mine));
    const char* out = temp_path("surgery.json");
    const char* file = temp_path(kind == 0 ? "cut.glb" : "other.glb");
    char args[1024];
    snprintf(args, sizeof args, "%s '%s' %s -o '%s' --json", kind == 0 ? "cut" : kind == 1 ? "tear" : "drill",
             model_path(), cli_args, file);
    CHECK(run_cli(args, out) == 0);
    char* cli = read_file(out, NULL);
    CHECK(cli != NULL && mine != NULL);
    if (cli != NULL && mine != NULL) {
      const char* keys[] = {"intersection_points", "faces_in", "faces_split", "faces_removed", "new_vertices", "rims"};
      for (size_t k = 0; k < sizeof keys / sizeof *keys; ++k) {
        if (kind == 0 && strcmp(keys[k], "new_vertices") == 0) continue; /* two pieces there, one mesh here */
        if (json_int(cli, keys[k]) != json_int(mine, keys[k])) {
          fprintf(stderr, "%s: CLI %ld, C %ld\n", keys[k], json_int(cli, keys[k]), json_int(mine, keys[k]));
          ++failures;
        }
      }
    }
    free(cli);
    cgamesh_string_free(mine);
    remove(out);
    remove(file);
  }
  /* The model as it is now animates and saves. */
  cgamesh_model* now = NULL;
  CHECK_OK(cgamesh_live_model(live, &now));
  cgamesh_pose* pose = NULL;
  CHECK_OK(cgamesh_pose_create(now, &pose));
  CHECK_OK(cgamesh_pose_sample(pose, now, 0, 1.0, CGAMESH_BLEND_FORMAT));
  CHECK_OK(cgamesh_live_mesh_size(live, 0, &v, NULL));
  float* p = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  float* q = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  CHECK_OK(cgamesh_model_skin(now, pose, 0, CGAMESH_SKINNING_CGA, p, 3 * (size_t)v, NULL, 0));
  CHECK_OK(cgamesh_live_skin(live, pose, 0, CGAMESH_SKINNING_CGA, q, 3 * (size_t)v, NULL, 0));
  CHECK(memcmp(p, q, sizeof(float) * 3 * (size_t)v) == 0);
  const char* saved = temp_path("live.glb");
  CHECK_OK(cgamesh_model_save(now, saved, NULL));
  cgamesh_model* back = NULL;
  CHECK_OK(cgamesh_model_load(saved, &back));
  remove(saved);
  free(p);
  free(q);
  free(faces);
  cgamesh_change_free(change);
  cgamesh_pose_free(pose);
  cgamesh_model_free(back);
  cgamesh_model_free(now);
  cgamesh_live_free(live);
  cgamesh_model_free(m);
}

static void test_cut_in_place(void) { run_surgery("--plane 0,1,0,0.8", 0); }
static void test_tear_in_place(void) {
  run_surgery("--scalpel 0.5,1.2,-0.06,0,1.2,-0.06 --scalpel 0.5,1.25,0.06,0,1.25,0.06", 1);
}
static void test_drill_in_place(void) { run_surgery("--tip -0.5,1.2,0 --base 0.5,1.2,0 --radius 0.04", 2); }

static void test_tools_that_miss_or_are_degenerate(void) {
  cgamesh_model* m = load();
  cgamesh_live* live = NULL;
  CHECK_OK(cgamesh_live_create(m, NULL, &live));
  cgamesh_change* change = (cgamesh_change*)0x1;
  const double n[3] = {0, 1, 0}, zero[3] = {0, 0, 0};
  CHECK_STATUS(cgamesh_live_cut(live, n, 100, &change), CGAMESH_ERROR_TOPOLOGY);
  CHECK(change == (cgamesh_change*)0x1);
  CHECK_STATUS(cgamesh_live_cut(live, zero, 0, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  const double away[12] = {5, 5, 5, 5, 5, 6, 6, 5, 5, 6, 5, 6};
  CHECK_STATUS(cgamesh_live_tear(live, away, 2, 0, &change), CGAMESH_ERROR_TOPOLOGY);
  CHECK_STATUS(cgamesh_live_tear(live, away, 1, 0, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_tear(live, away, 2, -1, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  const double tip[3] = {-0.5, 1.2, 0}, base[3] = {0.5, 1.2, 0};
  CHECK_STATUS(cgamesh_live_drill(live, tip, base, -1, 0, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_live_drill(live, tip, tip, 0.05, 0, &change), CGAMESH_ERROR_INVALID_ARGUMENT);
  /* Nothing changed: the mesh is as loaded. */
  int32_t v = 0, f = 0;
  CHECK_OK(cgamesh_live_mesh_size(live, 0, &v, &f));
  CHECK(v == 3273 && f == 4672);
  /* A null change pointer is allowed: the operation runs all the same. */
  CHECK_OK(cgamesh_live_cut(live, n, 0.8, NULL));
  CHECK_OK(cgamesh_live_mesh_size(live, 0, &v, &f));
  CHECK(f > 4672);
  cgamesh_live_free(live);
  cgamesh_model_free(m);
}

static void test_living_tissue(void) {
  cgamesh_model* m = load();
  cgamesh_pose* pose = NULL;
  CHECK_OK(cgamesh_pose_create(m, &pose));
  cgamesh_live* live = NULL;
  CHECK_OK(cgamesh_live_create(m, pose, &live));
  CHECK_STATUS(cgamesh_live_step_tissue(live, pose, 0.01), CGAMESH_ERROR_INVALID_ARGUMENT);
  cgamesh_tissue_options o;
  CHECK_OK(cgamesh_tissue_options_default(&o));
  CHECK(o.substep > 0 && o.max_particles == 2000 && o.gravity[1] < 0);
  cgamesh_tissue_options bad = o;
  bad.density = -1;
  CHECK_STATUS(cgamesh_live_set_tissue(live, &bad), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(cgamesh_last_error(), "density") != NULL);
  bad = o;
  bad.substep = 0;
  CHECK_STATUS(cgamesh_live_set_tissue(live, &bad), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_OK(cgamesh_live_set_tissue(live, &o));
  const double blades[12] = {0.5, 1.2, -0.06, 0, 1.2, -0.06, 0.5, 1.25, 0.06, 0, 1.25, 0.06};
  CHECK_OK(cgamesh_live_tear(live, blades, 2, 0, NULL));
  for (int frame = 0; frame < 30; ++frame) CHECK_OK(cgamesh_live_step_tissue(live, pose, 1.0 / 90));
  CHECK_STATUS(cgamesh_live_step_tissue(live, pose, -1), CGAMESH_ERROR_INVALID_ARGUMENT);
  int32_t v = 0;
  CHECK_OK(cgamesh_live_mesh_size(live, 0, &v, NULL));
  float* soft = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  float* skinned = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  CHECK_OK(cgamesh_live_skin(live, pose, 0, CGAMESH_SKINNING_CGA, soft, 3 * (size_t)v, NULL, 0));
  cgamesh_model* now = NULL;
  CHECK_OK(cgamesh_live_model(live, &now));
  CHECK_OK(cgamesh_model_skin(now, pose, 0, CGAMESH_SKINNING_CGA, skinned, 3 * (size_t)v, NULL, 0));
  /* The wound moved (it gapes); the far parts of the body did not, to the bit. */
  int moved = 0, far_moved = 0;
  for (int32_t i = 0; i < v; ++i) {
    const int differs = memcmp(soft + 3 * i, skinned + 3 * i, 3 * sizeof(float)) != 0;
    moved += differs;
    far_moved += differs && skinned[3 * i + 1] < 0.6f;
  }
  CHECK(moved > 10);
  CHECK(far_moved == 0);
  /* Baked, the model skins to the simulated surface. */
  CHECK_OK(cgamesh_live_bake_tissue(live, pose));
  cgamesh_model* baked = NULL;
  CHECK_OK(cgamesh_live_model(live, &baked));
  CHECK_OK(cgamesh_model_skin(baked, pose, 0, CGAMESH_SKINNING_CGA, skinned, 3 * (size_t)v, NULL, 0));
  double worst = 0;
  for (size_t i = 0; i < 3 * (size_t)v; ++i) worst = fabs(soft[i] - skinned[i]) > worst ? fabs(soft[i] - skinned[i]) : worst;
  CHECK(worst < 1e-4);
  CHECK_OK(cgamesh_live_clear_tissue(live));
  CHECK_STATUS(cgamesh_live_bake_tissue(live, pose), CGAMESH_ERROR_INVALID_ARGUMENT);
  free(soft);
  free(skinned);
  cgamesh_model_free(now);
  cgamesh_model_free(baked);
  cgamesh_live_free(live);
  cgamesh_pose_free(pose);
  cgamesh_model_free(m);
}

static void test_deform_by_spec(void) {
  cgamesh_model* m = load();
  size_t size = 0;
  char* spec = read_file(CGAMESH_DATA_DIR "/specs/cesiumman_bend.json", &size);
  CHECK(spec != NULL);
  cgamesh_model* bent = NULL;
  CHECK_OK(cgamesh_model_deform(m, spec, &bent));
  const int v = mesh_vertices(m);
  float* a = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  float* b = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  CHECK_OK(cgamesh_model_skin(m, NULL, 0, CGAMESH_SKINNING_CGA, a, 3 * (size_t)v, NULL, 0));
  CHECK_OK(cgamesh_model_skin(bent, NULL, 0, CGAMESH_SKINNING_CGA, b, 3 * (size_t)v, NULL, 0));
  /* The CLI's deform of the same spec, as an OBJ in the bind pose: the same surface. */
  const char* obj = temp_path("bent.obj");
  const char* cli = temp_path("cli_bent.obj");
  const char* log = temp_path("deform.log");
  CHECK_OK(cgamesh_model_save(bent, obj, NULL));
  char args[1024];
  snprintf(args, sizeof args, "deform '%s' --spec '%s' -o '%s'", model_path(), CGAMESH_DATA_DIR "/specs/cesiumman_bend.json",
           cli);
  CHECK(run_cli(args, log) == 0);
  size_t x = 0, y = 0;
  char* mine = read_file(obj, &x);
  char* theirs = read_file(cli, &y);
  CHECK(mine != NULL && theirs != NULL);
  float* from_c = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  float* from_cli = (float*)malloc(sizeof(float) * 3 * (size_t)v);
  CHECK(mine != NULL && obj_vertices(mine, from_c, v) == v);
  CHECK(theirs != NULL && obj_vertices(theirs, from_cli, v) == v);
  double gap = 0;
  for (size_t i = 0; i < 3 * (size_t)v; ++i) gap = fabs(from_c[i] - from_cli[i]) > gap ? fabs(from_c[i] - from_cli[i]) : gap;
  CHECK(gap < 1e-5); /* CesiumMan is 1.6 units tall */
  free(from_c);
  free(from_cli);
  /* Bent: the head moved; the feet (held by the first handle) did not. */
  double head = 0;
  for (int i = 0; i < v; ++i)
    if (a[3 * i + 1] > 1.4f) head = fabs(b[3 * i] - a[3 * i]) > head ? fabs(b[3 * i] - a[3 * i]) : head;
  CHECK(head > 0.1);
  free(mine);
  free(theirs);
  remove(obj);
  remove(cli);
  remove(log);
  CHECK_STATUS(cgamesh_model_deform(m, "{\"method\": \"nonsense\"}", &bent), CGAMESH_ERROR_INVALID_ARGUMENT);
  CHECK_STATUS(cgamesh_model_deform(m, "not json", &bent), CGAMESH_ERROR_INVALID_ARGUMENT);
  free(spec);
  free(a);
  free(b);
  cgamesh_model_free(bent);
  cgamesh_model_free(m);
}

typedef struct {
  const char* name;
  void (*run)(void);
} test_case;

static const test_case tests[] = {
    {"version_and_status", test_version_and_status},
    {"load_and_inspect", test_load_and_inspect},
    {"bad_files_and_null_handles", test_bad_files_and_null_handles},
    {"pose_and_skin_equal_the_cli", test_pose_and_skin_equal_the_cli},
    {"save_equals_the_cli", test_save_equals_the_cli},
    {"cut_in_place", test_cut_in_place},
    {"tear_in_place", test_tear_in_place},
    {"drill_in_place", test_drill_in_place},
    {"tools_that_miss_or_are_degenerate", test_tools_that_miss_or_are_degenerate},
    {"living_tissue", test_living_tissue},
    {"deform_by_spec", test_deform_by_spec},
};

int main(int argc, char** argv) {
  int ran = 0;
  for (size_t i = 0; i < sizeof tests / sizeof *tests; ++i)
    if (argc < 2 || strcmp(argv[1], tests[i].name) == 0) {
      tests[i].run();
      ++ran;
    }
  if (ran == 0) {
    fprintf(stderr, "no test named %s\n", argv[1]);
    return 2;
  }
  if (failures > 0) fprintf(stderr, "%d checks failed\n", failures);
  return failures > 0 ? 1 : 0;
}
