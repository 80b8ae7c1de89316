#include "cgamesh/render/headless_context.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <sstream>

#include "cgamesh/errors.hpp"

namespace cgamesh::render {
namespace {

std::string egl_error() {
  std::ostringstream s;
  s << "EGL error 0x" << std::hex << eglGetError();
  return s.str();
}

bool has_extension(const char* list, const std::string& name) {
  if (!list) return false;
  std::istringstream words(list);
  for (std::string w; words >> w;)
    if (w == name) return true;
  return false;
}

}  // namespace

struct HeadlessContext::State {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;

  // The display stays initialised: an EGL display is one per process, shared by every context
  // made on it, and eglTerminate would unload the driver that the next context loads again.
  ~State() {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
  }
};

HeadlessContext::HeadlessContext() : state_(std::make_unique<State>()) {
  const std::string fix =
      " (headless rendering needs EGL with Mesa's surfaceless platform or a GPU driver: "
      "Debian packages libegl1 libegl-mesa0 libgl1-mesa-dri)";
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (has_extension(client, "EGL_MESA_platform_surfaceless"))
    state_->display = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (state_->display == EGL_NO_DISPLAY) state_->display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  if (state_->display == EGL_NO_DISPLAY) throw PlatformError("no EGL display" + fix);
  EGLint major = 0, minor = 0;
  if (!eglInitialize(state_->display, &major, &minor)) {
    state_->display = EGL_NO_DISPLAY;
    throw PlatformError("eglInitialize failed: " + egl_error() + fix);
  }
  if (!eglBindAPI(EGL_OPENGL_API)) throw PlatformError("eglBindAPI(EGL_OPENGL_API) failed: " + egl_error() + fix);
  const char* display_extensions = eglQueryString(state_->display, EGL_EXTENSIONS);
  EGLConfig config = nullptr;
  if (!has_extension(display_extensions, "EGL_KHR_no_config_context")) {
    const EGLint attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(state_->display, attributes, &config, 1, &count) || count < 1)
      throw PlatformError("no EGL config for desktop OpenGL: " + egl_error() + fix);
  }
  const EGLint context_attributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  state_->context = eglCreateContext(state_->display, config, EGL_NO_CONTEXT, context_attributes);
  if (state_->context == EGL_NO_CONTEXT) throw PlatformError("no OpenGL 3.3 core context: " + egl_error() + fix);
  if (!has_extension(display_extensions, "EGL_KHR_surfaceless_context"))
    throw PlatformError(
        "the EGL display cannot make a context current without a surface (EGL_KHR_surfaceless_context)" + fix);
  if (!eglMakeCurrent(state_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, state_->context))
    throw PlatformError("eglMakeCurrent failed: " + egl_error() + fix);
}

HeadlessContext::~HeadlessContext() = default;

std::string HeadlessContext::description() const {
  const auto text = [](GLenum name) {
    const auto* s = reinterpret_cast<const char*>(glGetString(name));
    return std::string(s ? s : "?");
  };
  return text(GL_RENDERER) + ", OpenGL " + text(GL_VERSION);
}

}  // namespace cgamesh::render
