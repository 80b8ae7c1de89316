#include "cgamesh/render/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "cgamesh/errors.hpp"

namespace cgamesh::render {
namespace {

struct ViewDirection {
  Eigen::Vector3d from;  ///< direction from the target to the eye
  Eigen::Vector3d up;
};

ViewDirection direction(View view) {
  switch (view) {
    case View::front:
      return {{0, 0, 1}, {0, 1, 0}};
    case View::back:
      return {{0, 0, -1}, {0, 1, 0}};
    case View::left:
      return {{-1, 0, 0}, {0, 1, 0}};
    case View::right:
      return {{1, 0, 0}, {0, 1, 0}};
    case View::top:
      return {{0, 1, 0}, {0, 0, -1}};
    case View::iso:
      return {Eigen::Vector3d(1, 0.8, 1).normalized(), {0, 1, 0}};
  }
  return {{0, 0, 1}, {0, 1, 0}};
}

/// The one axis along which `box` is flat (thinner than 1e-6 of its diagonal), or -1 (none, or
/// a box flat along more than one: a line or a point, which no view shows).
int flat_axis(const Box& box) {
  if (box.empty()) return -1;
  const Eigen::Vector3d size = box.hi - box.lo;
  int axis = -1, count = 0;
  for (int a = 0; a < 3; ++a)
    if (size[a] <= 1e-6 * size.norm()) {
      axis = a;
      ++count;
    }
  return count == 1 ? axis : -1;
}

}  // namespace

bool sees_edge_on(const Box& box, const Camera& camera) {
  const int a = flat_axis(box);
  if (a < 0) return false;
  const double plane = box.centre()[a];
  return std::abs(camera.eye[a] - plane) <= 1e-3 * (camera.eye - box.centre()).norm();
}

std::string edge_on_warning(const Box& box, std::span<const Camera> cameras, const std::string& view) {
  if (cameras.empty() ||
      !std::all_of(cameras.begin(), cameras.end(), [&](const Camera& c) { return sees_edge_on(box, c); }))
    return "";
  const int a = flat_axis(box);
  static constexpr const char* kAxis[] = {"x", "y", "z"};
  static constexpr const char* kFaceOn[] = {"right", "top", "front"};  // views along +x, +y, +z
  return view + " sees the model edge-on (it is flat along " + kAxis[a] +
         "), so the picture shows next to nothing; the view '" + kFaceOn[a] + "' sees it face-on";
}

View parse_view(const std::string& name) {
  for (const auto& [text, view] : kViews)
    if (name == text) return view;
  throw InvalidInputError("view '" + name + "': expected front, back, left, right, top or iso");
}

void validate(const Camera& c) {
  if (!c.eye.allFinite() || !c.target.allFinite() || !c.up.allFinite() || !std::isfinite(c.fov_degrees))
    throw InvalidInputError("camera: every value must be finite");
  const Eigen::Vector3d d = c.target - c.eye;
  if (!(d.norm() > 0)) throw InvalidInputError("camera: the eye and the target are the same point");
  if (!(c.up.norm() > 0)) throw InvalidInputError("camera: the up vector is zero");
  if (!(d.normalized().cross(c.up.normalized()).norm() > 1e-6))
    throw InvalidInputError("camera: the up vector is parallel to the viewing direction");
  if (!(c.fov_degrees > 0 && c.fov_degrees < 180))
    throw InvalidInputError("camera: the field of view must be in (0, 180) degrees, got " +
                            std::to_string(c.fov_degrees));
}

Camera frame(const Box& box, const Camera& camera, double aspect) {
  validate(camera);
  if (box.empty() || !box.lo.allFinite() || !box.hi.allFinite()) throw InvalidInputError("frame: the box is empty");
  if (!(aspect > 0) || !std::isfinite(aspect)) throw InvalidInputError("frame: the aspect must be > 0");
  const double tan_v = std::tan(camera.fov_degrees * std::numbers::pi / 360.0), tan_h = tan_v * aspect;
  // The eye backs off along the viewing direction until every corner of the box lies inside
  // 92 % of both half-angles.
  const Eigen::Vector3d back = (camera.eye - camera.target).normalized();
  const Eigen::Vector3d side = camera.up.cross(back).normalized(), up = back.cross(side);
  const Eigen::Vector3d c = box.centre();
  double distance = 1e-9;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner((k & 1) ? box.hi.x() : box.lo.x(), (k & 2) ? box.hi.y() : box.lo.y(),
                                 (k & 4) ? box.hi.z() : box.lo.z());
    const Eigen::Vector3d d = corner - c;
    const double toward = d.dot(back);
    distance = std::max(
        {distance, toward + std::abs(d.dot(side)) / (0.92 * tan_h), toward + std::abs(d.dot(up)) / (0.92 * tan_v)});
  }
  // Never inside the box.
  distance = std::max(distance, 1.05 * box.diagonal() / 2);
  return {c + distance * back, c, camera.up, camera.fov_degrees};
}

Camera frame(const Box& box, View view, double fov_degrees, double aspect) {
  const ViewDirection dir = direction(view);
  return frame(box, Camera{dir.from, Eigen::Vector3d::Zero(), dir.up, fov_degrees}, aspect);
}

Camera orbit(const Camera& camera, double radians) {
  const Eigen::AngleAxisd turn(radians, camera.up.normalized());
  Camera out = camera;
  out.eye = camera.target + turn * (camera.eye - camera.target);
  return out;
}

Camera orbit(const Camera& c, double yaw, double pitch) {
  const Eigen::Vector3d up = c.up.normalized();
  Eigen::Vector3d offset = Eigen::AngleAxisd(yaw, up) * (c.eye - c.target);
  const double elevation = std::asin(std::clamp(offset.normalized().dot(up), -1.0, 1.0));
  const double limit = std::numbers::pi / 2 - std::numbers::pi / 180;
  const double turn = std::clamp(elevation + pitch, -limit, limit) - elevation;
  const Eigen::Vector3d right = up.cross(offset).normalized();
  offset = Eigen::AngleAxisd(-turn, right) * offset;
  Camera out = c;
  out.eye = c.target + offset;
  return out;
}

Camera pan(const Camera& c, double dx, double dy) {
  const Eigen::Vector3d f = (c.target - c.eye).normalized();
  const Eigen::Vector3d s = f.cross(c.up).normalized();
  const Eigen::Vector3d u = s.cross(f);
  const double height = 2 * (c.target - c.eye).norm() * std::tan(c.fov_degrees * std::numbers::pi / 360.0);
  const Eigen::Vector3d move = (dx * s + dy * u) * height;
  Camera out = c;
  out.eye += move;
  out.target += move;
  return out;
}

Camera dolly(const Camera& c, double factor) {
  if (!(factor > 0 && std::isfinite(factor))) throw InvalidInputError("dolly: the factor must be positive and finite");
  Camera out = c;
  out.eye = c.target + (c.eye - c.target) * factor;
  return out;
}

Ray pixel_ray(const Camera& c, int width, int height, double x, double y) {
  const Eigen::Vector3d f = (c.target - c.eye).normalized();
  const Eigen::Vector3d s = f.cross(c.up).normalized();
  const Eigen::Vector3d u = s.cross(f);
  const double t = std::tan(c.fov_degrees * std::numbers::pi / 360.0);
  const double aspect = static_cast<double>(width) / std::max(height, 1);
  const double nx = 2 * x / std::max(width, 1) - 1, ny = 1 - 2 * y / std::max(height, 1);
  return {c.eye, (f + s * (nx * t * aspect) + u * (ny * t)).normalized()};
}

Eigen::Matrix4d view_matrix(const Camera& c) {
  const Eigen::Vector3d f = (c.target - c.eye).normalized();
  const Eigen::Vector3d s = f.cross(c.up).normalized();
  const Eigen::Vector3d u = s.cross(f);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.row(0).head<3>() = s;
  m.row(1).head<3>() = u;
  m.row(2).head<3>() = -f;
  m(0, 3) = -s.dot(c.eye);
  m(1, 3) = -u.dot(c.eye);
  m(2, 3) = f.dot(c.eye);
  return m;
}

Eigen::Matrix4d projection_matrix(const Camera& c, double aspect, double near, double far) {
  const double t = 1.0 / std::tan(c.fov_degrees * std::numbers::pi / 360.0);
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = t / aspect;
  m(1, 1) = t;
  m(2, 2) = (far + near) / (near - far);
  m(2, 3) = 2 * far * near / (near - far);
  m(3, 2) = -1;
  return m;
}

void depth_range(const Camera& c, const Box& box, double& near, double& far) {
  const Eigen::Vector3d f = (c.target - c.eye).normalized();
  if (box.empty()) {
    near = 0.01;
    far = 100;
    return;
  }
  const double centre = f.dot(box.centre() - c.eye), radius = box.diagonal() / 2;
  far = std::max(centre + radius * 1.01, 1e-6);
  // Near as far out as the box allows, but keep 1e-4 of far for depth precision.
  near = std::max(centre - radius * 1.01, far * 1e-4);
}

}  // namespace cgamesh::render
