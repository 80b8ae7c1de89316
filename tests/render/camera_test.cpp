#include "cgamesh/render/camera.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"

namespace {

using cgamesh::render::Box;
using cgamesh::render::Camera;
using cgamesh::render::View;
namespace render = cgamesh::render;

Eigen::Vector4d clip_of(const Camera& c, double aspect, const Eigen::Vector3d& p, double near = 0.1, double far = 100) {
  return render::projection_matrix(c, aspect, near, far) * render::view_matrix(c) * p.homogeneous();
}

TEST(Camera, LookAtPutsTheEyeAtTheOriginAndTheTargetDownMinusZ) {
  const Camera c{{1, 2, 3}, {-2, 0.5, 1}, {0, 1, 0}, 40};
  const Eigen::Matrix4d v = render::view_matrix(c);
  EXPECT_LT((v * c.eye.homogeneous()).template head<3>().norm(), 1e-12);
  const Eigen::Vector3d t = (v * c.target.homogeneous()).template head<3>();
  EXPECT_NEAR(t.x(), 0, 1e-12);
  EXPECT_NEAR(t.y(), 0, 1e-12);
  EXPECT_NEAR(t.z(), -(c.target - c.eye).norm(), 1e-12);
  // The rotation part is orthonormal and right-handed; up maps into the upper half.
  EXPECT_TRUE((v.topLeftCorner<3, 3>() * v.topLeftCorner<3, 3>().transpose()).isIdentity(1e-12));
  EXPECT_NEAR((v.topLeftCorner<3, 3>().determinant()), 1, 1e-12);
  EXPECT_GT((v.topLeftCorner<3, 3>() * c.up).y(), 0);
}

TEST(Camera, PerspectiveMapsNearAndFarToTheClipRange) {
  const Camera c{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60};
  const Eigen::Vector4d near = clip_of(c, 2.0, {0, 0, 5 - 0.1}), far = clip_of(c, 2.0, {0, 0, 5 - 100});
  EXPECT_NEAR(near.z() / near.w(), -1, 1e-9);
  EXPECT_NEAR(far.z() / far.w(), 1, 1e-9);
  // A point on the upper edge of the vertical field of view lands on y = 1.
  const double y = std::tan(30 * std::numbers::pi / 180) * 5;
  const Eigen::Vector4d top = clip_of(c, 2.0, {0, y, 0});
  EXPECT_NEAR(top.y() / top.w(), 1, 1e-9);
  const Eigen::Vector4d right = clip_of(c, 2.0, {2 * y, 0, 0});
  EXPECT_NEAR(right.x() / right.w(), 1, 1e-9);
}

TEST(Camera, FramingHoldsEveryCornerTightly) {
  Box box;
  box.add({-0.3, 0, -0.2});
  box.add({0.5, 1.8, 0.4});
  for (const View view : {View::front, View::back, View::left, View::right, View::top, View::iso})
    for (const double aspect : {0.5, 4.0 / 3.0, 2.5}) {
      const Camera c = render::frame(box, view, 35, aspect);
      ASSERT_NO_THROW(render::validate(c));
      double extent = 0;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d corner((k & 1) ? box.hi.x() : box.lo.x(), (k & 2) ? box.hi.y() : box.lo.y(),
                                     (k & 4) ? box.hi.z() : box.lo.z());
        const Eigen::Vector4d p = clip_of(c, aspect, corner);
        ASSERT_GT(p.w(), 0);
        extent = std::max({extent, std::abs(p.x() / p.w()), std::abs(p.y() / p.w())});
      }
      EXPECT_LE(extent, 0.92 + 1e-9) << static_cast<int>(view) << " " << aspect;
      EXPECT_GE(extent, 0.90) << "not tight: " << static_cast<int>(view) << " " << aspect;
    }
}

TEST(Camera, FramingKeepsAGivenDirection) {
  Box box;
  box.add({0, 0, 0});
  box.add({1, 1, 1});
  const Camera given{{10, 3, 0}, {9, 3, 0}, {0, 1, 0}, 50};
  const Camera c = render::frame(box, given, 1.0);
  EXPECT_TRUE(c.target.isApprox(box.centre()));
  EXPECT_TRUE((c.eye - c.target).normalized().isApprox(Eigen::Vector3d::UnitX()));
  EXPECT_EQ(c.fov_degrees, 50);
}

TEST(Camera, OrbitTurnsAboutTheUpAxisThroughTheTarget) {
  const Camera c{{0, 1, 4}, {0, 1, 0}, {0, 1, 0}, 35};
  const Camera quarter = render::orbit(c, std::numbers::pi / 2);
  EXPECT_TRUE(quarter.eye.isApprox(Eigen::Vector3d(4, 1, 0), 1e-12));
  EXPECT_TRUE(render::orbit(c, 2 * std::numbers::pi).eye.isApprox(c.eye, 1e-12));
}

// Issue #33 item 7: a flat model seen along its plane draws nothing; the warning says so and
// names the view that sees it face-on.
TEST(Camera, AFlatBoxSeenEdgeOnIsNamed) {
  Box flat;  // a sheet in the xz-plane, as a ground quad
  flat.add({-1, 0.5, -2});
  flat.add({1, 0.5, 2});
  const Camera front = render::frame(flat, View::front, 35, 1.5), top = render::frame(flat, View::top, 35, 1.5);
  EXPECT_TRUE(render::sees_edge_on(flat, front));
  EXPECT_FALSE(render::sees_edge_on(flat, top));
  EXPECT_FALSE(render::sees_edge_on(flat, render::frame(flat, View::iso, 35, 1.5)));
  const std::string w = render::edge_on_warning(flat, std::span(&front, 1), "the view 'front'");
  EXPECT_NE(w.find("the view 'front' sees the model edge-on (it is flat along y)"), std::string::npos) << w;
  EXPECT_NE(w.find("the view 'top' sees it face-on"), std::string::npos) << w;
  EXPECT_EQ(render::edge_on_warning(flat, std::span(&top, 1), "the view 'top'"), "");
  // A turntable about y never leaves the plane: every view is edge-on. About a sheet in the
  // xy-plane, some views see it: no warning.
  const std::vector<Camera> turns = {front, render::orbit(front, std::numbers::pi / 2)};
  EXPECT_NE(render::edge_on_warning(flat, turns, "the view 'front'"), "");
  Box wall;
  wall.add({-1, 0, 0});
  wall.add({1, 2, 0});
  const Camera side = render::frame(wall, View::right, 35, 1.5);
  EXPECT_NE(render::edge_on_warning(wall, std::span(&side, 1), "v").find("'front' sees it face-on"), std::string::npos);
  const std::vector<Camera> around = {side, render::orbit(side, std::numbers::pi / 2)};
  EXPECT_EQ(render::edge_on_warning(wall, around, "v"), "");
  // A box with depth is never edge-on.
  Box solid = flat;
  solid.add({0, 1, 0});
  EXPECT_FALSE(render::sees_edge_on(solid, front));
}

TEST(Camera, BadCamerasAreRejected) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(render::validate(Camera{{1, 1, 1}, {1, 1, 1}, {0, 1, 0}, 35}), cgamesh::InvalidInputError);
  EXPECT_THROW(render::validate(Camera{{0, 5, 0}, {0, 0, 0}, {0, 1, 0}, 35}), cgamesh::InvalidInputError);
  EXPECT_THROW(render::validate(Camera{{0, 0, 5}, {0, 0, 0}, {0, 0, 0}, 35}), cgamesh::InvalidInputError);
  EXPECT_THROW(render::validate(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0}), cgamesh::InvalidInputError);
  EXPECT_THROW(render::validate(Camera{{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 180}), cgamesh::InvalidInputError);
  EXPECT_THROW(render::validate(Camera{{nan, 0, 5}, {0, 0, 0}, {0, 1, 0}, 35}), cgamesh::InvalidInputError);
  EXPECT_THROW(static_cast<void>(render::frame(Box{}, View::front, 35, 1)), cgamesh::InvalidInputError);
  EXPECT_THROW(static_cast<void>(render::parse_view("side")), cgamesh::InvalidInputError);
  EXPECT_EQ(render::parse_view("iso"), View::iso);
}

}  // namespace
