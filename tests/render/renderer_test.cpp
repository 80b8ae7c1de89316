// The renderer on a real context: EGL surfaceless (Mesa's llvmpipe in CI, no GPU, no display).
#include "cgamesh/render/renderer.hpp"

#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/render/headless_context.hpp"
#include "cgamesh/render/model_scene.hpp"

#include "anim/model_fixtures.hpp"
#include "render/render_checks.hpp"

namespace {

namespace render = cgamesh::render;
namespace anim = cgamesh::anim;
using cgamesh_test::Mask;

class Renderer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model_ = std::make_unique<anim::RiggedModel>(cgamesh::io::load_model(cgamesh_test::demo_model()));
  }
  static void TearDownTestSuite() { model_.reset(); }

  void SetUp() override {
    context_ = std::make_unique<render::HeadlessContext>();
    renderer_ = std::make_unique<render::Renderer>();
  }

  static anim::Pose pose_at(double t) {
    return anim::sample(model_->skeleton, model_->clips[0], t, anim::BlendMode::format);
  }

  render::Scene scene_at(double t, const render::ModelSceneOptions& o = {}) {
    const render::ModelInstance in{model_.get(), pose_at(t)};
    return render::model_scene(std::span(&in, 1), o);
  }

  static inline std::unique_ptr<anim::RiggedModel> model_;
  std::unique_ptr<render::HeadlessContext> context_;
  std::unique_ptr<render::Renderer> renderer_;
  render::RenderOptions options_{.width = 320, .height = 240, .background = {0, 0, 0}};
};

TEST_F(Renderer, TwoPosesAreFramedNotEmptyDifferentAndMatchACpuProjection) {
  std::vector<Mask> masks;
  for (const double t : {0.0, 0.6}) {
    const render::Scene scene = scene_at(t);
    const render::Camera camera = render::frame(scene.bounds(), render::View::front, 35, 320.0 / 240.0);
    const render::Image image = renderer_->render(scene, camera, options_);
    ASSERT_EQ(image.width, 320);
    ASSERT_EQ(image.height, 240);
    const Mask drawn = cgamesh_test::silhouette(image, {0, 0, 0});
    const auto e = cgamesh_test::extent(drawn);
    ASSERT_GT(drawn.count(), 0) << "empty picture";
    EXPECT_GT(e.x0, 0);
    EXPECT_LT(e.x1, 319);
    EXPECT_GT(e.y0, 0);
    EXPECT_LT(e.y1, 239);
    EXPECT_TRUE(e.x1 - e.x0 + 1 >= 0.25 * 320 || e.y1 - e.y0 + 1 >= 0.25 * 240) << "the model is too small";
    const Mask expected = cgamesh_test::project(scene.meshes, camera, 320, 240, scene.bounds(),
                                                [](std::size_t, Eigen::Index) { return true; });
    EXPECT_GE(cgamesh_test::iou(drawn, expected), 0.95) << "t = " << t;
    masks.push_back(drawn);
  }
  EXPECT_LT(cgamesh_test::iou(masks[0], masks[1]), 0.8) << "the two poses look the same";
}

TEST_F(Renderer, AGivenCameraIsTheOneUsed) {
  const render::Scene scene = scene_at(0.3);
  const render::Camera camera{{1.5, 1.6, 1.2}, {0, 0.8, 0}, {0, 1, 0}, 50};
  const render::Image image = renderer_->render(scene, camera, options_);
  const Mask expected = cgamesh_test::project(scene.meshes, camera, 320, 240, scene.bounds(),
                                              [](std::size_t, Eigen::Index) { return true; });
  EXPECT_GE(cgamesh_test::iou(cgamesh_test::silhouette(image, {0, 0, 0}), expected), 0.95);
}

TEST_F(Renderer, JointColourIsHotWhereTheJointInfluences) {
  // The joint whose vertices' region is hot: the neck-and-head joint has the largest region.
  const cgamesh::mesh::Mesh& m = model_->meshes[0];
  std::vector<double> area(static_cast<std::size_t>(model_->skeleton.size()), 0);
  for (Eigen::Index v = 0; v < m.vertex_count(); ++v)
    if (m.skin.weights(v, 0) > 0.9) area[static_cast<std::size_t>(m.skin.palette[m.skin.joints(v, 0)])] += 1;
  const int joint = static_cast<int>(std::max_element(area.begin(), area.end()) - area.begin());
  render::ModelSceneOptions o;
  o.color = render::ColorMode::joint;
  o.joint = model_->skeleton.names()[static_cast<std::size_t>(joint)];
  const render::Scene scene = scene_at(0.0, o);
  const render::Camera camera = render::frame(scene.bounds(), render::View::front, 35, 320.0 / 240.0);
  const render::Image image = renderer_->render(scene, camera, options_);
  // Faces whose corners the joint dominates, projected; hot pixels must lie there.
  const auto weight = [&](int v) {
    float w = 0;
    for (int k = 0; k < 4; ++k)
      if (m.skin.palette[m.skin.joints(v, k)] == joint) w += m.skin.weights(v, k);
    return w;
  };
  const Mask region =
      cgamesh_test::project(scene.meshes, camera, 320, 240, scene.bounds(), [&](std::size_t, Eigen::Index f) {
        return weight(m.faces(f, 0)) > 0.5 || weight(m.faces(f, 1)) > 0.5 || weight(m.faces(f, 2)) > 0.5;
      });
  long hot = 0, inside = 0, cold = 0;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      if (p[0] > 110 && p[0] > 2 * p[1] && p[0] > 2 * p[2]) {
        ++hot;
        inside += region.at(x, y);
      }
      if (p[2] > 60 && p[2] > 2 * p[0]) ++cold;
    }
  EXPECT_GT(hot, 300) << "no hot region";
  EXPECT_GT(cold, hot) << "the rest of the body is not cold";
  EXPECT_GE(static_cast<double>(inside), 0.95 * static_cast<double>(hot));
}

TEST_F(Renderer, HeightColourIsHotAtTheTopAndColdAtTheBottom) {
  render::ModelSceneOptions o;
  o.color = render::ColorMode::height;
  const render::Scene scene = scene_at(0.0, o);
  const render::Camera camera = render::frame(scene.bounds(), render::View::front, 35, 320.0 / 240.0);
  const render::Image image = renderer_->render(scene, camera, options_);
  const auto e = cgamesh_test::extent(cgamesh_test::silhouette(image, {0, 0, 0}));
  const auto mean_of_row = [&](int y) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
    for (int x = 0; x < 320; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      if (p[0] + p[1] + p[2] > 60) {
        sum += Eigen::Vector3d(p[0], p[1], p[2]);
        ++n;
      }
    }
    return Eigen::Vector3d(sum / std::max(n, 1));
  };
  const Eigen::Vector3d top = mean_of_row(e.y0 + 3), bottom = mean_of_row(e.y1 - 3);
  EXPECT_GT(top.x(), top.z()) << "top not red: " << top.transpose();
  EXPECT_GT(bottom.z(), bottom.x()) << "bottom not blue: " << bottom.transpose();
}

TEST_F(Renderer, MaterialModeShowsTheBaseColourTexture) {
  // CesiumMan's texture is white with blue and green bands: both show, with the white
  // between them.
  const render::Scene scene = scene_at(0.5);
  ASSERT_TRUE(scene.meshes[0].texture);
  const render::Camera camera = render::frame(scene.bounds(), render::View::right, 35, 320.0 / 240.0);
  const render::Image image = renderer_->render(scene, camera, options_);
  long green = 0, blue = 0, drawn = 0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
    const int r = image.rgba[i], g = image.rgba[i + 1], b = image.rgba[i + 2];
    drawn += r + g + b > 60;
    green += g > r + 40 && g > b + 20;
    blue += b > r + 40 && b > g;
  }
  EXPECT_GT(green, 100);
  EXPECT_GT(blue, 100);
  EXPECT_GT(2 * drawn, 3 * (green + blue));
}

TEST_F(Renderer, BackFacesAreTinted) {
  // A single triangle seen from behind takes the back-face colour; from the front it does not.
  render::Scene scene;
  render::DrawMesh tri;
  tri.positions.resize(3, 3);
  tri.positions << -1, -1, 0, 1, -1, 0, 0, 1, 0;
  tri.faces.resize(1, 3);
  tri.faces << 0, 1, 2;
  tri.base_color = {0.2f, 0.9f, 0.2f, 1};
  scene.meshes.push_back(tri);
  const auto centre = [&](const render::Camera& c) {
    const render::Image im = renderer_->render(scene, c, options_);
    const std::uint8_t* p = im.pixel(160, 130);
    return Eigen::Vector3i(p[0], p[1], p[2]);
  };
  const Eigen::Vector3i front = centre({{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 50});
  const Eigen::Vector3i back = centre({{0, 0, -4}, {0, 0, 0}, {0, 1, 0}, 50});
  EXPECT_GT(front.y(), front.x());
  EXPECT_GT(back.x(), back.y()) << back.transpose();
}

TEST_F(Renderer, WireframeDarkensEdgesAndOverlaysAreDrawn) {
  render::ModelSceneOptions o;
  o.skeleton = true;
  const render::Scene scene = scene_at(0.0, o);
  ASSERT_FALSE(scene.points.empty());
  const render::Camera camera = render::frame(scene.bounds(), render::View::front, 35, 320.0 / 240.0);
  render::RenderOptions wire = options_;
  wire.wireframe = true;
  const render::Image plain = renderer_->render(scene_at(0.0), camera, options_);
  const render::Image wired = renderer_->render(scene_at(0.0), camera, wire);
  const render::Image skeleton = renderer_->render(scene, camera, options_);
  long darker = 0, orange = 0;
  for (std::size_t i = 0; i < plain.rgba.size(); i += 4) {
    darker += wired.rgba[i] + 30 < plain.rgba[i];
    orange +=
        skeleton.rgba[i] > 200 && skeleton.rgba[i + 1] > 100 && skeleton.rgba[i + 1] < 200 && skeleton.rgba[i + 2] < 80;
  }
  EXPECT_GT(darker, 500);
  EXPECT_GT(orange, 19 * 10) << "joint dots missing";
}

TEST_F(Renderer, BadScenesAndOptionsAreErrors) {
  render::Scene scene = scene_at(0.0);
  const render::Camera camera = render::frame(scene.bounds(), render::View::front, 35, 1);
  render::RenderOptions o = options_;
  o.width = 0;
  EXPECT_THROW(static_cast<void>(renderer_->render(scene, camera, o)), cgamesh::InvalidInputError);
  o = options_;
  o.height = render::kMaxImageSide + 1;
  EXPECT_THROW(static_cast<void>(renderer_->render(scene, camera, o)), cgamesh::InvalidInputError);
  render::Scene broken = scene;
  broken.meshes[0].faces(0, 0) = static_cast<int>(broken.meshes[0].positions.rows());
  EXPECT_THROW(static_cast<void>(renderer_->render(broken, camera, options_)), cgamesh::InvalidInputError);
  broken = scene;
  broken.meshes[0].colors.resize(2, 3);
  EXPECT_THROW(static_cast<void>(renderer_->render(broken, camera, options_)), cgamesh::InvalidInputError);
  EXPECT_THROW(
      static_cast<void>(renderer_->render(scene, render::Camera{{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 35}, options_)),
      cgamesh::InvalidInputError);
}

}  // namespace
