#pragma once
// The viewer's window: a GLFW window with an OpenGL 3.3 core context, the model drawn by
// render::Renderer, a Dear ImGui panel, mouse tools, and scripts run one action per frame. The
// model's state and every operation live in session::Session; this file only maps input to it.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cgamesh/deform/bound_deformer.hpp"
#include "cgamesh/render/camera.hpp"
#include "cgamesh/render/model_scene.hpp"
#include "cgamesh/render/renderer.hpp"
#include "cgamesh/session/script.hpp"
#include "cgamesh/session/session.hpp"

namespace cgamesh::viewer {

struct ViewerOptions {
  int width = 1280;  ///< window size in screen coordinates
  int height = 800;
  std::string title = "cgamesh";
  std::string model_path;  ///< shown in the panel; the MODEL of logged commands
  render::View view = render::View::front;
  render::ModelSceneOptions scene;
  std::vector<session::ScriptAction> script;  ///< run one per frame; the window closes after the last
  bool json = false;                          ///< log each operation as one JSON line on stdout (else as text)
  std::optional<deform::DeformSpec> spec;     ///< a deformation spec to preview and apply (--spec)
  std::string spec_path;
};

/// Opens the window, runs until it is closed (or the script quits) and closes it.
/// @throws PlatformError when there is no display or no OpenGL 3.3 context; what a script
///         action throws, its message prefixed with "SCRIPT:LINE: ".
void run_viewer(session::Session& session, const ViewerOptions& options, const std::string& script_name);

}  // namespace cgamesh::viewer
