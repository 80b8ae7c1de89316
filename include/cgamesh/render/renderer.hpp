#pragma once
// The OpenGL 3.3 core renderer: draws a Scene seen by a Camera into the current framebuffer, or
// into an off-screen multisampled framebuffer that is read back as an Image. It needs a current
// OpenGL context (headless_context.hpp, or the viewer's window); functions are loaded with
// libepoxy, which serves GLX and EGL alike.

#include <memory>

#include <Eigen/Core>

#include "cgamesh/render/camera.hpp"
#include "cgamesh/render/image.hpp"
#include "cgamesh/render/scene.hpp"

namespace cgamesh::render {

/// How a picture is drawn.
struct RenderOptions {
  int width = 1280;
  int height = 960;
  Eigen::Vector3f background{1, 1, 1};
  bool wireframe = false;  ///< triangle edges drawn over the shading
  Eigen::Vector3f wire_color{0.1f, 0.1f, 0.12f};
  /// Back faces (the inside seen through a hole or an open cut) are mixed with this colour.
  Eigen::Vector3f back_face_color{0.85f, 0.25f, 0.2f};
  float ambient = 0.3f;  ///< ambient light; the key light (from above, left and behind the eye) adds the rest
  int samples = 4;       ///< multisampling of off-screen pictures (1: none)
};

/// Checks width and height (1 … kMaxImageSide, image.hpp) and samples (1 … 16).
/// @throws InvalidInputError naming the problem.
void validate(const RenderOptions& options);

class Renderer {
 public:
  /// Compiles the shaders in the current context.
  /// @throws PlatformError when no context is current or it is older than OpenGL 3.3.
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Draws `scene` into the currently bound framebuffer over a viewport of
  /// options.width × options.height (clears it to the background first).
  /// @throws InvalidInputError for a mesh whose attribute rows do not match its vertices or
  ///         a face index out of range, or a bad camera or options.
  void draw(const Scene& scene, const Camera& camera, const RenderOptions& options);

  /// Draws off-screen and reads the picture back.
  /// @throws as draw(); PlatformError when the framebuffer cannot be made (too large for the
  ///         driver).
  [[nodiscard]] Image render(const Scene& scene, const Camera& camera, const RenderOptions& options);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace cgamesh::render
