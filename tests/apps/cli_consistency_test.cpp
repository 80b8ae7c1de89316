// What every command shares (issue #15, items 8-10): one default pose (the bind pose) reported
// by every command, a rig `info` lets you discover, and an answer for every bad value (empty,
// overflowing, denormal, far from the model, an output over its input, non-UTF-8 names).

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skeleton.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "anim/model_fixtures.hpp"
#include "apps/cli_util.hpp"

namespace {

using namespace cgamesh_cli_test;
using Json = nlohmann::json;

fs::path cesium() { return cgamesh_test::demo_model(); }

/// The joint of CesiumMan that the most vertices hang from, found once.
std::string busy_joint() {
  static const std::string name = cgamesh_test::busiest_joint(cesium());
  return name;
}

bool has_warning(const Json& j, const std::string& part) {
  return std::any_of(j["warnings"].begin(), j["warnings"].end(),
                     [&](const Json& w) { return contains(w.get<std::string>(), part); });
}

// ---- item 8: one default pose -----------------------------------------------------------------

TEST(CliDefaultPose, EveryCommandDefaultsToTheBindPoseAndReportsIt) {
  TempDir dir;
  const Json bind = {{"kind", "bind"}};
  // pose without options is the bind pose: the box `info` reports, the same file as --bind-pose.
  const Json p = parse_json(run_ok(dir, {"pose", cesium().string(), "-o", (dir / "d.obj").string(), "--json"}));
  EXPECT_EQ(p["pose"], bind) << p.dump(2);
  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "b.obj").string(), "--bind-pose"});
  EXPECT_EQ(read_file(dir / "d.obj"), read_file(dir / "b.obj"));
  const Json info = parse_json(run_ok(dir, {"info", cesium().string(), "--json"}));
  EXPECT_EQ(info["pose"], bind);
  const Points d = read_obj_vertices(dir / "d.obj");
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(d.col(c).minCoeff(), info["bounding_box"]["min"][c].get<double>(), 1e-6);
    EXPECT_NEAR(d.col(c).maxCoeff(), info["bounding_box"]["max"][c].get<double>(), 1e-6);
  }
  // The text summary says so too.
  EXPECT_TRUE(contains(run_ok(dir, {"pose", cesium().string(), "-o", (dir / "t.obj").string()}).out, "bind pose"));

  // The surgery commands place their tools in the same pose.
  const Json cut = parse_json(run_ok(dir, {"cut", cesium().string(), "--plane", "0,1,0,0.9", "-o",
                                           (dir / "a.glb").string(), (dir / "b.glb").string(), "--json"}));
  EXPECT_EQ(cut["pose"], bind) << cut.dump(2);
  const Result cut_text = run_ok(dir, {"cut", cesium().string(), "--plane", "0,1,0,0.9", "-o", (dir / "a.obj").string(),
                                       (dir / "b.obj").string()});
  EXPECT_TRUE(contains(cut_text.out, "placed in the bind pose")) << cut_text;

  // A clip at a time, with edits, is reported as such.
  const Json clip = parse_json(run_ok(dir, {"pose", cesium().string(), "-o", (dir / "c.obj").string(), "--time", "0.5",
                                            "--set", busy_joint() + ":scale=1.5", "--json"}));
  EXPECT_EQ(clip["pose"]["kind"], "clip") << clip.dump(2);
  EXPECT_EQ(clip["pose"]["index"], 0);
  EXPECT_EQ(clip["pose"]["clip"], info["animations"][0]["name"]);
  EXPECT_EQ(clip["pose"]["time"], 0.5);
  EXPECT_EQ(clip["pose"]["blend"], "format");
  EXPECT_EQ(clip["pose"]["edits"], Json::array({busy_joint() + ":scale=1.5"}));
  const Json drill = parse_json(
      run_ok(dir, {"drill", cesium().string(), "--anim", "0", "--time", "0.5", "--base", "0.01,0.9,0.6", "--tip",
                   "0.01,0.9,-0.6", "--radius", "0.04", "-o", (dir / "drilled.glb").string(), "--json"}));
  EXPECT_EQ(drill["pose"]["kind"], "clip") << drill.dump(2);
  EXPECT_EQ(drill["pose"]["time"], 0.5);
  // deform acts on the bind pose in world space (the rigged model's default), and says so.
  const fs::path spec = fs::path(CGAMESH_DATA_DIR) / "specs" / "cesiumman_bend.json";
  const Json deform = parse_json(
      run_ok(dir, {"deform", cesium().string(), "--spec", spec.string(), "-o", (dir / "f.obj").string(), "--json"}));
  EXPECT_EQ(deform["pose"], Json({{"kind", "bind"}, {"space", "world"}})) << deform.dump(2);
}

TEST(CliDefaultPose, TimePastTheEndOrWithoutAClipWarns) {
  TempDir dir;
  const Result late =
      run_ok(dir, {"pose", cesium().string(), "-o", (dir / "late.obj").string(), "--time", "5", "--json"});
  EXPECT_TRUE(contains(late.err, "past the end of clip")) << late;
  EXPECT_TRUE(has_warning(parse_json(late), "past the end of clip")) << late;
  // A static frame has no clip: --time is a warning, the bind pose is used.
  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "frame.glb").string()});
  const Result none =
      run_ok(dir, {"pose", (dir / "frame.glb").string(), "-o", (dir / "none.obj").string(), "--time", "0.5", "--json"});
  EXPECT_TRUE(contains(none.err, "no animation")) << none;
  const Json j = parse_json(none);
  EXPECT_TRUE(has_warning(j, "no animation")) << none;
  EXPECT_EQ(j["pose"]["kind"], "bind");
  const Result cut = run_ok(dir, {"cut", cesium().string(), "--time", "9", "--plane", "0,1,0,0.9", "-o",
                                  (dir / "a.glb").string(), (dir / "b.glb").string(), "--json"});
  EXPECT_TRUE(has_warning(parse_json(cut), "past the end of clip")) << cut;
}

// A clip declared longer than its keys (the FBX declares 5 s, its keys end at 2.083 s) lasts as
// declared, also once converted to glTF: posing inside it is no "past the end" (issue #33, item 5).
TEST(CliDefaultPose, TimeInsideADeclaredLengthDoesNotWarnAfterConvert) {
  TempDir dir;
  const fs::path fbx = cgamesh_test::asset("rigged_simple_5s.fbx"), glb = dir / "converted.glb";
  run_ok(dir, {"convert", fbx.string(), "-o", glb.string()});
  for (const fs::path& model : {fbx, glb}) {
    const Result r = run_ok(dir, {"pose", model.string(), "--time", "2.5", "-o", (dir / "p.obj").string(), "--json"});
    EXPECT_FALSE(has_warning(parse_json(r), "past the end")) << r;
    const Json info = parse_json(run_ok(dir, {"info", model.string(), "--json"}));
    EXPECT_NEAR(info["animations"][0]["duration"].get<double>(), 5.0, 1e-6) << model;
  }
  const Result late = run_ok(dir, {"pose", glb.string(), "--time", "5.5", "-o", (dir / "p.obj").string(), "--json"});
  EXPECT_TRUE(has_warning(parse_json(late), "past the end of clip")) << late;
}

// ---- item 9: a rig you can discover -----------------------------------------------------------

TEST(CliInfo, ListsTheJointHierarchyBoxesAndClips) {
  TempDir dir;
  const Json j = parse_json(run_ok(dir, {"info", cesium().string(), "--json"}));
  const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(cesium());
  EXPECT_EQ(j["nodes"], m.skeleton.size());
  EXPECT_EQ(j["skinned_joints"], 19);  // the skin's joints, apart from the nodes above them
  EXPECT_GT(m.skeleton.size(), 19);
  EXPECT_EQ(j["meshes"][0]["skinned_joints"], 19);
  EXPECT_FALSE(j["meshes"][0].contains("joints")) << j["meshes"][0].dump();
  // convert --json names its counts as info does (it said 'joints' for the nodes).
  const Json c = parse_json(run_ok(dir, {"convert", cesium().string(), "-o", (dir / "c.glb").string(), "--json"}));
  EXPECT_EQ(c["nodes"], j["nodes"]);
  EXPECT_EQ(c["skinned_joints"], j["skinned_joints"]);
  EXPECT_FALSE(c.contains("joints")) << c.dump();
  ASSERT_EQ(j["skeleton"].size(), static_cast<std::size_t>(m.skeleton.size()));
  int skinning = 0;
  for (int i = 0; i < m.skeleton.size(); ++i) {
    const Json& joint = j["skeleton"][static_cast<std::size_t>(i)];
    EXPECT_EQ(joint["name"], std::string(m.skeleton.names()[i]));
    EXPECT_EQ(joint["parent"], m.skeleton.parents()[i]);
    skinning += joint["skins"] == Json::array({0}) ? 1 : 0;
  }
  EXPECT_EQ(skinning, 19);
  // Per mesh, the bind-pose box in world space and the box in mesh space (they differ for
  // CesiumMan, whose mesh hangs below a rotated node).
  const Json& mesh = j["meshes"][0];
  ASSERT_TRUE(mesh["bounding_box"]["min"].is_array()) << mesh.dump(2);
  ASSERT_TRUE(mesh["bounding_box_mesh_space"]["max"].is_array()) << mesh.dump(2);
  EXPECT_EQ(mesh["bounding_box"], j["bounding_box"]);
  EXPECT_NE(mesh["bounding_box_mesh_space"], mesh["bounding_box"]);
  EXPECT_EQ(j["animations"][0]["index"], 0);
  EXPECT_NEAR(j["animations"][0]["duration"].get<double>(), 2.0, 1e-6);

  // The text output: an indented tree, each child deeper than its parent, skin joints marked.
  const std::string text = run_ok(dir, {"info", cesium().string()}).out;
  EXPECT_TRUE(contains(text, "nodes: " + std::to_string(m.skeleton.size()) + " (19 skin joints)")) << text;
  EXPECT_TRUE(contains(text, "mesh-space box")) << text;
  const auto indent = [&](const std::string& name) {
    const std::size_t at = text.find("\n    ");
    std::size_t line = text.find(" " + name + "\n", at);
    if (line == std::string::npos) line = text.find(" " + name + "  [skins", at);
    if (line == std::string::npos) return std::string::npos;
    const std::size_t start = text.rfind('\n', line) + 1;
    return text.find_first_not_of(' ', start) - start;
  };
  for (int i = 0; i < m.skeleton.size(); ++i) {
    const int p = m.skeleton.parents()[i];
    if (p < 0) continue;
    const std::string child(m.skeleton.names()[i]), parent(m.skeleton.names()[p]);
    ASSERT_NE(indent(child), std::string::npos) << child << "\n" << text;
    EXPECT_EQ(indent(child), indent(parent) + 2) << child << " under " << parent << "\n" << text;
  }
  EXPECT_TRUE(contains(text, "[skins Cesium_Man]")) << text;
}

TEST(CliErrors, UnknownClipsAndJointsListTheValidNames) {
  Failure f;
  const fs::path out = f.outputs / "out.obj";
  const cgamesh::anim::RiggedModel m = cgamesh::io::load_model(cesium());
  // CesiumMan has 22 nodes: the first 20 are listed, then the count.
  const std::string first(m.skeleton.names()[0]), twentieth(m.skeleton.names()[19]);
  for (const std::vector<std::string>& edit :
       {std::vector<std::string>{"pose", cesium().string(), "-o", out.string(), "--set", "nope:scale=2"},
        std::vector<std::string>{"animate", cesium().string(), "-o", (f.outputs / "a.glb").string(), "--key",
                                 "0:nope:scale=1", "--key", "1:nope:scale=2"},
        std::vector<std::string>{"cut", cesium().string(), "--plane", "0,1,0,0.9", "--set", "nope:scale=2", "-o",
                                 (f.outputs / "a.glb").string(), (f.outputs / "b.glb").string()}}) {
    SCOPED_TRACE(edit[0]);
    expect_failure(f, edit, 2, "'" + first + "', ", out);
    expect_failure(f, edit, 2, "'" + twentieth + "', … (22 in all)", out);
  }
  const std::string clip = m.clips.at(0).name;
  expect_failure(f, {"pose", cesium().string(), "-o", out.string(), "--anim", "walk"}, 2,
                 "no animation 'walk' (the model has 1: '" + clip + "', or an index)", out);
  // The library's list: all names when few, else the first ones and the count.
  const std::vector<std::string> few{"a", "b"};
  EXPECT_EQ(cgamesh::anim::name_list(few), "'a', 'b'");
  EXPECT_EQ(cgamesh::anim::name_list(few, 1), "'a', … (2 in all)");
  EXPECT_EQ(cgamesh::anim::name_list({}), "none");
}

// ---- item 10: every bad value answered --------------------------------------------------------

// A name with a byte that is not UTF-8 (assimp passes it on) is read as Latin-1, with a warning;
// other text that is not UTF-8 (the file's path) shows U+FFFD in JSON. Exit 0.
TEST(CliJson, NonUtf8NamesAreReadAsLatin1AndPathsReplacedInJson) {
  TempDir dir;
  std::string bytes = read_file(cesium());
  const std::size_t at = bytes.find("Cesium_Man");
  ASSERT_NE(at, std::string::npos);
  bytes[at + 6] = static_cast<char>(0x8b);
  const fs::path bad = dir / "bad\x8b.glb";
  { std::ofstream(bad, std::ios::binary) << bytes; }
  const Result r = run_ok(dir, {"info", bad.string(), "--json"});
  const Json j = parse_json(r);
  EXPECT_EQ(j["meshes"][0]["name"], "Cesium\xC2\x8BMan") << r;
  EXPECT_TRUE(contains(j["file"].get<std::string>(), "bad\xEF\xBF\xBD.glb")) << r;
  EXPECT_TRUE(contains(j["warnings"].dump(), "are read as Latin-1")) << r;
  const Result p = run_ok(dir, {"pose", bad.string(), "-o", (dir / "p.obj").string(), "--json"});
  EXPECT_TRUE(parse_json(p).is_object()) << p;
}

TEST(CliValues, ResultsThatOverflowAreRefused) {
  Failure f;
  const fs::path out = f.outputs / "a.glb";
  const std::string j = busy_joint();
  // 1e308 is a double, but no float: the clip could only hold Infinity.
  expect_failure(f,
                 {"animate", cesium().string(), "--key", "0:" + j + ":rotate=1,0,0,0", "--key",
                  "1:" + j + ":translate=1e308,0.1,0", "-o", out.string()},
                 2, "translate", out);
  expect_failure(f, {"pose", cesium().string(), "--set", j + ":translate=1e308,0,0", "-o", out.string()}, 2,
                 "translate", out);
  expect_failure(f, {"pose", cesium().string(), "--set", j + ":scale=1e308", "-o", out.string()}, 2, "scale", out);
  expect_failure(f,
                 {"animate", cesium().string(), "--key", "0:" + j + ":scale=1", "--key", "1:" + j + ":scale=1e300",
                  "-o", out.string()},
                 2, "scale", out);
  // Too many frames: a huge fps, or a key far away in time.
  expect_failure(f,
                 {"animate", cesium().string(), "--key", "0:" + j + ":scale=1", "--key", "1:" + j + ":scale=2", "--fps",
                  "1e9", "-o", out.string()},
                 2, "more than the 100000 a generated clip may hold", out);
  expect_failure(f,
                 {"animate", cesium().string(), "--key", "0:" + j + ":scale=1", "--key", "1e6:" + j + ":scale=2", "-o",
                  out.string()},
                 2, "frames", out);
}

TEST(CliValues, EmptyValuesAreRefused) {
  Failure f;
  const fs::path out = f.outputs / "out.obj";
  const std::string m = cesium().string();
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--time", ""}, {"--anim", ""}, {"--set", ""}, {"--blend", ""}, {"--skinning", ""}}) {
    std::vector<std::string> args{"pose", m, "-o", out.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    SCOPED_TRACE(extra[0]);
    expect_failure(f, args, 2, extra[0], out);
  }
  expect_failure(
      f, {"tear", m, "--open", "", "--scalpel", "0,1,2,0,1,0", "--scalpel", "0.1,1,2,0.1,1,0", "-o", out.string()}, 2,
      "--open: the value is empty", out);
  expect_failure(f, {"drill", m, "--radius", "", "--tip", "0,1,0", "--base", "0,1,1", "-o", out.string()}, 2,
                 "--radius: the value is empty", out);
  expect_failure(f, {"pose", m, "-o", ""}, 2, "empty", out);
}

TEST(CliValues, DenormalsAndHugeAxesAreNumbers) {
  TempDir dir;
  const std::string j = busy_joint();
  const Points plain =
      read_obj_vertices((run_ok(dir, {"pose", cesium().string(), "-o", (dir / "p.obj").string()}), dir / "p.obj"));
  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "d.obj").string(), "--set", j + ":translate=5e-324,0,0"});
  EXPECT_LE(max_distance(read_obj_vertices(dir / "d.obj"), plain), 1e-6);
  // A rotation axis is a direction: its length does not matter, 1e308 included.
  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "r1.obj").string(), "--set", j + ":rotate=1,0,0,40"});
  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "r2.obj").string(), "--set", j + ":rotate=1e308,0,0,400"});
  run_ok(dir, {"pose", cesium().string(), "-o", (dir / "r3.obj").string(), "--set", j + ":rotate=5e-324,0,0,40"});
  const Points r1 = read_obj_vertices(dir / "r1.obj");
  EXPECT_GT(max_distance(r1, plain), 1e-2);
  EXPECT_LE(max_distance(read_obj_vertices(dir / "r2.obj"), r1), 1e-5);
  EXPECT_LE(max_distance(read_obj_vertices(dir / "r3.obj"), r1), 1e-5);
  Failure f;
  expect_failure(f, {"pose", cesium().string(), "-o", (f.outputs / "z.obj").string(), "--set", j + ":rotate=0,0,0,40"},
                 2, "zero vector", f.outputs / "z.obj");
}

TEST(CliValues, ToolsFarFromTheModelAreRefused) {
  Failure f;
  const fs::path out = f.outputs / "out.glb";
  const std::string m = cesium().string();
  expect_failure(
      f, {"drill", m, "--base", "0.01,0.9,0.6", "--tip", "0.01,0.9,-0.6", "--radius", "1e308", "-o", out.string()}, 2,
      "drill: the radius", out);
  expect_failure(
      f, {"drill", m, "--base", "0.01,0.9,0.6", "--tip", "1e308,0.9,-0.6", "--radius", "0.04", "-o", out.string()}, 2,
      "drill: the tip", out);
  expect_failure(f,
                 {"tear", m, "--scalpel", "0.01,0.9,2,0.01,0.9,0.06", "--scalpel", "0.02,0.9,1e308,0.02,0.9,0.06", "-o",
                  out.string()},
                 2, "tear: the handle of scalpel step 1", out);
  const fs::path b = f.outputs / "b.glb";
  expect_failure(f, {"cut", m, "--plane", "0,1,0,1e300", "-o", out.string(), b.string()}, 2, "cut: the plane", out);
  // A drill whose axis would meet the model further on says it stops short.
  expect_failure(f, {"drill", m, "--base", "0.01,0.9,3", "--tip", "0.01,0.9,2", "--radius", "0.04", "-o", out.string()},
                 4, "stops short of the surface", out);
  expect_failure(f, {"drill", m, "--base", "0.01,0.9,2", "--tip", "0.01,0.9,3", "--radius", "0.04", "-o", out.string()},
                 4, "points away from the model", out);
  expect_failure(f, {"drill", m, "--base", "5,0.9,2", "--tip", "5,0.9,3", "--radius", "0.04", "-o", out.string()}, 4,
                 "misses the model", out);
}

TEST(CliErrors, PoseListsEveryFormatItWrites) {
  Failure f;
  const fs::path out = f.outputs / "a.fbx";
  expect_failure(f, {"pose", cesium().string(), "-o", out.string()}, 2, ".glb, .gltf, .obj or .ply", out);
  expect_failure(f, {"cut", cesium().string(), "--plane", "0,1,0,0.9", "-o", out.string(), out.string() + ".glb"}, 2,
                 ".glb, .gltf, .obj or .ply", out);
}

TEST(CliErrors, OutputOverAnInputIsRefusedUnlessForced) {
  Failure f;
  const fs::path in = f.inputs / "m.glb";
  fs::copy_file(cesium(), in);
  const std::string before = read_file(in);
  const std::string same = (f.inputs / "." / "m.glb").string();
  const std::string j = busy_joint();
  const std::vector<std::vector<std::string>> commands{
      {"convert", in.string(), "-o", same},
      {"animate", in.string(), "--key", "0:" + j + ":scale=1", "--key", "1:" + j + ":scale=2", "-o", in.string()},
      {"cut", in.string(), "--plane", "0,1,0,0.9", "-o", (f.outputs / "a.glb").string(), same},
      {"tear", in.string(), "--scalpel", "0,1,2,0,1,0", "--scalpel", "0.1,1,2,0.1,1,0", "-o", in.string()},
      {"drill", in.string(), "--tip", "0,1,0", "--base", "0,1,1", "--radius", "0.1", "-o", in.string()}};
  for (const auto& args : commands) {
    SCOPED_TRACE(args[0]);
    const Result r = run_cli(args, f.outputs.path());
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_TRUE(contains(r.err, "is the input file")) << r;
    EXPECT_EQ(read_file(in), before);
  }
  expect_failure(f,
                 {"cut", in.string(), "--plane", "0,1,0,0.9", "-o", (f.outputs / "a.glb").string(),
                  (f.outputs / "." / "a.glb").string()},
                 2, "are the same file", f.outputs / "a.glb");
  // An OBJ posed over itself: the input is the output.
  const fs::path obj = f.inputs / "m.obj";
  run_ok(f.inputs, {"pose", in.string(), "-o", obj.string()});
  const Result r = run_cli({"pose", obj.string(), "-o", obj.string()}, f.outputs.path());
  EXPECT_EQ(r.code, 2) << r;
  // --force writes anyway.
  run_ok(f.inputs, {"convert", in.string(), "-o", same, "--force"});
  EXPECT_TRUE(fs::exists(in));
}

}  // namespace
