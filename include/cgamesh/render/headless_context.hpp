#pragma once
// An OpenGL 3.3 core context without a window or display server: EGL on Mesa's surfaceless
// platform (EGL_PLATFORM_SURFACELESS_MESA; llvmpipe on a machine without a GPU, the GPU's
// driver otherwise), falling back to the default EGL display. Render into a framebuffer object.

#include <memory>
#include <string>

namespace cgamesh::render {

class HeadlessContext {
 public:
  /// Creates the context and makes it current on this thread.
  /// @throws PlatformError naming the step that failed (no EGL display, eglInitialize,
  ///         eglBindAPI, no OpenGL 3.3 core context, eglMakeCurrent).
  HeadlessContext();
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;

  /// GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa".
  [[nodiscard]] std::string description() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace cgamesh::render
