// `cgamesh render`: pictures of models and of surgery results, and every bad request refused.
#include <cstdlib>
#include <fstream>
#include <memory>
#include <span>
#include <vector>

#include <gtest/gtest.h>
#include <webp/demux.h>

#include "cgamesh/render/image.hpp"

#include "apps/cli_util.hpp"

namespace {

using namespace cgamesh_cli_test;

fs::path cesium() { return fs::path(CGAMESH_DATA_DIR) / "CesiumMan.glb"; }

cgamesh::render::Image read_png(const fs::path& p) {
  const std::string bytes = read_file(p);
  return cgamesh::render::decode_image(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                                       p.string());
}

TEST(CliRender, WritesAPictureOfTheRequestedSize) {
  TempDir dir;
  const fs::path out = dir.path() / "man.png";
  const Result r = run_ok(dir, {"render", cesium().string(), "-o", out.string(), "--anim", "0", "--time", "0.5",
                                "--size", "200x150", "--view", "iso", "--json"});
  const auto j = parse_json(r);
  EXPECT_EQ(j["width"], 200);
  EXPECT_EQ(j["height"], 150);
  EXPECT_TRUE(contains(j["renderer"].get<std::string>(), "OpenGL")) << r;
  const auto image = read_png(out);
  EXPECT_EQ(image.width, 200);
  EXPECT_EQ(image.height, 150);
  // Something other than the white background is drawn.
  long drawn = 0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4)
    drawn += image.rgba[i] + image.rgba[i + 1] + image.rgba[i + 2] < 700;
  EXPECT_GT(drawn, 500);
}

// Issue #33 item 7: a flat model seen edge-on made a blank picture without a word.
TEST(CliRender, AFlatModelSeenEdgeOnIsAWarning) {
  TempDir dir;
  const fs::path quad = dir.path() / "ground.obj", out = dir.path() / "ground.png";
  { std::ofstream(quad) << "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 3 2\nf 1 4 3\n"; }
  const Result front = run_ok(dir, {"render", quad.string(), "-o", out.string(), "--size", "64x48", "--json"});
  EXPECT_TRUE(contains(front.err, "warning: the view 'front' sees the model edge-on")) << front;
  const auto j = parse_json(front);
  bool warned = false;
  for (const auto& w : j["warnings"]) warned |= contains(w.get<std::string>(), "'top' sees it face-on");
  EXPECT_TRUE(warned) << front;
  const Result top = run_ok(dir, {"render", quad.string(), "-o", out.string(), "--size", "64x48", "--view", "top"});
  EXPECT_FALSE(contains(top.err, "edge-on")) << top;
}

// Found by the field sweep: glTF2/cameras/Cameras.gltf (one single-sided square facing away)
// rendered blank from the front without a word.
TEST(CliRender, APictureOfNothingIsAWarning) {
  TempDir dir;
  const fs::path quad = "/usr/share/assimp/models/glTF2/cameras/Cameras.gltf", out = dir.path() / "away.png";
  ASSERT_TRUE(fs::exists(quad)) << "scripts/install-deps.sh installs assimp-testmodels";
  const Result front = run_ok(dir, {"render", quad.string(), "-o", out.string(), "--size", "64x48", "--json"});
  EXPECT_TRUE(contains(front.err, "warning: the view 'front' shows nothing of the model")) << front;
  EXPECT_EQ(parse_json(front)["warnings"].size(), 1u) << front;
  const Result back = run_ok(dir, {"render", quad.string(), "-o", out.string(), "--size", "64x48", "--view", "back"});
  EXPECT_FALSE(contains(back.err, "shows nothing")) << back;
}

TEST(CliRender, TurntableMakesAContactSheetAndCutPiecesRenderTogether) {
  TempDir dir;
  const fs::path a = dir.path() / "a.glb", b = dir.path() / "b.glb", sheet = dir.path() / "sheet.png";
  run_ok(dir, {"cut", cesium().string(), "--plane", "0,1,0,0.9", "--cap", "-o", a.string(), b.string()});
  run_ok(dir, {"render", a.string(), b.string(), "-o", sheet.string(), "--color", "piece", "--turntable", "4", "--size",
               "120x90", "--skeleton", "--wireframe", "--bg", "0.2,0.2,0.2"});
  const auto image = read_png(sheet);
  EXPECT_EQ(image.width, 240);
  EXPECT_EQ(image.height, 180);
  const fs::path fresh = dir.path() / "new.png";
  run_ok(dir, {"render", a.string(), "-o", fresh.string(), "--color", "new", "--size", "160x120", "--camera",
               "0,1,3,0,0.9,0,0,1,0", "--frame"});
  EXPECT_TRUE(fs::exists(fresh));
}

TEST(CliRender, BadRequestsExitWithTheirCodeAndWriteNothing) {
  Failure f;
  const fs::path out = f.outputs / "out.png";
  const std::string m = cesium().string();
  expect_failure(f, {"render", (f.inputs / "missing.glb").string(), "-o", out.string()}, 3, "no such file", out);
  { std::ofstream(f.inputs / "x.glb") << "not a model\n"; }
  expect_failure(f, {"render", (f.inputs / "x.glb").string(), "-o", out.string()}, 3, "not a valid .glb", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--size", "0x100"}, 2, "--size", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--size", "100"}, 2, "WIDTHxHEIGHT", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--size", "100000x10"}, 2, "--size", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--camera", "1,1,1,1,1,1,0,1,0"}, 2, "same point", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--camera", "0,5,0,0,0,0,0,1,0"}, 2, "parallel", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--camera", "0,0,5,0,0,0"}, 2, "expected 9", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--camera", "nan,0,5,0,0,0,0,1,0"}, 2, "--camera", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--fov", "0"}, 2, "--fov", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--view", "side"}, 2, "view 'side'", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--bg", "2,0,0"}, 2, "--bg", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--color", "rainbow"}, 2, "colour 'rainbow'", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--color", "joint:nobody"}, 2, "unknown joint 'nobody'", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--turntable", "65"}, 2, "--turntable", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--turntable", "64", "--size", "4000x4000"}, 2, "sheet", out);
  expect_failure(f, {"render", m, "-o", (f.outputs / "out.jpg").string()}, 2, ".png", f.outputs / "out.jpg");
  expect_failure(f, {"render", m, "-o", out.string(), "--time", "-1"}, 2, "--time", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--time", "0:1:0"}, 2, "--time", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--time", "1:0:5"}, 2, "END must be after START", out);
  expect_failure(f, {"render", m, "-o", out.string(), "--time", "0:1:5000", "--size", "4000x4000"}, 2, "MiB", out);
  const fs::path webp = f.outputs / "out.webp";
  expect_failure(f, {"render", m, "-o", webp.string(), "--time", "0:1:x"}, 2, "whole number of frames", webp);
}

// Issue #34: moving pictures. A time range renders one frame per time, framed together, into an
// animated WebP that libwebp's decoder plays back with the frames' times, or into numbered PNGs.
TEST(CliRender, ATimeRangeMakesAnAnimationOrASequence) {
  TempDir dir;
  const fs::path webp = dir.path() / "walk.webp";
  const auto j = parse_json(run_ok(dir, {"render", cesium().string(), "--time", "0:1:6", "--size", "96x96", "-o",
                                         webp.string(), "--json"}));
  EXPECT_EQ(j["frames"], 6);
  EXPECT_DOUBLE_EQ(j["time"]["frame_seconds"].get<double>(), 1.0 / 6);
  const std::string bytes = read_file(webp);
  WebPData data{reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()};
  WebPAnimDecoderOptions options;
  ASSERT_TRUE(WebPAnimDecoderOptionsInit(&options));
  options.color_mode = MODE_RGBA;
  const std::unique_ptr<WebPAnimDecoder, void (*)(WebPAnimDecoder*)> decoder(WebPAnimDecoderNew(&data, &options),
                                                                             WebPAnimDecoderDelete);
  ASSERT_TRUE(decoder) << "libwebp reads the animation";
  std::vector<std::vector<std::uint8_t>> frames;
  std::vector<int> ends;
  while (WebPAnimDecoderHasMoreFrames(decoder.get()) != 0) {
    std::uint8_t* pixels = nullptr;
    int end = 0;
    ASSERT_TRUE(WebPAnimDecoderGetNext(decoder.get(), &pixels, &end));
    frames.emplace_back(pixels, pixels + 96 * 96 * 4);
    ends.push_back(end);
  }
  ASSERT_EQ(frames.size(), 6u);
  EXPECT_EQ(ends, (std::vector<int>{167, 333, 500, 667, 833, 1000}));
  // He walks: every frame differs from the one before.
  for (std::size_t k = 1; k < frames.size(); ++k) EXPECT_NE(frames[k], frames[k - 1]) << "frame " << k;

  // As PNGs: NAME_000.png ..., each the picture of that time alone (from one camera: a range
  // is framed as a whole).
  const fs::path png = dir.path() / "walk.png";
  const std::string camera = "0,1,3,0,0.8,0,0,1,0";
  run_ok(dir, {"render", cesium().string(), "--time", "0:1:3", "--size", "64x64", "--camera", camera, "-o",
               png.string()});
  EXPECT_FALSE(fs::exists(png));
  const fs::path single = dir.path() / "at.png";
  run_ok(dir, {"render", cesium().string(), "--time", "0.3333333333333333", "--size", "64x64", "--camera", camera,
               "-o", single.string()});
  EXPECT_EQ(read_png(dir.path() / "walk_001.png").rgba, read_png(single).rgba);
  EXPECT_TRUE(fs::exists(dir.path() / "walk_002.png"));
  EXPECT_FALSE(fs::exists(dir.path() / "walk_003.png"));
}

TEST(CliRender, NoEglIsExitOneNamingWhatFailed) {
  Failure f;
  const fs::path out = f.outputs / "out.png";
  // glvnd finds no EGL vendor: no display can be made.
  ::setenv("__EGL_VENDOR_LIBRARY_FILENAMES", (f.inputs.path() / "none.json").c_str(), 1);
  expect_failure(f, {"render", cesium().string(), "-o", out.string()}, 1, "EGL", out);
  ::unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
}

}  // namespace
