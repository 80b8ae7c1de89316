#pragma once
// A perspective look-at camera with OpenGL's conventions (right-handed view space looking down
// −z, clip space z in [−w, w]), named views, and framing a bounding box. No OpenGL here: the
// same matrices project points on the CPU (tests compare silhouettes with them).

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include <Eigen/Core>

namespace cgamesh::render {

/// An axis-aligned box; empty (lo > hi) until a point is added.
struct Box {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-1e300);

  void add(const Eigen::Vector3d& p) noexcept {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  [[nodiscard]] bool empty() const noexcept { return (lo.array() > hi.array()).any(); }
  [[nodiscard]] Eigen::Vector3d centre() const noexcept { return (lo + hi) / 2; }
  [[nodiscard]] double diagonal() const noexcept { return empty() ? 0.0 : (hi - lo).norm(); }
};

/// Eye, target and up in world space (gluLookAt), and the vertical field of view.
struct Camera {
  Eigen::Vector3d eye{0, 0, 1};
  Eigen::Vector3d target{0, 0, 0};
  Eigen::Vector3d up{0, 1, 0};
  double fov_degrees = 35;  ///< vertical field of view, in (0, 180)
};

/// Named directions to look from, world +y up (glTF's convention): `front` looks from +z down
/// −z, `back` from −z, `left` from −x, `right` from +x, `top` from +y (up = −z), `iso` from
/// (+1, +0.8, +1).
enum class View { front, back, left, right, top, iso };

/// The views by name, in the order a user meets them.
inline constexpr std::array<std::pair<std::string_view, View>, 6> kViews{{{"front", View::front},
                                                                          {"back", View::back},
                                                                          {"left", View::left},
                                                                          {"right", View::right},
                                                                          {"top", View::top},
                                                                          {"iso", View::iso}}};

/// The view named `name` (front, back, left, right, top, iso).
/// @throws InvalidInputError for another name.
[[nodiscard]] View parse_view(const std::string& name);

/// Checks a camera: finite values, eye ≠ target, up not parallel to the viewing direction, fov
/// in (0, 180) degrees.
/// @throws InvalidInputError naming the problem.
void validate(const Camera& camera);

/// A camera looking at the centre of `box` from `view` whose picture of aspect `aspect`
/// (width / height) holds the whole box with a small margin: every corner of the box projects
/// inside 92 % of the picture's half-width and half-height.
/// @throws InvalidInputError for an empty box or a non-positive aspect.
[[nodiscard]] Camera frame(const Box& box, View view, double fov_degrees, double aspect);

/// A camera looking at `box` along the direction and with the up vector of `camera` (its eye
/// and target moved), holding the box as frame(box, view, ...) does.
/// @throws InvalidInputError for an empty box, a non-positive aspect or a bad camera.
[[nodiscard]] Camera frame(const Box& box, const Camera& camera, double aspect);

/// Whether `camera` sees `box` edge-on: the box is flat along one axis (thinner than 1e-6 of its
/// diagonal: a planar model) and the eye lies in its plane, within 1e-3 of its distance to the
/// box, so the model projects to a line and draws (next to) no pixel.
[[nodiscard]] bool sees_edge_on(const Box& box, const Camera& camera);

/// Why pictures of `box` taken by `cameras` would be blank, or "": when every camera sees the
/// box edge-on (sees_edge_on), a warning that names `view` (how the user chose the cameras, e.g.
/// "the view 'front'") and the named view that looks at the box face-on.
[[nodiscard]] std::string edge_on_warning(const Box& box, std::span<const Camera> cameras, const std::string& view);

/// `camera` turned by `radians` about the axis through its target along its up vector (a
/// turntable step; positive turns the eye counter-clockwise seen from above).
[[nodiscard]] Camera orbit(const Camera& camera, double radians);

/// `camera` with its eye turned about the target: by `yaw` radians about the up vector and by
/// `pitch` radians about the camera's right axis (positive looks from higher up), the pitch
/// stopping 1° short of the up vector so the view never flips (a viewer's orbit drag).
[[nodiscard]] Camera orbit(const Camera& camera, double yaw, double pitch);

/// `camera` with eye and target moved in the view plane by (dx, dy) picture heights at the
/// target's distance (a viewer's pan drag; +x right, +y up).
[[nodiscard]] Camera pan(const Camera& camera, double dx, double dy);

/// `camera` with its eye moved towards the target, to `factor` times its distance (< 1 zooms in).
/// @throws InvalidInputError for a factor that is not positive and finite.
[[nodiscard]] Camera dolly(const Camera& camera, double factor);

/// A ray from the eye through a point of the picture.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;  ///< unit length
};

/// The ray from the eye of `camera` through the picture point (x, y) in pixels of a picture
/// `width` × `height` (x right, y down from the top-left corner, pixel centres at +0.5).
[[nodiscard]] Ray pixel_ray(const Camera& camera, int width, int height, double x, double y);

/// The world → view matrix of `camera` (gluLookAt).
[[nodiscard]] Eigen::Matrix4d view_matrix(const Camera& camera);

/// The view → clip matrix (gluPerspective) for `aspect` = width / height and depths near < far.
[[nodiscard]] Eigen::Matrix4d projection_matrix(const Camera& camera, double aspect, double near, double far);

/// Near and far depths that enclose `box` seen from `camera` (near > 0).
void depth_range(const Camera& camera, const Box& box, double& near, double& far);

}  // namespace cgamesh::render
