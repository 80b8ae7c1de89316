// `cgamesh view`: scripts run on a virtual display (Xvfb), and what the viewer saves equals what
// the command-line tools write with the same parameters.
#include <cstdlib>
#include <map>
#include <span>
#include <sstream>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/io/model_info.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/render/image.hpp"
#include "cgamesh/render/model_scene.hpp"
#include "cgamesh/surgery/placement.hpp"

#include "apps/cli_util.hpp"
#include "render/render_checks.hpp"
#include "support/js_oracles.hpp"

namespace {

using namespace cgamesh_cli_test;
using cgamesh::anim::RiggedModel;

fs::path cesium() { return fs::path(CGAMESH_DATA_DIR) / "CesiumMan.glb"; }

bool xvfb_available() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

/// `cgamesh view ARGS...` on a virtual 1280×1024 display. The X authority file lives in the
/// test's directory: with its own temporary directory, xvfb-run can fail its clean-up (exit 5)
/// after the viewer has returned its code.
Result run_view(const fs::path& dir, const std::vector<std::string>& args) {
  static int runs = 0;
  const fs::path auth = dir / ("Xauthority." + std::to_string(runs++));
  std::vector<std::string> argv{"xvfb-run",          "-a",  "-f", auth.string(), "-s", "-screen 0 1280x1024x24",
                                cli_path().string(), "view"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_program(argv, dir);
}

/// The arguments of a logged command (its words after "cgamesh"; the test's paths need no
/// quotes), those in `names` replaced.
std::vector<std::string> command_words(const std::string& command, const std::map<std::string, std::string>& names) {
  std::istringstream in(command);
  std::vector<std::string> out;
  std::string w;
  in >> w;  // "cgamesh"
  while (in >> w) out.push_back(names.contains(w) ? names.at(w) : w);
  return out;
}

/// A vertex some face uses: rest position and skin weights by joint name.
struct UsedVertex {
  Eigen::Vector3d position;
  std::map<std::string, double> weights;
};

std::vector<UsedVertex> used_vertices(const RiggedModel& m) {
  std::vector<UsedVertex> out;
  for (const auto& mesh : m.meshes) {
    std::vector<char> used(static_cast<std::size_t>(mesh.vertex_count()), 0);
    for (Eigen::Index f = 0; f < mesh.face_count(); ++f)
      for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(mesh.faces(f, k))] = 1;
    for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v) {
      if (used[static_cast<std::size_t>(v)] == 0) continue;
      UsedVertex u{mesh.positions.row(v).transpose().cast<double>(), {}};
      for (int k = 0; k < 4 && !mesh.skin.empty(); ++k)
        if (mesh.skin.weights(v, k) > 0)
          u.weights[m.skeleton.names()[static_cast<std::size_t>(mesh.skin.palette[mesh.skin.joints(v, k)])]] +=
              mesh.skin.weights(v, k);
      out.push_back(std::move(u));
    }
  }
  return out;
}

long face_count(const RiggedModel& m) {
  long n = 0;
  for (const auto& mesh : m.meshes) n += mesh.face_count();
  return n;
}

/// Every vertex of `a` matches its own vertex of `b`: the same rest position and weights.
void expect_same_vertices(const std::vector<UsedVertex>& a, const std::vector<UsedVertex>& b, double tolerance) {
  ASSERT_EQ(a.size(), b.size());
  std::vector<char> taken(b.size(), 0);
  int unmatched = 0;
  for (const UsedVertex& u : a) {
    std::size_t best = b.size();
    double best_d = INFINITY;
    for (std::size_t i = 0; i < b.size(); ++i) {
      if (taken[i] != 0) continue;
      const double d = (b[i].position - u.position).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = i;
      }
    }
    bool same = best < b.size() && std::sqrt(best_d) <= tolerance && b[best].weights.size() == u.weights.size();
    if (same)
      for (const auto& [joint, w] : u.weights)
        same = same && b[best].weights.contains(joint) && std::abs(b[best].weights.at(joint) - w) <= 1e-5;
    if (!same) {
      ++unmatched;
      continue;
    }
    taken[best] = 1;
  }
  EXPECT_EQ(unmatched, 0) << "of " << a.size() << " vertices";
}

std::vector<nlohmann::json> json_lines(const std::string& out) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

TEST(CliView, ScriptCutsTearsDrillsUndoesAndSavesWhatTheCommandsWrite) {
  ASSERT_TRUE(xvfb_available()) << "xvfb-run is missing: scripts/install-deps.sh installs it";
  TempDir dir;
  const fs::path script = dir / "surgery.txt", saved = dir / "viewer.glb", shot = dir / "viewer.png";
  {
    std::ofstream s(script);
    s << "# CesiumMan at t = 0.5: a cut, a tear dragged across the chest, a drill, one undo\n"
         "clip 0\nplay 0.5\ncut 0,1,0,0.6\n"
         "drag 598,395 604,396 610,397 616,398 622,399 628,400 634,401 640,402 646,403 652,404\n"
         "drill 0.0,1.3,-0.05 0.0,1.3,0.3 0.04 wall\n"
         "undo\ncolor piece\n"
         "save \""
      << saved.string() << "\"\nscreenshot \"" << shot.string() << "\"\nquit\n";
  }
  const Result r = run_view(dir.path(), {cesium().string(), "--script", script.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r;
  const std::vector<nlohmann::json> log = json_lines(r.out);
  ASSERT_EQ(log.size(), 5u) << r;
  EXPECT_EQ(log[0]["operation"], "cut");
  EXPECT_EQ(log[1]["operation"], "tear");
  EXPECT_EQ(log[2]["operation"], "drill");
  EXPECT_EQ(log[3]["screenshot"], shot.string());
  EXPECT_GT(log[4]["frames"].get<int>(), 10);  // one action per frame, several for play and drag
  const std::string tear = log[1]["command"];
  int blades = 0;
  for (std::size_t at = tear.find("--scalpel"); at != std::string::npos; at = tear.find("--scalpel", at + 1)) ++blades;
  EXPECT_GE(blades, 3) << tear;  // a stroke dragged over several steps
  EXPECT_GT(log[2]["faces"].get<int>(), log[1]["faces"].get<int>());

  // The same cut and tear by the command line, replayed as printed: the first reads the model,
  // each writes stepN.glb (here in the test's directory) and the next reads it.
  EXPECT_TRUE(contains(tear, " step1.glb ")) << tear;
  const std::map<std::string, std::string> steps{{"step1.glb", (dir / "step1.glb").string()},
                                                 {"step2.glb", (dir / "step2.glb").string()}};
  run_ok(dir, command_words(log[0]["command"], steps));
  run_ok(dir, command_words(tear, steps));
  const RiggedModel viewer = cgamesh::io::load_model(saved);
  const RiggedModel cli_a = cgamesh::io::load_model(dir / "step2.glb");
  EXPECT_EQ(face_count(viewer), face_count(cli_a));
  expect_same_vertices(used_vertices(viewer), used_vertices(cli_a), 1e-5);
  EXPECT_EQ(viewer.clips.size(), cli_a.clips.size());
  // The command line's cut keeps the pieces as two meshes (the viewer's in-place cut, one), which
  // the writer gives nodes of their own: every node of the viewer's file is there, and the joints.
  for (const auto& name : viewer.skeleton.names()) EXPECT_GE(cli_a.skeleton.find(name), 0) << name;
  EXPECT_EQ(cgamesh::io::skinned_joint_count(cli_a), cgamesh::io::skinned_joint_count(viewer));

  if (cgamesh_test::validator_available()) {
    std::string validator_log;
    EXPECT_EQ(cgamesh_test::validate_gltf(saved, validator_log), 0) << validator_log;
  }

  // The screenshot is the saved model as the viewer showed it: its silhouette matches a CPU
  // projection of the same scene seen by the viewer's camera.
  const std::string png = read_file(shot);
  const cgamesh::render::Image image =
      cgamesh::render::decode_image(std::span(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()), "png");
  EXPECT_EQ(image.width, 1280);
  EXPECT_EQ(image.height, 800);
  const RiggedModel original = cgamesh::io::load_model(cesium());
  const std::array<cgamesh::render::ModelInstance, 1> bind{
      cgamesh::render::ModelInstance{&original, cgamesh::anim::rest_pose(original.skeleton)}};
  const cgamesh::render::Camera camera = cgamesh::render::frame(cgamesh::render::model_scene(bind, {}).bounds(),
                                                                cgamesh::render::View::front, 35, 1280.0 / 800);
  cgamesh::render::ModelSceneOptions options;
  options.color = cgamesh::render::ColorMode::piece;
  const std::array<cgamesh::render::ModelInstance, 1> posed{cgamesh::render::ModelInstance{
      &viewer, cgamesh::anim::sample(viewer.skeleton, viewer.clips[0], 0.5, cgamesh::anim::BlendMode::format)}};
  const cgamesh::render::Scene scene = cgamesh::render::model_scene(posed, options);
  const auto drawn = cgamesh_test::silhouette(image, {255, 255, 255});
  const auto expected_mask = cgamesh_test::project(scene.meshes, camera, 1280, 800, scene.bounds(),
                                                   [](std::size_t, Eigen::Index) { return true; });
  EXPECT_GT(expected_mask.count(), 20000);
  EXPECT_GT(cgamesh_test::iou(drawn, expected_mask), 0.95);
}

// A spline spec and an FFD spec: the viewer binds both through BoundDeformer.
TEST(CliView, ASpecIsPreviewedAndAppliedAsTheDeformCommandDoes) {
  ASSERT_TRUE(xvfb_available()) << "xvfb-run is missing: scripts/install-deps.sh installs it";
  TempDir dir;
  const fs::path script = dir / "deform.txt", viewer = dir / "viewer.obj", cli = dir / "cli.obj",
                 rigged = dir / "viewer.glb";
  {
    std::ofstream s(script);
    s << "wait 2\ndeform\nsave \"" << viewer.string() << "\"\nsave \"" << rigged.string() << "\"\nundo\nquit\n";
  }
  for (const char* name : {"cesiumman_bend.json", "ffd_twist_motor.json"}) {
    const std::string spec = std::string(CGAMESH_DATA_DIR) + "/specs/" + name;
    const Result r = run_view(dir.path(), {cesium().string(), "--spec", spec, "--script", script.string(), "--json"});
    ASSERT_EQ(r.code, 0) << name << "\n" << r;
    const std::vector<nlohmann::json> log = json_lines(r.out);
    ASSERT_GE(log.size(), 1u) << r;
    EXPECT_EQ(log[0]["operation"], "deform");
    run_ok(dir, {"deform", cesium().string(), "--spec", spec, "-o", cli.string(), "--force"});
    const Points a = read_obj_vertices(viewer), b = read_obj_vertices(cli);
    ASSERT_EQ(a.rows(), b.rows());
    EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-5) << name;
    // The deformed model keeps its rig and clips.
    const RiggedModel m = cgamesh::io::load_model(rigged);
    EXPECT_EQ(m.clips.size(), 1u);
    EXPECT_FALSE(m.meshes[0].skin.empty());
  }
}

TEST(CliView, WorksOnAnAssimpTestModel) {
  ASSERT_TRUE(xvfb_available()) << "xvfb-run is missing: scripts/install-deps.sh installs it";
  const fs::path wuson = "/usr/share/assimp/models/X/Testwuson.X";  // Debian's assimp-testmodels
  ASSERT_TRUE(fs::exists(wuson)) << "assimp-testmodels is missing: scripts/install-deps.sh installs it";
  TempDir dir;
  const fs::path script = dir / "wuson.txt", saved = dir / "wuson.glb", shot = dir / "wuson.png";
  {
    std::ofstream s(script);
    s << "clip 0\nplay 0.5\ncut 0,1,0,0.8\ndrill 1.0,1.0,0.3 -1.0,1.0,0.3 0.1 wall\nsave \"" << saved.string()
      << "\"\nscreenshot \"" << shot.string() << "\"\n";
  }
  const Result r = run_view(dir.path(), {wuson.string(), "--script", script.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r;
  const std::vector<nlohmann::json> log = json_lines(r.out);
  ASSERT_EQ(log.size(), 4u) << r;
  EXPECT_EQ(log[0]["operation"], "cut");
  EXPECT_EQ(log[1]["operation"], "drill");
  const RiggedModel original = cgamesh::io::load_model(wuson), edited = cgamesh::io::load_model(saved);
  EXPECT_GT(face_count(edited), face_count(original));
  EXPECT_EQ(edited.clips.size(), original.clips.size());
  EXPECT_EQ(log[1]["faces"].get<long>(), face_count(edited));
  const std::string png = read_file(shot);
  const auto image =
      cgamesh::render::decode_image(std::span(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()), "png");
  EXPECT_GT(cgamesh_test::silhouette(image, {255, 255, 255}).count(), 20000);
}

// Issue #34: with the tissue on, a tear dragged across CesiumMan's chest opens while he walks;
// the panel shows it; Bake writes the open wound into the model, which then animates with it.
TEST(CliView, LivingTissueOpensADraggedTearWhileHeWalksAndBakes) {
  ASSERT_TRUE(xvfb_available()) << "xvfb-run is missing: scripts/install-deps.sh installs it";
  TempDir dir;
  const fs::path script = dir / "tissue.txt", saved = dir / "baked.glb", shot = dir / "tissue.png";
  {
    std::ofstream s(script);
    s << "clip 0\nplay 0.5\ntissue 0.3\n"
         "drag 598,395 604,396 610,397 616,398 622,399 628,400 634,401 640,402 646,403 652,404\n"
         "play 1.2\nscreenshot \""
      << shot.string() << "\" panel\nbake\nsave \"" << saved.string() << "\"\nquit\n";
  }
  const Result r = run_view(dir.path(), {cesium().string(), "--script", script.string(), "--json"});
  ASSERT_EQ(r.code, 0) << r;
  const std::vector<nlohmann::json> log = json_lines(r.out);
  ASSERT_GE(log.size(), 3u) << r;
  EXPECT_EQ(log[0]["operation"], "tear");
  EXPECT_EQ(log[2]["operation"], "bake tissue") << r;
  // The tear alone, by the command line its log prints, against the baked model: the wound's
  // vertices moved (opened) by millimetres, the rest of the body did not move.
  const std::map<std::string, std::string> steps{{"step1.glb", (dir / "step1.glb").string()}};
  run_ok(dir, command_words(log[0]["command"], steps));
  const RiggedModel torn = cgamesh::io::load_model(dir / "step1.glb");
  const RiggedModel baked = cgamesh::io::load_model(saved);
  ASSERT_EQ(face_count(baked), face_count(torn));
  const auto a = cgamesh::surgery::place(torn, cgamesh::anim::sample(torn.skeleton, torn.clips[0], 1.2, cgamesh::anim::BlendMode::format)).positions;
  const auto b = cgamesh::surgery::place(baked, cgamesh::anim::sample(baked.skeleton, baked.clips[0], 1.2, cgamesh::anim::BlendMode::format)).positions;
  double moved = 0;
  long unmoved = 0, total = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (Eigen::Index v = 0; v < std::min(a[i].rows(), b[i].rows()); ++v) {
      const double d = (a[i].row(v) - b[i].row(v)).norm();
      moved = std::max(moved, d);
      unmoved += d < 1e-4 ? 1 : 0;
      ++total;
    }
  EXPECT_GT(moved, 2e-3) << "the wound opened";
  EXPECT_GT(unmoved, total * 8 / 10) << "away from the wound, the body is as skinned";
  if (cgamesh_test::validator_available()) {
    std::string validator_log;
    EXPECT_EQ(cgamesh_test::validate_gltf(saved, validator_log), 0) << validator_log;
  }
  EXPECT_TRUE(fs::exists(shot));
}

TEST(CliView, MorphWeightsChangeWhatIsShown) {
  ASSERT_TRUE(xvfb_available()) << "xvfb-run is missing: scripts/install-deps.sh installs it";
  TempDir dir;
  const fs::path script = dir / "morph.txt", a = dir / "a.png", b = dir / "b.png";
  {
    std::ofstream s(script);
    s << "morph bulge=1\nscreenshot \"" << a.string() << "\" panel\nunmorph\nscreenshot \"" << b.string() << "\"\n";
  }
  const Result r = run_view(dir.path(), {(fs::path(CGAMESH_TEST_ASSETS) / "rigged_simple_morph.glb").string(), "--script",
                                         script.string(), "--size", "640x480"});
  ASSERT_EQ(r.code, 0) << r;
  const auto silhouette = [](const fs::path& p) {
    const std::string png = read_file(p);
    return cgamesh_test::silhouette(
               cgamesh::render::decode_image(std::span(reinterpret_cast<const std::uint8_t*>(png.data()), png.size()),
                                             "png"),
               {255, 255, 255})
        .count();
  };
  // The bulge widens the cylinder by a fifth of its radius or more: more pixels are covered.
  EXPECT_GT(silhouette(a), silhouette(b) * 11 / 10) << "bulge=1 against the file's weights";
}

TEST(CliView, BadScriptsAndMissingModelsExitWithTheirCodes) {
  Failure f;
  const fs::path script = f.inputs / "bad.txt";
  {
    std::ofstream s(script);
    s << "clip 0\n\n# then\nfly 0.5\n";
  }
  // Checked before any window opens: no display needed.
  expect_failure(f, {"view", cesium().string(), "--script", script.string()}, 2, "bad.txt:4: unknown action 'fly'",
                 f.outputs / "x");
  {
    std::ofstream s(script);
    s << "joint Nobody:rotate=0,0,1,30\n";
  }
  expect_failure(f, {"view", cesium().string(), "--script", script.string()}, 2, "unknown joint 'Nobody'",
                 f.outputs / "x");
  {
    std::ofstream s(script);
    s << "cut 0,1,0\n";
  }
  expect_failure(f, {"view", cesium().string(), "--script", script.string()}, 2, "bad.txt:1:", f.outputs / "x");
  expect_failure(f, {"view", (f.inputs / "missing.glb").string()}, 3, "missing.glb", f.outputs / "x");
  expect_failure(f, {"view", cesium().string(), "--script", (f.inputs / "none.txt").string()}, 3, "none.txt",
                 f.outputs / "x");
  expect_failure(f, {"view", cesium().string(), "--spec", (f.inputs / "none.json").string()}, 3, "none.json",
                 f.outputs / "x");
}

TEST(CliView, NoDisplayIsExitOneAndPointsToRender) {
  TempDir dir;
  const Result r = run_program(
      {"env", "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", cli_path().string(), "view", cesium().string()}, dir.path());
  EXPECT_EQ(r.code, 1) << r;
  EXPECT_TRUE(contains(r.err, "cgamesh render")) << r;
}

TEST(CliView, AScriptThatFailsStopsAtItsLineWithTheOperationsCode) {
  ASSERT_TRUE(xvfb_available()) << "xvfb-run is missing: scripts/install-deps.sh installs it";
  TempDir dir;
  const fs::path script = dir / "miss.txt";
  {
    std::ofstream s(script);
    s << "cut 0,1,0,100\n";  // far above the model: nothing to cut
  }
  const Result r = run_view(dir.path(), {cesium().string(), "--script", script.string()});
  EXPECT_EQ(r.code, 4) << r;
  EXPECT_TRUE(contains(r.err, "miss.txt:1: cut:")) << r;
}

}  // namespace
