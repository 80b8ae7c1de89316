// The `cgamesh` command-line tool, run as a process: JSON summaries, posed geometry in every
// skinning mode, edits, conversion and keyframe generation, and bad input (exit codes, a
// message on stderr, and no output file or temporary file left behind).

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/text_values.hpp"

#include "anim/model_fixtures.hpp"
#include "apps/cli_util.hpp"
#include "support/gltf_edit.hpp"
#include "support/js_oracles.hpp"

namespace {

using namespace cgamesh_cli_test;
using Json = nlohmann::json;

const fs::path kFbx = cgamesh_test::assimp_model("FBX/animation_with_skeleton.fbx");
const fs::path kX = cgamesh_test::assimp_model("X/BCN_Epileptic.X");

fs::path cesium() { return cgamesh_test::demo_model(); }

/// The joint of CesiumMan that the most vertices hang from, found once.
std::string busiest_joint() {
  static const std::string name = cgamesh_test::busiest_joint(cesium());
  return name;
}

/// `pose` into dir/NAME, returning its vertices.
Points pose_obj(const TempDir& dir, const fs::path& model, const std::string& name, std::vector<std::string> extra) {
  std::vector<std::string> args{"pose", model.string(), "-o", (dir / name).string()};
  args.insert(args.end(), extra.begin(), extra.end());
  run_ok(dir, args);
  EXPECT_TRUE(fs::exists(dir / name)) << name;
  std::string ext = fs::path(name).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".ply" ? read_ply_vertices(dir / name) : read_obj_vertices(dir / name);
}

// ---- info -------------------------------------------------------------------------------------

TEST(CliInfo, JsonSummaryOfCesiumMan) {
  TempDir dir;
  const Result r = run_ok(dir, {"info", cesium().string(), "--json"});
  const Json j = parse_json(r);
  ASSERT_TRUE(j.is_object()) << r;
  ASSERT_TRUE(j["meshes"].is_array());
  ASSERT_EQ(j["meshes"].size(), 1u);
  EXPECT_EQ(j["meshes"][0]["vertices"], 3273);
  EXPECT_EQ(j["meshes"][0]["triangles"], 4672);
  EXPECT_EQ(j["meshes"][0]["skinned"], true);
  EXPECT_EQ(j["vertices"], 3273);
  EXPECT_EQ(j["triangles"], 4672);
  ASSERT_TRUE(j["nodes"].is_number_integer());
  EXPECT_GE(j["nodes"].get<int>(), 19);  // the skin's 19 joints and the nodes above them
  EXPECT_EQ(j["skinned_joints"], 19);
  ASSERT_TRUE(j["animations"].is_array());
  ASSERT_EQ(j["animations"].size(), 1u);
  EXPECT_TRUE(j["animations"][0]["name"].is_string());
  EXPECT_NEAR(j["animations"][0]["duration"].get<double>(), 2.0, 1e-6);
  EXPECT_EQ(j["max_influences"], 4);
  const Json& box = j["bounding_box"];
  ASSERT_TRUE(box["min"].is_array() && box["max"].is_array());
  ASSERT_EQ(box["min"].size(), 3u);
  ASSERT_EQ(box["max"].size(), 3u);
  // CesiumMan stands 1.5 m tall along +y (the glTF up axis), feet at 0.
  EXPECT_NEAR(box["min"][1].get<double>(), 0.0, 1e-3);
  EXPECT_NEAR(box["max"][1].get<double>(), 1.5065, 1e-3);
  for (int c = 0; c < 3; ++c) EXPECT_LT(box["min"][c].get<double>(), box["max"][c].get<double>());
  ASSERT_TRUE(j["warnings"].is_array());
  EXPECT_TRUE(j["warnings"].empty()) << j["warnings"].dump();
}

TEST(CliInfo, JsonWarningsOfTheFbx) {
  if (!fs::exists(kFbx)) GTEST_SKIP() << kFbx << " is not installed (assimp-testmodels)";
  TempDir dir;
  const Json j = parse_json(run_ok(dir, {"info", kFbx.string(), "--json"}));
  EXPECT_EQ(j["max_influences"], 6);
  bool scale = false, influences = false;
  for (const Json& w : j["warnings"]) {
    scale |= contains(w.get<std::string>(), "non-uniform scale");
    influences |= contains(w.get<std::string>(), "more than 4 influences");
  }
  EXPECT_TRUE(scale) << j["warnings"].dump(2);
  EXPECT_TRUE(influences) << j["warnings"].dump(2);
}

// Every command that loads a model says what the loader approximated: on stderr, and in --json.
TEST(CliWarnings, EveryCommandReportsTheLoadersWarnings) {
  if (!fs::exists(kFbx)) GTEST_SKIP() << kFbx << " is not installed (assimp-testmodels)";
  TempDir dir;
  const std::string joint(cgamesh::io::load_model(kFbx).skeleton.names()[0]);
  const auto has_scale = [](const Json& warnings) {
    return std::any_of(warnings.begin(), warnings.end(),
                       [](const Json& w) { return contains(w.get<std::string>(), "non-uniform scale"); });
  };
  const std::vector<std::vector<std::string>> commands{
      {"pose", kFbx.string(), "--time", "0.4", "-o", (dir.path() / "p.obj").string(), "--json"},
      {"convert", kFbx.string(), "-o", (dir.path() / "c.glb").string(), "--json"},
      {"animate", kFbx.string(), "--key", "0:" + joint + ":scale=1", "--key", "1:" + joint + ":scale=2", "-o",
       (dir.path() / "a.glb").string(), "--json"}};
  for (const auto& args : commands) {
    SCOPED_TRACE(args[0]);
    const Result r = run_cli(args, dir.path());
    ASSERT_EQ(r.code, 0) << r;
    EXPECT_TRUE(contains(r.err, "cgamesh: warning: " + kFbx.string() + ": ")) << r;
    EXPECT_TRUE(has_scale(parse_json(r)["warnings"])) << r;
  }
}

// ---- pose -------------------------------------------------------------------------------------

TEST(CliPose, CgaAndMatrixSkinningWriteTheSameVertices) {
  TempDir dir;
  const Points cga = pose_obj(dir, cesium(), "cga.obj", {"--time", "0.5", "--skinning", "cga"});
  const Points matrix = pose_obj(dir, cesium(), "matrix.obj", {"--time", "0.5", "--skinning", "matrix"});
  ASSERT_EQ(cga.rows(), 3273);
  ASSERT_EQ(matrix.rows(), 3273);
  EXPECT_LE(max_distance(cga, matrix), 1e-5 * diagonal(matrix));
  // The other two modes differ from linear blend skinning only where joints bend.
  const Points versor = pose_obj(dir, cesium(), "versor.obj", {"--time", "0.5", "--skinning", "versor"});
  const Points dqs = pose_obj(dir, cesium(), "dqs.obj", {"--time", "0.5", "--skinning", "DQS"});
  EXPECT_LE(max_distance(versor, dqs), 1e-5 * diagonal(matrix));
  EXPECT_LE(max_distance(versor, matrix), 0.05 * diagonal(matrix));
  EXPECT_GT(max_distance(versor, matrix), 1e-3 * diagonal(matrix));  // --skinning is not ignored
}

TEST(CliPose, BindPoseDiffersFromTheAnimation) {
  TempDir dir;
  const Points animated = pose_obj(dir, cesium(), "t.obj", {"--time", "0.5"});
  const Points bind = pose_obj(dir, cesium(), "bind.obj", {"--bind-pose"});
  ASSERT_EQ(bind.rows(), animated.rows());
  EXPECT_GT(max_distance(bind, animated), 1e-2 * diagonal(bind));
  // The bind pose is the box `info` reports.
  const Json info = parse_json(run_ok(dir, {"info", cesium().string(), "--json"}));
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(bind.col(c).minCoeff(), info["bounding_box"]["min"][c].get<double>(), 1e-6);
    EXPECT_NEAR(bind.col(c).maxCoeff(), info["bounding_box"]["max"][c].get<double>(), 1e-6);
  }
}

TEST(CliPose, PlyHoldsTheSameVerticesAsObj) {
  TempDir dir;
  const Points obj = pose_obj(dir, cesium(), "p.obj", {"--time", "0.5"});
  const Points ply = pose_obj(dir, cesium(), "p.PLY", {"--time", "0.5"});
  ASSERT_EQ(ply.rows(), obj.rows());
  EXPECT_LE(max_distance(obj, ply), 1e-6 * diagonal(obj));  // OBJ prints 9 digits: exact floats
}

TEST(CliPose, EditsChangeTheOutput) {
  TempDir dir;
  const std::string j = busiest_joint();
  const Points plain = pose_obj(dir, cesium(), "plain.obj", {"--time", "0.5"});
  const double diag = diagonal(plain);
  const Points rotated = pose_obj(dir, cesium(), "r.obj", {"--time", "0.5", "--set", j + ":rotate=0,0,1,30"});
  const Points moved = pose_obj(dir, cesium(), "t.obj", {"--time", "0.5", "--set", j + ":translate=0.1,0,0"});
  const Points scaled = pose_obj(dir, cesium(), "s.obj", {"--time", "0.5", "--set", j + ":scale=2"});
  const Points both = pose_obj(dir, cesium(), "b.obj",
                               {"--time", "0.5", "--set", j + ":rotate=0,0,1,30", "--set", j + ":translate=0.1,0,0"});
  for (const Points* p : {&rotated, &moved, &scaled, &both}) {
    ASSERT_EQ(p->rows(), plain.rows());
    EXPECT_GT(max_distance(*p, plain), 1e-2 * diag);
  }
  EXPECT_GT(max_distance(both, rotated), 1e-2 * diag);
  EXPECT_GT(max_distance(both, moved), 1e-2 * diag);
  // An identity edit changes nothing.
  const Points identity = pose_obj(dir, cesium(), "i.obj", {"--time", "0.5", "--set", j + ":scale=1"});
  EXPECT_LE(max_distance(identity, plain), 1e-5 * diag);
}

TEST(CliPose, EveryBlendModeRuns) {
  TempDir dir;
  std::vector<Points> out;
  for (const char* blend : {"format", "linear", "log"}) {
    out.push_back(pose_obj(dir, cesium(), std::string(blend) + ".obj", {"--time", "0.77", "--blend", blend}));
    ASSERT_EQ(out.back().rows(), 3273) << blend;
  }
  // CesiumMan's keys are dense: the three blends of its clip agree closely.
  const double diag = diagonal(out[0]);
  EXPECT_LE(max_distance(out[0], out[1]), 1e-3 * diag);
  EXPECT_LE(max_distance(out[0], out[2]), 1e-3 * diag);

  // Two keys far apart (a 90 degree turn and a scale by 3 in one second) tell them apart: slerp
  // and a linear scale (format), nlerp of the versors (linear), slerp and a geometric scale (log).
  const std::string j = busiest_joint();
  const fs::path two_keys = dir / "two_keys.glb";
  run_ok(dir, {"animate", cesium().string(), "-o", two_keys.string(), "--key", "0:" + j + ":scale=1", "--key",
               "1:" + j + ":rotate=0,0,1,90", "--key", "1:" + j + ":scale=3", "--fps", "1"});
  std::vector<Points> mid;
  for (const char* blend : {"format", "linear", "log"})
    mid.push_back(pose_obj(dir, two_keys, std::string("mid_") + blend + ".obj",
                           {"--anim", "generated", "--time", "0.3", "--blend", blend}));
  EXPECT_GT(max_distance(mid[0], mid[1]), 1e-3 * diag);
  EXPECT_GT(max_distance(mid[0], mid[2]), 1e-3 * diag);
  EXPECT_GT(max_distance(mid[1], mid[2]), 1e-3 * diag);
}

TEST(CliPose, StaticGltfFrameHoldsThePosedVertices) {
  TempDir dir;
  const Points obj = pose_obj(dir, cesium(), "frame.obj", {"--time", "0.5"});
  for (const char* frame : {"frame.glb", "frame.gltf"}) {
    SCOPED_TRACE(frame);
    run_ok(dir, {"pose", cesium().string(), "-o", (dir / frame).string(), "--time", "0.5"});
    const Json info = parse_json(run_ok(dir, {"info", (dir / frame).string(), "--json"}));
    EXPECT_TRUE(info["animations"].empty()) << info.dump(2);
    EXPECT_EQ(info["meshes"][0]["skinned"], false);
    // Static: its bind pose is the posed frame.
    const Points again = pose_obj(dir, dir / frame, std::string(frame) + ".obj", {"--bind-pose"});
    ASSERT_EQ(again.rows(), obj.rows());
    EXPECT_LE(max_distance(again, obj), 1e-6 * diagonal(obj));
  }
  EXPECT_TRUE(fs::exists(dir / "frame.bin"));
}

TEST(CliPose, WritesSkinnedNormalsInEveryFormat) {
  // The normals of io::posed_frame for the same pose (--time alone: the first clip, format blend,
  // cga skinning): OBJ vn lines with v/vt/vn corners, PLY nx ny nz, a glTF NORMAL attribute.
  namespace cg = cgamesh;
  TempDir dir;
  const cg::anim::RiggedModel model = cg::io::load_model(cesium());
  const cg::io::PosedFrame frame =
      cg::io::posed_frame(model, cg::anim::sample(model.skeleton, model.clips.at(0), 0.5, cg::anim::BlendMode::format),
                          cg::anim::SkinningMode::cga);
  const cg::mesh::RowMatrixXf<3>& expected = frame.normals.at(0);
  ASSERT_EQ(expected.rows(), model.meshes.at(0).vertex_count());

  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "p.obj").string(), "--time", "0.5"});
  std::ifstream obj(dir / "p.obj");
  std::vector<Eigen::Vector3f> vn;
  long v = 0, faces = 0;
  for (std::string line; std::getline(obj, line);) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v") ++v;
    if (tag == "vn") {
      Eigen::Vector3f n;
      s >> n.x() >> n.y() >> n.z();
      vn.push_back(n);
    }
    if (tag != "f") continue;
    ++faces;
    for (std::string corner; s >> corner;) {
      const std::size_t a = corner.find('/'), b = corner.rfind('/');
      ASSERT_TRUE(a != std::string::npos && b > a + 1) << "not v/vt/vn: " << line;
      EXPECT_EQ(corner.substr(b + 1), corner.substr(0, a)) << line;  // one mesh: vn index = v index
    }
  }
  EXPECT_EQ(faces, model.meshes[0].face_count());
  ASSERT_EQ(static_cast<long>(vn.size()), v);
  ASSERT_EQ(v, expected.rows());
  for (std::size_t i = 0; i < vn.size(); ++i)
    ASSERT_LT((vn[i] - expected.row(static_cast<Eigen::Index>(i)).transpose()).norm(), 1e-6f) << "vn " << i;

  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "p.ply").string(), "--time", "0.5"});
  EXPECT_NE(
      read_file(dir / "p.ply").find("property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"),
      std::string::npos);
  EXPECT_EQ(read_ply_vertices(dir / "p.ply").rows(), expected.rows());

  for (const char* name : {"p.glb", "p.gltf"}) {
    SCOPED_TRACE(name);
    run_ok(dir, {"pose", cesium().string(), "-o", (dir / name).string(), "--time", "0.5"});
    const cg::anim::RiggedModel again = cg::io::load_model(dir / name);
    ASSERT_EQ(again.meshes.size(), 1u);
    const cg::mesh::RowMatrixXf<3>& n = again.meshes[0].normals;
    ASSERT_EQ(n.rows(), expected.rows()) << "no NORMAL attribute";
    EXPECT_LT((n.rowwise().norm().array() - 1).abs().maxCoeff(), 1e-5f);
    EXPECT_LT((n - expected).rowwise().norm().maxCoeff(), 1e-5f);
    if (cgamesh_test::validator_available()) {
      std::string log;
      EXPECT_EQ(cgamesh_test::validate_gltf(dir / name, log), 0) << log;
    }
  }
}

// ---- convert ----------------------------------------------------------------------------------

TEST(CliConvert, ConvertedModelPosesLikeTheInput) {
  std::vector<fs::path> models{cesium()};
  if (fs::exists(kX)) models.push_back(kX);
  for (const fs::path& model : models) {
    SCOPED_TRACE(model.string());
    TempDir dir;
    run_ok(dir, {"convert", model.string(), "-o", (dir / "out.glb").string()});
    ASSERT_TRUE(fs::exists(dir / "out.glb"));
    const Points original = pose_obj(dir, model, "original.obj", {"--time", "0.3"});
    const Points converted = pose_obj(dir, dir / "out.glb", "converted.obj", {"--time", "0.3"});
    ASSERT_GT(original.rows(), 0);
    ASSERT_EQ(converted.rows(), original.rows());
    EXPECT_LE(max_distance(original, converted), 1e-5 * diagonal(original));
    // And the time matters (the clip came along).
    const Points later = pose_obj(dir, dir / "out.glb", "later.obj", {"--time", "0.9"});
    EXPECT_GT(max_distance(later, converted), 1e-3 * diagonal(original));
  }
}

// ---- animate ----------------------------------------------------------------------------------

TEST(CliAnimate, GeneratedClipIsWrittenAndValid) {
  TempDir dir;
  const std::string j = busiest_joint();
  const fs::path out = dir / "out.glb";
  run_ok(dir, {"animate", cesium().string(), "-o", out.string(), "--key", "0:" + j + ":rotate=1,0,0,0", "--key",
               "1:" + j + ":rotate=1,0,0,60", "--blend", "linear", "--fps", "10"});
  ASSERT_TRUE(fs::exists(out));
  const Json info = parse_json(run_ok(dir, {"info", out.string(), "--json"}));
  ASSERT_EQ(info["animations"].size(), 2u) << info.dump(2);
  EXPECT_EQ(info["animations"][1]["name"], "generated");
  EXPECT_NEAR(info["animations"][1]["duration"].get<double>(), 1.0, 1e-6);
  EXPECT_NEAR(info["animations"][0]["duration"].get<double>(), 2.0, 1e-6);  // the original clip stays
  EXPECT_EQ(info["vertices"], 3273);

  // The new clip moves the mesh: at 1 s the joint is bent by 60 degrees, at 0 s not at all.
  const Points start = pose_obj(dir, out, "start.obj", {"--anim", "generated", "--time", "0"});
  const Points end = pose_obj(dir, out, "end.obj", {"--anim", "1", "--time", "1"});
  const Points bind = pose_obj(dir, cesium(), "bind.obj", {"--bind-pose"});
  EXPECT_LE(max_distance(start, bind), 1e-5 * diagonal(bind));
  EXPECT_GT(max_distance(end, bind), 1e-2 * diagonal(bind));

  if (!cgamesh_test::validator_available())
    GTEST_SKIP() << "node or tests/oracle/js/node_modules is missing (npm ci there)";
  std::string text;
  const int status = cgamesh_test::validate_gltf(out, text);
  EXPECT_EQ(status, 0) << text;
  EXPECT_TRUE(contains(text, " 0 error(s)")) << text;
}

// ---- bad input ----------------------------------------------------------------------------------

TEST(CliErrors, TruncatedGlbIsBadInput) {
  Failure f;
  const std::string bytes = read_file(cesium()).substr(0, 3000);
  { std::ofstream(f.inputs / "truncated.glb", std::ios::binary) << bytes; }
  for (const char* cmd : {"info", "pose", "convert"}) {
    SCOPED_TRACE(cmd);
    const fs::path out = f.outputs / (std::string(cmd) == "pose" ? "out.obj" : "out.glb");
    std::vector<std::string> args{cmd, (f.inputs / "truncated.glb").string()};
    if (std::string(cmd) != "info") args.insert(args.end(), {"-o", out.string()});
    expect_failure(f, args, 3, "'" + (f.inputs / "truncated.glb").string() + "': not a valid .glb file", out);
  }
}

// Files on which Assimp's readers loop forever or allocate without bound are refused before
// reading, and any reading that runs too long ends with exit 3.
TEST(CliErrors, HangingOrOverdeclaredFilesAreBadInputAndLoadingHasATimeBudget) {
  Failure f;
  { std::ofstream(f.inputs / "t.smd") << "version 1\nnodes\n"; }
  expect_failure(f, {"info", (f.inputs / "t.smd").string()}, 3, "section 'nodes' (line 2) has no 'end' line",
                 f.outputs / "none");
  {
    std::ofstream(f.inputs / "big.ply")
        << "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n0\n";
  }
  expect_failure(f, {"info", (f.inputs / "big.ply").string()}, 3, "declares 4000000000 'vertex' elements",
                 f.outputs / "none");
  {
    std::ofstream(f.inputs / "open.md5mesh")
        << "MD5Version 10\nnumJoints 1\njoints {\n\"root\" -1 ( 0 0 0 ) ( 0 0 0 )\n";
  }
  expect_failure(f, {"info", (f.inputs / "open.md5mesh").string()}, 3, "never closes", f.outputs / "none");
  // OFF counts, on the keyword's line or the next (assimp-testmodels' invalid/OutOfMemory.off
  // took minutes before); a true header, after a comment, loads.
  { std::ofstream(f.inputs / "big.off") << "OFF\n# a comment\n353535235358 6 0\n-0.5 -0.5 0.5\n"; }
  expect_failure(f, {"info", (f.inputs / "big.off").string()}, 3, "line 3 declares 353535235358 vertices",
                 f.outputs / "none");
  { std::ofstream(f.inputs / "faces.off") << "COFF 3 99999 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"; }
  expect_failure(f, {"info", (f.inputs / "faces.off").string()}, 3, "line 1 declares 99999 faces", f.outputs / "none");
  { std::ofstream(f.inputs / "true.off") << "OFF\n# a comment\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"; }
  EXPECT_EQ(run_cli({"info", (f.inputs / "true.off").string()}, f.inputs.path()).code, 0);
  const fs::path out = f.outputs / "out.glb";
  expect_failure(f, {"--load-timeout", "0.000001", "convert", cesium().string(), "-o", out.string()}, 3,
                 "took longer than", out);
  expect_failure(f, {"info", cesium().string(), "--load-timeout", "0.000001"}, 3, "allow more with --load-timeout",
                 out);
  expect_failure(f, {"info", cesium().string(), "--load-timeout", "-1"}, 2, "load-timeout", out);
}

// Issue #33 item 7: messages a person can read, and exit 3 for a file no command can use.
TEST(CliErrors, RefusedFilesAreNamedInAFewLines) {
  Failure f;
  const fs::path out = f.outputs / "out.glb";
  const Result x = run_cli({"info", cgamesh_test::asset("testentities_cool_guy.x").string()}, f.inputs.path());
  EXPECT_EQ(x.code, 3) << x;
  EXPECT_LT(x.err.size(), 600u) << x.err.size();  // was 34 kB: Assimp quotes the rest of the file
  expect_failure(f, {"convert", cgamesh_test::asset("pirate_meshopt.glb").string(), "-o", out.string()}, 3,
                 "requires glTF extensions that cgamesh cannot read: KHR_mesh_quantization, EXT_meshopt_compression",
                 out);
  // Fewer inverse bind matrices than joints: refused by every command, naming the skin.
  tinygltf::Model m = cgamesh_test::read_glb(cgamesh_test::asset("RiggedSimple.glb"));
  m.accessors[static_cast<std::size_t>(m.skins[0].inverseBindMatrices)].count -= 1;
  const fs::path bad = cgamesh_test::write_glb(std::move(m), f.inputs / "short_ibm.glb");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"info", bad.string()},
        {"convert", bad.string(), "-o", out.string()},
        {"pose", bad.string(), "-o", out.string()},
        {"cut", bad.string(), "--plane", "0,0,1,0", "-o", out.string(), (f.outputs / "b.glb").string()}})
    expect_failure(f, args, 3, "skin 0 'Armature' has 2 joints but its inverseBindMatrices accessor holds 1", out);
}

TEST(CliErrors, TextFileNamedGlbIsBadInput) {
  Failure f;
  { std::ofstream(f.inputs / "x.glb") << "this is a text file, not a model\n"; }
  const fs::path out = f.outputs / "out.obj";
  expect_failure(f, {"pose", (f.inputs / "x.glb").string(), "-o", out.string()}, 3,
                 "'" + (f.inputs / "x.glb").string() + "': not a valid .glb file", out);
}

TEST(CliErrors, MissingFileIsBadInput) {
  Failure f;
  const fs::path out = f.outputs / "out.glb";
  expect_failure(f, {"convert", (f.inputs / "missing.glb").string(), "-o", out.string()}, 3, "no such file", out);
  expect_failure(f, {"info", (f.inputs / "missing.glb").string()}, 3, "missing.glb': no such file", out);
}

TEST(CliErrors, UnknownJointIsABadArgument) {
  Failure f;
  const fs::path out = f.outputs / "out.obj";
  expect_failure(f, {"pose", cesium().string(), "-o", out.string(), "--set", "no_such_joint:scale=2"}, 2,
                 "unknown joint 'no_such_joint'", out);
  const fs::path glb = f.outputs / "out.glb";
  expect_failure(f,
                 {"animate", cesium().string(), "-o", glb.string(), "--key", "0:no_such_joint:rotate=1,0,0,0", "--key",
                  "1:no_such_joint:rotate=1,0,0,60"},
                 2, "unknown joint 'no_such_joint'", glb);
}

TEST(CliErrors, NegativeScaleIsABadArgument) {
  Failure f;
  const fs::path out = f.outputs / "out.obj";
  expect_failure(f, {"pose", cesium().string(), "-o", out.string(), "--set", busiest_joint() + ":scale=-2"}, 2, "scale",
                 out);
}

TEST(CliErrors, BadVectorIsABadArgument) {
  Failure f;
  const fs::path out = f.outputs / "out.obj";
  expect_failure(f, {"pose", cesium().string(), "-o", out.string(), "--set", busiest_joint() + ":rotate=1,2"}, 2,
                 "rotate", out);
  expect_failure(f, {"pose", cesium().string(), "-o", out.string(), "--set", busiest_joint() + ":translate=1,x,2"}, 2,
                 "'x' is not a number", out);
}

TEST(CliErrors, UnknownSkinningModeIsABadArgument) {
  Failure f;
  const fs::path out = f.outputs / "out.obj";
  expect_failure(f, {"pose", cesium().string(), "-o", out.string(), "--skinning", "bogus"}, 2, "bogus", out);
}

TEST(CliErrors, UnwritableOutputLeavesNothing) {
  Failure f;
  if (!fs::exists("/nonexistent")) {
    const Result r = run_cli({"pose", cesium().string(), "-o", "/nonexistent/dir/out.obj"}, f.inputs.path());
    EXPECT_NE(r.code, 0) << r;
    EXPECT_TRUE(contains(r.err, "/nonexistent/dir")) << r;
    EXPECT_FALSE(fs::exists("/nonexistent")) << r;
  }
  // A missing directory inside the output directory: nothing appears there either.
  for (const char* name : {"out.obj", "out.ply", "out.glb", "out.gltf"}) {
    const fs::path out = f.outputs / "missing" / name;
    const bool mesh = fs::path(name).extension() == ".obj" || fs::path(name).extension() == ".ply";
    const Result r = run_cli({mesh ? "pose" : "convert", cesium().string(), "-o", out.string()}, f.inputs.path());
    EXPECT_NE(r.code, 0) << r;
    EXPECT_TRUE(contains(r.err, "cannot write")) << r;
    EXPECT_TRUE(f.outputs.entries().empty()) << r;
  }
  // The output path is a directory.
  fs::create_directory(f.outputs / "taken.obj");
  const Result r = run_cli({"pose", cesium().string(), "-o", (f.outputs / "taken.obj").string()}, f.inputs.path());
  EXPECT_NE(r.code, 0) << r;
  EXPECT_EQ(f.outputs.entries(), std::vector<std::string>{"taken.obj"}) << r;
  EXPECT_TRUE(fs::is_empty(f.outputs / "taken.obj"));
}

TEST(CliErrors, UnknownOutputExtensionIsABadArgument) {
  Failure f;
  const fs::path out = f.outputs / "out.xyz";
  expect_failure(f, {"pose", cesium().string(), "-o", out.string()}, 2, ".xyz", out);
  expect_failure(f, {"convert", cesium().string(), "-o", out.string()}, 2, ".xyz", out);
}

TEST(CliErrors, NoOutputIsOverwrittenOnFailure) {
  Failure f;
  const fs::path out = f.outputs / "out.obj";
  { std::ofstream(out) << "previous"; }
  const Result r =
      run_cli({"pose", cesium().string(), "-o", out.string(), "--set", "no_such_joint:scale=2"}, f.inputs.path());
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(read_file(out), "previous");
  EXPECT_EQ(f.outputs.entries(), std::vector<std::string>{"out.obj"});
}

// ---- algebra-demo -------------------------------------------------------------------------------

TEST(CliAlgebraDemo, JsonPointAndMatrixAgree) {
  TempDir dir;
  const Json j = parse_json(run_ok(dir, {"algebra-demo", "--json"}));
  const auto vec = [](const Json& v) {
    return Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  };
  ASSERT_TRUE(j.contains("point")) << j.dump(2);
  const Eigen::Vector3d cga = vec(j["point"]["cga"]), matrix = vec(j["point"]["matrix"]), in = vec(j["point"]["in"]);
  EXPECT_LE((cga - matrix).norm(), 1e-12);
  EXPECT_GT((cga - in).norm(), 0.1);  // the versor moved the point
  EXPECT_LE((vec(j["sphere"]["cga"]["center"]) - vec(j["sphere"]["matrix"]["center"])).norm(), 1e-12);
  EXPECT_NEAR(j["sphere"]["cga"]["radius"].get<double>(), j["sphere"]["matrix"]["radius"].get<double>(), 1e-12);
  EXPECT_LE((vec(j["plane"]["cga"]["normal"]) - vec(j["plane"]["matrix"]["normal"])).norm(), 1e-12);
  EXPECT_NEAR(j["plane"]["cga"]["distance"].get<double>(), j["plane"]["matrix"]["distance"].get<double>(), 1e-12);
  // Both blends start at the point and end where the versor takes it.
  const Json& path = j["blend"];
  ASSERT_GE(path.size(), 2u);
  for (const char* kind : {"linear", "log"}) {
    EXPECT_LE((vec(path.front()[kind]) - in).norm(), 1e-12) << kind;
    EXPECT_LE((vec(path.back()[kind]) - cga).norm(), 1e-9) << kind;
  }
  // A different versor on the command line changes the answer, and still agrees.
  const Json k = parse_json(run_ok(dir, {"algebra-demo", "--json", "--angle", "45", "--scale", "0.5"}));
  EXPECT_LE((vec(k["point"]["cga"]) - vec(k["point"]["matrix"])).norm(), 1e-12);
  EXPECT_GT((vec(k["point"]["cga"]) - cga).norm(), 0.1);
}

}  // namespace
