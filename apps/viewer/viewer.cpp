#include "viewer.hpp"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <functional>
#include <iostream>
#include <map>
#include <numbers>
#include <set>
#include <span>
#include <utility>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <nlohmann/json.hpp>
#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

#include "cgamesh/errors.hpp"
#include "cgamesh/io/text_values.hpp"
#include "cgamesh/render/image.hpp"

namespace cgamesh::viewer {
namespace {

using Clock = std::chrono::steady_clock;
using Vec3 = Eigen::Vector3d;

/// The window, its OpenGL context and Dear ImGui, torn down in reverse order.
class Window {
 public:
  explicit Window(const ViewerOptions& options);
  ~Window() { close(); }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;
  [[nodiscard]] GLFWwindow* handle() const noexcept { return window_; }

 private:
  void close() noexcept;
  GLFWwindow* window_ = nullptr;
  bool imgui_ = false, glfw_imgui_ = false, gl_imgui_ = false;
};

std::string glfw_error;

void on_glfw_error(int, const char* description) { glfw_error = description; }

Window::Window(const ViewerOptions& options) {
  glfwSetErrorCallback(on_glfw_error);
  if (glfwInit() != GLFW_TRUE)
    throw PlatformError("no display to open a window on (" + glfw_error +
                        "); to make pictures without a display, use `cgamesh render`");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  window_ = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
  if (window_ == nullptr) {
    glfwTerminate();
    throw PlatformError("cannot open an OpenGL 3.3 core window (" + glfw_error +
                        "); to make pictures without one, use `cgamesh render`");
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(options.script.empty() ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  imgui_ = true;
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the user's files
  ImGui::StyleColorsDark();
  glfw_imgui_ = ImGui_ImplGlfw_InitForOpenGL(window_, true);
  gl_imgui_ = ImGui_ImplOpenGL3_Init("#version 330 core");
  if (!glfw_imgui_ || !gl_imgui_) {
    close();
    throw PlatformError("Dear ImGui could not start on this OpenGL context");
  }
}

void Window::close() noexcept {
  if (gl_imgui_) ImGui_ImplOpenGL3_Shutdown();
  if (glfw_imgui_) ImGui_ImplGlfw_Shutdown();
  if (imgui_) ImGui::DestroyContext();
  gl_imgui_ = glfw_imgui_ = imgui_ = false;
  if (window_ != nullptr) {
#if defined(__SANITIZE_ADDRESS__)
    // The OpenGL driver keeps allocations for the life of the process in libraries that
    // closing the window unloads; LeakSanitizer could then neither name nor suppress them,
    // so the leak check runs here, while they are loaded.
    __lsan_do_leak_check();
#endif
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  window_ = nullptr;
}

enum class Tool { camera, joint, cut, tear, drill };

/// A drag of the mouse in window pixels.
struct Drag {
  int button = -1;
  Eigen::Vector2d start, last;
  bool moved = false;
};

/// Circle of `n` points of radius r around `centre` in the plane ⟂ `axis`.
std::vector<Eigen::Vector3f> circle(const Vec3& centre, const Vec3& axis, double r, int n) {
  const Vec3 a = axis.normalized();
  const Vec3 u = a.unitOrthogonal(), v = a.cross(u);
  std::vector<Eigen::Vector3f> out;
  for (int i = 0; i < n; ++i) {
    const double t0 = 2 * std::numbers::pi * i / n, t1 = 2 * std::numbers::pi * (i + 1) / n;
    out.push_back((centre + r * (std::cos(t0) * u + std::sin(t0) * v)).cast<float>());
    out.push_back((centre + r * (std::cos(t1) * u + std::sin(t1) * v)).cast<float>());
  }
  return out;
}

/// The viewer: one session, a camera, the tools and the panel. Per frame:
///  1. input: the next script action, or the mouse and keys (tools, camera);
///  2. animation: the time advances while playing;
///  3. the scene: the model in the session's pose, and the tools' previews;
///  4. drawing: the scene, then the panel; a screenshot renders the scene off-screen.
class Viewer {
 public:
  Viewer(session::Session& session, const ViewerOptions& options, const std::string& script_name);
  void run();

 private:
  void frame_all();
  void script_step();
  void run_action(const session::ScriptAction& a);
  void continue_action();
  void mouse();
  void press(const Eigen::Vector2d& at);
  void move(const Eigen::Vector2d& at);
  void release(const Eigen::Vector2d& at);
  void stroke_to(const Eigen::Vector2d& at);
  [[nodiscard]] render::Ray ray(const Eigen::Vector2d& at) const;
  void advance(double seconds);
  [[nodiscard]] render::Scene scene() const;
  void panel();
  void joint_tree(int joint, const std::vector<std::vector<int>>& children);
  void apply_cut();
  void apply_drill();
  void bind_spec();
  [[nodiscard]] std::vector<cga::Versor<double>> deform_keys() const;
  void update_preview();
  void apply_deformation();
  void deformation_panel();
  void morph_panel();
  void tissue_panel();
  void step_tissue(double seconds);
  void log(const session::OperationReport& r);
  void failed(const std::string& what);
  void screenshot(const std::string& path) const;
  void read_window(const std::string& path) const;
  void save(const std::string& path);
  template <class F>
  void guarded(const std::string& what, F&& f);

  session::Session& session_;
  ViewerOptions options_;
  std::string script_name_;
  Window window_;
  std::unique_ptr<render::Renderer> renderer_;
  render::Camera camera_;
  render::RenderOptions render_options_;
  int fb_width_ = 1, fb_height_ = 1, win_width_ = 1, win_height_ = 1;
  bool playing_ = false;
  double speed_ = 1;
  double frame_ms_ = 0, fps_ = 0;
  Tool tool_ = Tool::camera;
  std::optional<Drag> drag_;
  int joint_ = -1;  ///< selected joint
  // Cut: the plane n·x = d through a picked point.
  std::optional<Vec3> cut_point_;
  Vec3 cut_normal_ = Vec3::UnitX();
  bool cap_ = false;
  // Tear.
  double open_ = 0;                                 ///< opening width of a tear (model units)
  double blade_depth_ = 0.03, step_length_ = 0.02;  ///< in model sizes
  std::optional<Vec3> last_blade_point_;
  // Drill.
  std::optional<session::Pick> drill_at_;
  double radius_ = 0.02, depth_ = 0.15;  ///< in model sizes
  bool wall_ = false, drill_along_view_ = false;
  Vec3 drill_view_ = -Vec3::UnitZ();
  // Deformation (--spec): the bound deformer, its keys as the sliders set them, and the model
  // with the deformed rest shape drawn instead of the session's while previewing.
  std::optional<deform::BoundDeformer> deformer_;
  std::vector<deform::KeyTransform> keys_;
  bool preview_on_ = true, preview_dirty_ = true;
  std::optional<anim::RiggedModel> preview_;
  std::vector<Eigen::Vector3f> handle_points_;
  // ffd, cage: the other control points and the lattice's or cage's edges, in the spec's space
  // (world: the bind pose), where the keys put them.
  std::vector<Eigen::Vector3f> free_control_points_, control_lines_;
  // Living tissue: the options its sliders set, and the time of the last step.
  soft::TissueOptions tissue_options_;
  double tissue_ms_ = 0;
  std::deque<std::string> log_;
  std::string status_;
  // Script.
  std::size_t next_action_ = 0;
  const session::ScriptAction* current_ = nullptr;
  int frames_left_ = 0;  ///< frames an action (play, wait, drag) still takes
  double play_to_ = 0;
  std::vector<Eigen::Vector2d> drag_points_;
  std::size_t drag_index_ = 0;
  bool quit_ = false;
  std::string window_shot_;  ///< a picture of the whole window, panel included, to take this frame
  std::array<char, 512> save_path_{};
  std::array<char, 32> clip_name_{};
};

Viewer::Viewer(session::Session& session, const ViewerOptions& options, const std::string& script_name)
    : session_(session), options_(options), script_name_(script_name), window_(options) {
  renderer_ = std::make_unique<render::Renderer>();
  if (options_.spec) {
    keys_ = options_.spec->keys;
    bind_spec();
  }
  glfwGetFramebufferSize(window_.handle(), &fb_width_, &fb_height_);
  glfwGetWindowSize(window_.handle(), &win_width_, &win_height_);
  frame_all();
  std::snprintf(save_path_.data(), save_path_.size(), "%s", "edited.glb");
  std::snprintf(clip_name_.data(), clip_name_.size(), "%s", "generated");
}

void Viewer::frame_all() {
  const render::Box box = scene().bounds();
  if (box.empty()) return;
  camera_ =
      render::frame(box, options_.view, camera_.fov_degrees, static_cast<double>(fb_width_) / std::max(fb_height_, 1));
}

template <class F>
void Viewer::guarded(const std::string& what, F&& f) {
  if (!options_.script.empty()) {
    f();  // a script stops at its first failure
    return;
  }
  try {
    f();
  } catch (const Error& e) {
    failed(what + ": " + e.what());
  }
}

void Viewer::failed(const std::string& what) {
  status_ = what;
  std::cerr << "cgamesh: " << what << "\n";
}

void Viewer::log(const session::OperationReport& r) {
  char line[160];
  std::snprintf(line, sizeof line, "%s: %.3f ms (placing %.1f ms), %d faces", r.kind.c_str(), r.milliseconds,
                r.placement_milliseconds, r.faces);
  log_.emplace_front(line);
  if (log_.size() > 12) log_.pop_back();
  status_.clear();
  for (const std::string& w : r.warnings) std::cerr << "cgamesh: warning: " << w << "\n";
  if (r.kind == "tear step") return;  // the stroke's tear is logged when it ends
  const std::string& command = r.command;
  if (options_.json) {
    std::cout << nlohmann::json{{"operation", r.kind},
                                {"milliseconds", r.milliseconds},
                                {"placement_milliseconds", r.placement_milliseconds},
                                {"faces", r.faces},
                                {"command", "cgamesh " + command},
                                {"warnings", r.warnings}}
                     .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)
              << std::endl;
  } else {
    std::cout << line << "\n  cgamesh " << command << std::endl;
  }
}

render::Ray Viewer::ray(const Eigen::Vector2d& at) const {
  // Mouse positions are in screen coordinates; the picture is in framebuffer pixels.
  const double sx = static_cast<double>(fb_width_) / std::max(win_width_, 1);
  const double sy = static_cast<double>(fb_height_) / std::max(win_height_, 1);
  return render::pixel_ray(camera_, fb_width_, fb_height_, at.x() * sx, at.y() * sy);
}

// ---- Script ----

void Viewer::script_step() {
  if (frames_left_ == 0) {
    if (next_action_ >= options_.script.size()) {
      quit_ = true;
      return;
    }
    current_ = &options_.script[next_action_++];
  }
  try {
    if (frames_left_ == 0) {
      run_action(*current_);
    } else {
      continue_action();
    }
  } catch (...) {
    rethrow_with_context(script_name_ + ":" + std::to_string(current_->line) + ": " + current_->verb + ": ");
  }
}

void Viewer::continue_action() {
  --frames_left_;
  if (!drag_points_.empty()) {
    const Eigen::Vector2d p = drag_points_[drag_index_++];
    if (drag_index_ == 1) {
      press(p);
      if (!session_.stroking())
        throw TopologyError("the first point " + io::number(p.x()) + "," + io::number(p.y()) + " is not on the model");
    }
    move(p);
    if (drag_index_ == drag_points_.size()) {
      release(p);
      drag_points_.clear();
    }
  } else if (playing_) {
    session_.set_time(frames_left_ == 0 ? play_to_ : std::min(session_.time() + 1.0 / 30, play_to_));
    playing_ = frames_left_ > 0;
  }
}

void Viewer::run_action(const session::ScriptAction& a) {
  if (session::is_session_action(a.verb)) {
    if (const auto r = session::apply(session_, a)) log(*r);
    if (a.verb == "tear") open_ = a.open;
  } else if (a.verb == "play") {
    // At 30 frames per second of model time, whatever the machine's frame rate: scripts replay alike.
    const double t = a.numbers[0];
    if (t <= session_.time()) {
      session_.set_time(t);
      return;
    }
    play_to_ = t;
    playing_ = true;
    frames_left_ = static_cast<int>(std::ceil((t - session_.time()) * 30));
  } else if (a.verb == "skinning") {
    options_.scene.skinning = io::kSkinningModes.at(a.text);
  } else if (a.verb == "color") {
    options_.scene.color = render::parse_color_mode(a.text, options_.scene.joint);
  } else if (a.verb == "view") {
    options_.view = render::parse_view(a.text);
    frame_all();
  } else if (a.verb == "explode") {
    options_.scene.explode = a.numbers[0];
  } else if (a.verb == "wait") {
    frames_left_ = static_cast<int>(a.numbers[0]);
  } else if (a.verb == "drag") {
    tool_ = Tool::tear;
    open_ = a.open;
    drag_points_ = a.points;
    drag_index_ = 0;
    frames_left_ = static_cast<int>(a.points.size());
  } else if (a.verb == "save") {
    session_.save(a.text, options_.scene.skinning);
  } else if (a.verb == "screenshot" && a.flag) {
    window_shot_ = a.text;  // after the panel is drawn
  } else if (a.verb == "screenshot") {
    screenshot(a.text);
  } else if (a.verb == "deform") {
    if (!options_.spec) throw InvalidInputError("there is no deformation spec (give --spec)");
    apply_deformation();
  } else if (a.verb == "quit") {
    quit_ = true;
  }
}

// ---- Mouse ----

void Viewer::mouse() {
  ImGuiIO& io = ImGui::GetIO();
  double x = 0, y = 0;
  glfwGetCursorPos(window_.handle(), &x, &y);
  const Eigen::Vector2d at(x, y);
  if (!io.WantCaptureMouse && io.MouseWheel != 0) camera_ = render::dolly(camera_, std::pow(0.9, io.MouseWheel));
  for (int b = 0; b < 3; ++b) {
    if (ImGui::IsMouseClicked(b) && !io.WantCaptureMouse && !drag_) {
      drag_ = Drag{b, at, at, false};
      if (b == 0 && tool_ != Tool::camera) press(at);
    }
  }
  if (!drag_) return;
  const Eigen::Vector2d delta = at - drag_->last;
  if ((at - drag_->start).norm() > 3) drag_->moved = true;
  const bool shift = io.KeyShift;
  const bool orbiting = (drag_->button == 1 && !shift) || (drag_->button == 0 && tool_ == Tool::camera);
  const bool panning = drag_->button == 2 || (drag_->button == 1 && shift);
  if (orbiting && delta.norm() > 0) {
    camera_ = render::orbit(camera_, -delta.x() * 0.01, delta.y() * 0.01);
  } else if (panning && delta.norm() > 0) {
    camera_ = render::pan(camera_, -delta.x() / std::max(win_height_, 1), delta.y() / std::max(win_height_, 1));
  } else if (drag_->button == 0 && tool_ != Tool::camera && delta.norm() > 0) {
    move(at);
  }
  drag_->last = at;
  if (!ImGui::IsMouseDown(drag_->button)) {
    if (drag_->button == 0 && tool_ != Tool::camera) release(at);
    drag_.reset();
  }
}

void Viewer::press(const Eigen::Vector2d& at) {
  const render::Ray r = ray(at);
  guarded("pick", [&] {
    const std::optional<session::Pick> hit = session_.pick(r.origin, r.direction);
    switch (tool_) {
      case Tool::joint:
        if (hit && hit->joint >= 0) joint_ = hit->joint;
        break;
      case Tool::cut:
        if (!hit) return;
        cut_point_ = hit->point;
        cut_normal_ = -r.direction;  // facing the camera until a drag turns it
        break;
      case Tool::tear:
        if (!hit) return;
        session_.begin_stroke();
        last_blade_point_ = hit->point;
        if (auto s = session_.stroke_step(session::Session::blade(*hit, r.direction, blade_depth_ * session_.size())))
          log(*s);
        break;
      case Tool::drill:
        if (!hit) return;
        drill_at_ = hit;
        drill_view_ = r.direction;
        break;
      case Tool::camera:
        break;
    }
  });
}

void Viewer::move(const Eigen::Vector2d& at) {
  if (tool_ == Tool::cut && cut_point_ && drag_ && drag_->moved) {
    // The plane through the picked point that holds the view ray and the dragged line.
    const render::Ray r0 = ray(drag_->start), r1 = ray(at);
    const double depth = (*cut_point_ - r0.origin).norm();
    if (const auto n = session::Session::cut_normal(*cut_point_, r0.direction, r1.origin + r1.direction * depth))
      cut_normal_ = *n;
  } else if (tool_ == Tool::tear && session_.stroking()) {
    stroke_to(at);
  }
}

void Viewer::stroke_to(const Eigen::Vector2d& at) {
  const render::Ray r = ray(at);
  guarded("tear", [&] {
    const std::optional<session::Pick> hit = session_.pick(r.origin, r.direction);
    if (!hit) return;
    const double size = session_.size();
    if (last_blade_point_ && (hit->point - *last_blade_point_).norm() < step_length_ * size) return;
    std::string error;
    if (auto s = session_.stroke_step(session::Session::blade(*hit, r.direction, blade_depth_ * size), &error)) {
      last_blade_point_ = hit->point;
      log(*s);
    } else if (!error.empty()) {
      status_ = "tear step dropped: " + error;
      std::cerr << "cgamesh: warning: " << status_ << "\n";
    }
  });
}

void Viewer::release(const Eigen::Vector2d& at) {
  if (tool_ != Tool::tear || !session_.stroking()) return;
  stroke_to(at);
  last_blade_point_.reset();
  surgery::TearOptions o;
  o.open = open_;
  const auto end = [&] {
    if (const auto r = session_.end_stroke(o)) log(*r);
  };
  guarded("tear", end);
}

void Viewer::apply_cut() {
  if (!cut_point_) return;
  surgery::CutOptions o;
  o.cap = cap_;
  guarded("cut", [&] {
    log(session_.cut(cut_normal_, cut_normal_.dot(*cut_point_), o));
    cut_point_.reset();
  });
}

void Viewer::apply_drill() {
  if (!drill_at_) return;
  const double size = session_.size();
  const auto [axis, base, tip] = session::Session::drill_axis(*drill_at_, drill_view_, drill_along_view_, depth_ * size);
  surgery::DrillOptions o;
  o.wall = wall_;
  guarded("drill", [&] {
    log(session_.drill(tip, base, radius_ * size, o));
    drill_at_.reset();
  });
}

void Viewer::advance(double seconds) {
  if (!playing_ || !options_.script.empty() || session_.stroking()) return;
  const double d = session_.duration();
  if (d <= 0) {
    playing_ = false;
    return;
  }
  session_.set_time(std::fmod(session_.time() + seconds * speed_, d));
}

// ---- Deformation ----

void Viewer::bind_spec() {
  deformer_.reset();
  preview_.reset();
  const auto bind = [&] { deformer_.emplace(*options_.spec, session_.model()); };
  guarded("bind " + options_.spec_path, bind);
  preview_dirty_ = true;
}

std::vector<cga::Versor<double>> Viewer::deform_keys() const {
  // An IK chain's keys are FABRIK's motors; key transforms come from the sliders.
  if (deformer_->ik()) return deformer_->keys();
  std::vector<cga::Versor<double>> out;
  for (const deform::KeyTransform& k : keys_) out.push_back(k.versor());
  return out;
}

void Viewer::update_preview() {
  if (!deformer_) return;
  const mesh::Mesh& m = session_.model().meshes[static_cast<std::size_t>(deformer_->mesh_index())];
  if (m.vertex_count() != deformer_->vertex_count()) {  // surgery changed the mesh
    deformer_.reset();
    preview_.reset();
    status_ = "the model changed since the spec was bound: bind it again";
    return;
  }
  if (!preview_on_) {
    preview_.reset();
    return;
  }
  guarded("deform", [&] {
    if (preview_dirty_ || !preview_) {
      preview_ = deformer_->deformed_model(session_.model(), deformer_->apply(deform_keys()));
      preview_dirty_ = false;
    }
    const mesh::RowMatrixXf<3> placed = io::posed_positions(
        *preview_, session_.pose(), options_.scene.skinning)[static_cast<std::size_t>(deformer_->mesh_index())];
    handle_points_.clear();
    for (const std::vector<int>& h : deformer_->handles())
      for (const int v : h) handle_points_.push_back(placed.row(v).transpose());
    const std::vector<Eigen::Vector3d> control = deformer_->control_points(deform_keys());
    std::vector<char> selected(control.size(), 0);
    for (const std::vector<int>& h : deformer_->control_handles())
      for (const int c : h) selected[static_cast<std::size_t>(c)] = 1;
    free_control_points_.clear();
    for (std::size_t c = 0; c < control.size(); ++c)
      (selected[c] ? handle_points_ : free_control_points_).push_back(control[c].cast<float>());
    control_lines_.clear();
    for (const auto& [a, b] : deformer_->control_edges()) {
      control_lines_.push_back(control[static_cast<std::size_t>(a)].cast<float>());
      control_lines_.push_back(control[static_cast<std::size_t>(b)].cast<float>());
    }
  });
}

void Viewer::apply_deformation() {
  if (!deformer_) throw InvalidInputError("the spec is not bound to this model (bind it again)");
  log(session_.deform(*deformer_, deform_keys(), options_.spec_path));
  // The rest shape changed: what was bound belongs to the shape before.
  deformer_.reset();
  preview_.reset();
}

void Viewer::deformation_panel() {
  if (!options_.spec || !ImGui::CollapsingHeader("Deformation", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::TextWrapped("%s", options_.spec_path.c_str());
  if (!deformer_) {
    if (ImGui::Button("Bind the spec to the model")) bind_spec();
    return;
  }
  if (ImGui::Checkbox("preview (handles in green)", &preview_on_)) preview_dirty_ = true;
  if (deformer_->ik()) ImGui::TextWrapped("keys from the IK chain (FABRIK)");
  for (std::size_t i = 0; i < keys_.size() && !deformer_->ik(); ++i) {
    deform::KeyTransform& k = keys_[i];
    if (!ImGui::TreeNodeEx(("key " + std::to_string(i)).c_str(), ImGuiTreeNodeFlags_DefaultOpen)) continue;
    std::array<float, 3> axis{static_cast<float>(k.axis.x()), static_cast<float>(k.axis.y()),
                              static_cast<float>(k.axis.z())};
    std::array<float, 3> move{static_cast<float>(k.translate.x()), static_cast<float>(k.translate.y()),
                              static_cast<float>(k.translate.z())};
    float degrees = static_cast<float>(k.degrees), scale = static_cast<float>(k.scale);
    const float reach = static_cast<float>(session_.size() / 2);
    bool changed = ImGui::SliderFloat3("axis", axis.data(), -1, 1);
    changed |= ImGui::SliderFloat("degrees", &degrees, -180, 180);
    changed |= ImGui::SliderFloat3("translate", move.data(), -reach, reach);
    changed |= ImGui::SliderFloat("scale", &scale, 0.2f, 3.0f, "%.3f", ImGuiSliderFlags_Logarithmic);
    const Vec3 a(axis[0], axis[1], axis[2]);
    if (changed && a.norm() > 1e-6) {
      k.axis = a;
      k.degrees = degrees;
      k.translate = Vec3(move[0], move[1], move[2]);
      k.scale = scale;
      preview_dirty_ = true;
    }
    ImGui::TreePop();
  }
  if (ImGui::Button("Apply deformation")) guarded("deform", [&] { apply_deformation(); });
  ImGui::SameLine();
  if (ImGui::Button("Spec's keys")) {
    keys_ = options_.spec->keys;
    preview_dirty_ = true;
  }
}

// ---- Scene ----

render::Scene Viewer::scene() const {
  const anim::RiggedModel& shown = preview_ ? *preview_ : session_.model();
  std::vector<mesh::RowMatrixXf<3>> tissue;
  if (!preview_ && session_.tissue() != nullptr) tissue = session_.tissue_positions();
  const std::array<render::ModelInstance, 1> one{
      render::ModelInstance{&shown, session_.pose(), &session_.index(), tissue.empty() ? nullptr : &tissue}};
  render::Scene s = render::model_scene(one, options_.scene);
  if (preview_ && !control_lines_.empty()) {
    render::LineSet l;
    l.points = control_lines_;
    l.color = {0.45f, 0.55f, 0.85f};
    s.lines.push_back(std::move(l));
  }
  if (preview_ && !free_control_points_.empty()) {
    render::PointSet p;
    p.points = free_control_points_;
    p.color = {0.45f, 0.55f, 0.85f};
    p.size_pixels = 5;
    s.points.push_back(std::move(p));
  }
  if (preview_ && !handle_points_.empty()) {
    render::PointSet p;
    p.points = handle_points_;
    p.color = {0.1f, 0.9f, 0.3f};
    p.size_pixels = 5;
    s.points.push_back(std::move(p));
  }
  if (joint_ >= 0 && options_.scene.skeleton) {
    const auto g = anim::global_matrices(session_.model().skeleton, session_.pose());
    render::PointSet p;
    p.points.push_back(g[static_cast<std::size_t>(joint_)].block<3, 1>(0, 3).cast<float>());
    p.color = {1, 0.85f, 0.1f};
    p.size_pixels = 12;
    s.points.push_back(std::move(p));
  }
  const double size = session_.size();
  if (tool_ == Tool::cut && cut_point_) {
    const Vec3 u = cut_normal_.unitOrthogonal() * size / 2, v = cut_normal_.cross(u);
    const std::array<Vec3, 4> c{*cut_point_ + u + v, *cut_point_ - u + v, *cut_point_ - u - v, *cut_point_ + u - v};
    render::LineSet l;
    for (int i = 0; i < 4; ++i) {
      l.points.push_back(c[static_cast<std::size_t>(i)].cast<float>());
      l.points.push_back(c[static_cast<std::size_t>((i + 1) % 4)].cast<float>());
    }
    l.points.push_back(cut_point_->cast<float>());
    l.points.push_back((*cut_point_ + cut_normal_ * size * 0.1).cast<float>());
    l.color = {0.95f, 0.3f, 0.2f};
    s.lines.push_back(std::move(l));
  }
  if (tool_ == Tool::drill && drill_at_) {
    const auto [axis, base, tip] = session::Session::drill_axis(*drill_at_, drill_view_, drill_along_view_, depth_ * size);
    render::LineSet l;
    l.points = circle(base, axis, radius_ * size, 32);
    const auto bottom = circle(tip, axis, radius_ * size, 32);
    l.points.insert(l.points.end(), bottom.begin(), bottom.end());
    for (std::size_t i = 0; i < 32; i += 8) {
      l.points.push_back(l.points[2 * i]);
      l.points.push_back(bottom[2 * i]);
    }
    l.color = {0.2f, 0.6f, 1.0f};
    s.lines.push_back(std::move(l));
  }
  if (session_.stroking()) {
    render::LineSet l;
    for (const surgery::Scalpel& b : session_.stroke()) {
      l.points.push_back(b.handle.cast<float>());
      l.points.push_back(b.tip.cast<float>());
    }
    l.color = {1, 0.9f, 0.2f};
    s.lines.push_back(std::move(l));
  }
  return s;
}

void Viewer::screenshot(const std::string& path) const {
  render::RenderOptions o = render_options_;
  o.width = fb_width_;
  o.height = fb_height_;
  render::write_png(renderer_->render(scene(), camera_, o), path);
  std::cout << (options_.json ? "{\"screenshot\": " + nlohmann::json(path).dump() + "}" : "screenshot: " + path)
            << std::endl;
}

void Viewer::read_window(const std::string& path) const {
  render::Image im;
  im.width = fb_width_;
  im.height = fb_height_;
  std::vector<std::uint8_t> rows(static_cast<std::size_t>(fb_width_) * static_cast<std::size_t>(fb_height_) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, fb_width_, fb_height_, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
  const std::size_t row = static_cast<std::size_t>(fb_width_) * 4;
  im.rgba.resize(rows.size());
  for (int y = 0; y < fb_height_; ++y)  // OpenGL's rows start at the bottom
    std::copy_n(rows.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(fb_height_ - 1 - y)), row,
                im.rgba.begin() + static_cast<std::ptrdiff_t>(row * static_cast<std::size_t>(y)));
  for (std::size_t i = 3; i < im.rgba.size(); i += 4) im.rgba[i] = 255;
  render::write_png(im, path);
  std::cout << (options_.json ? "{\"screenshot\": " + nlohmann::json(path).dump() + "}" : "screenshot: " + path)
            << std::endl;
}

void Viewer::save(const std::string& path) {
  guarded("save", [&] {
    session_.save(path, options_.scene.skinning);
    status_ = "saved " + path;
  });
}

// ---- Panel ----

template <class E>
bool combo(const char* label, E& value, const std::map<std::string, E>& names) {
  std::string current;
  for (const auto& [name, v] : names)
    if (v == value) current = name;
  bool changed = false;
  if (ImGui::BeginCombo(label, current.c_str())) {
    for (const auto& [name, v] : names)
      if (ImGui::Selectable(name.c_str(), v == value)) {
        value = v;
        changed = true;
      }
    ImGui::EndCombo();
  }
  return changed;
}

void Viewer::joint_tree(int joint, const std::vector<std::vector<int>>& children) {
  const std::string& name = session_.model().skeleton.names()[static_cast<std::size_t>(joint)];
  ImGuiTreeNodeFlags flags = ImGuiTreeNodeFlags_OpenOnArrow | ImGuiTreeNodeFlags_DefaultOpen;
  if (children[static_cast<std::size_t>(joint)].empty()) flags |= ImGuiTreeNodeFlags_Leaf;
  if (joint == joint_) flags |= ImGuiTreeNodeFlags_Selected;
  const bool open =
      ImGui::TreeNodeEx(reinterpret_cast<void*>(static_cast<std::intptr_t>(joint)), flags, "%s", name.c_str());
  if (ImGui::IsItemClicked()) joint_ = joint;
  if (open) {
    for (const int c : children[static_cast<std::size_t>(joint)]) joint_tree(c, children);
    ImGui::TreePop();
  }
}

/// A slider per morph target (targets of one name on several meshes share one), over the weights
/// the clip or the file gives.
void Viewer::morph_panel() {
  const anim::RiggedModel& model = session_.model();
  if (std::none_of(model.meshes.begin(), model.meshes.end(), [](const mesh::Mesh& m) { return !m.morph_targets.empty(); }) ||
      !ImGui::CollapsingHeader("Morph targets", ImGuiTreeNodeFlags_DefaultOpen))
    return;
  const anim::Pose pose = session_.pose();
  std::set<std::string> names;
  for (const mesh::Mesh& m : model.meshes)
    for (const mesh::MorphTarget& t : m.morph_targets) names.insert(t.name);
  // Up to 8 sliders in view; more scroll (bitmoji's head has 82).
  const float rows = static_cast<float>(std::min<std::size_t>(names.size(), 8));
  ImGui::BeginChild("targets",
                    ImVec2(0, rows * ImGui::GetFrameHeightWithSpacing() + 2 * ImGui::GetStyle().WindowPadding.y), true);
  std::set<std::string> shown;
  for (const mesh::Mesh& m : model.meshes) {
    const std::span<const float> weights = anim::morph_weights(pose, m);
    for (std::size_t k = 0; k < m.morph_targets.size(); ++k) {
      const std::string& name = m.morph_targets[k].name;
      if (!shown.insert(name).second) continue;
      float w = k < weights.size() ? weights[k] : 0.0f;
      ImGui::PushID(static_cast<int>(shown.size()));
      if (ImGui::SliderFloat(name.empty() ? "(unnamed)" : name.c_str(), &w, 0, 1, "%.3f"))
        guarded("morph weight", [&] { session_.set_morph_weight(name, w); });
      ImGui::PopID();
    }
  }
  ImGui::EndChild();
  if (ImGui::Button("Reset morph weights")) session_.clear_morph_weights();
}

// ---- Living tissue ----

void Viewer::step_tissue(double seconds) {
  if (session_.tissue() == nullptr) return;
  // A slow frame (a window dragged, a breakpoint) is not simulated all at once.
  guarded("tissue", [&] { tissue_ms_ = session_.step_tissue(std::min(seconds, 1.0 / 30)); });
}

void Viewer::tissue_panel() {
  if (!ImGui::CollapsingHeader("Living tissue", ImGuiTreeNodeFlags_DefaultOpen)) return;
  bool on = session_.tissue() != nullptr;
  soft::TissueOptions& o = tissue_options_;
  if (on) o = session_.tissue()->options();  // a script may have set them
  bool changed = ImGui::Checkbox("on (wounds open under the skin's tension)", &on);
  if (on) {
    float tension = static_cast<float>(o.pretension), stiffness = static_cast<float>(1 / o.stretch_compliance),
          hold = static_cast<float>(1 / o.attachment_compliance), damping = static_cast<float>(o.damping),
          region = static_cast<float>(o.region_radius / session_.size());
    int budget = o.max_particles;
    bool gravity = o.gravity.squaredNorm() > 0;
    // Each slider sets its option; any change rebuilds the tissue's links (Session::set_tissue).
    changed |= ImGui::SliderFloat("tension", &tension, 0, 0.5f, "%.3f");
    changed |= ImGui::SliderFloat("stiffness", &stiffness, 1e2f, 1e9f, "%.3g N/unit", ImGuiSliderFlags_Logarithmic);
    changed |= ImGui::SliderFloat("hold on body", &hold, 1e1f, 1e7f, "%.3g N/unit", ImGuiSliderFlags_Logarithmic);
    changed |= ImGui::SliderFloat("damping", &damping, 0, 50, "%.1f /s");
    changed |= ImGui::SliderFloat("region", &region, 0, 0.5f, region == 0 ? "default (0.1 x size)" : "%.3f x size");
    changed |= ImGui::SliderInt("budget", &budget, 0, 50000, budget == 0 ? "no limit" : "%d particles");
    o.pretension = tension;
    o.stretch_compliance = 1 / static_cast<double>(stiffness);
    o.attachment_compliance = 1 / static_cast<double>(hold);
    o.damping = damping;
    o.region_radius = region * session_.size();
    o.max_particles = budget;
    if (ImGui::Checkbox("gravity", &gravity)) {
      o.gravity = gravity ? Vec3(0, -9.81, 0) : Vec3::Zero();
      changed = true;
    }
  }
  if (changed) guarded("tissue", [&] { session_.set_tissue(on ? std::optional(o) : std::nullopt); });
  if (const soft::Tissue* t = session_.tissue()) {
    ImGui::Text("%zu particles simulated, %zu links; %.3f ms per frame", t->free_particles(), t->links(), tissue_ms_);
    ImGui::BeginDisabled(session_.stroking());
    if (ImGui::Button("Bake (the wound's shape into the model)")) guarded("bake", [&] { log(session_.bake_tissue()); });
    ImGui::EndDisabled();
  }
}

void Viewer::panel() {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(360, static_cast<float>(win_height_) - 16), ImGuiCond_FirstUseEver);
  ImGui::Begin("cgamesh");
  const anim::RiggedModel& model = session_.model();
  long long vertices = 0, faces = 0;
  for (const mesh::Mesh& m : model.meshes) {
    vertices += m.vertex_count();
    faces += m.face_count();
  }
  ImGui::Text("%s", options_.model_path.c_str());
  ImGui::Text("%lld vertices, %lld faces, %d joints", vertices, faces, static_cast<int>(model.skeleton.size()));
  ImGui::Text("%.1f FPS, %.2f ms per frame", fps_, frame_ms_);

  if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (const auto& [name, view] : render::kViews) {
      if (view != render::kViews.front().second) ImGui::SameLine();
      if (ImGui::SmallButton(std::string(name).c_str())) {
        options_.view = view;
        frame_all();
      }
    }
    if (ImGui::Button("Frame all")) frame_all();
    static const std::map<std::string, render::ColorMode> colors(render::kColorModes.begin(), render::kColorModes.end());
    combo("colour", options_.scene.color, colors);
    if (options_.scene.color == render::ColorMode::joint && joint_ >= 0)
      options_.scene.joint = model.skeleton.names()[static_cast<std::size_t>(joint_)];
    if (options_.scene.color == render::ColorMode::joint && options_.scene.joint.empty())
      options_.scene.color = render::ColorMode::weights;  // no joint picked yet
    ImGui::Checkbox("skeleton", &options_.scene.skeleton);
    ImGui::SameLine();
    ImGui::Checkbox("wireframe", &render_options_.wireframe);
    float explode = static_cast<float>(options_.scene.explode);
    if (ImGui::SliderFloat("pull pieces apart", &explode, 0, 1)) options_.scene.explode = explode;
  }

  if (ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen)) {
    const int clip = session_.clip();
    const std::string current = clip < 0 ? "bind pose" : model.clips[static_cast<std::size_t>(clip)].name;
    if (ImGui::BeginCombo("clip", current.c_str())) {
      if (ImGui::Selectable("bind pose", clip < 0)) session_.set_clip(-1);
      for (std::size_t i = 0; i < model.clips.size(); ++i) {
        const std::string label = model.clips[i].name.empty() ? "clip " + std::to_string(i) : model.clips[i].name;
        if (ImGui::Selectable((label + "##" + std::to_string(i)).c_str(), static_cast<int>(i) == clip))
          session_.set_clip(static_cast<int>(i));
      }
      ImGui::EndCombo();
    }
    if (ImGui::Button(playing_ ? "Pause" : "Play")) playing_ = !playing_;
    ImGui::SameLine();
    float speed = static_cast<float>(speed_);
    if (ImGui::SliderFloat("speed", &speed, 0.05f, 4.0f, "%.2fx")) speed_ = speed;
    float t = static_cast<float>(session_.time());
    if (ImGui::SliderFloat("time", &t, 0, static_cast<float>(std::max(session_.duration(), 1e-3)), "%.3f s"))
      session_.set_time(t);
    anim::BlendMode blend = session_.blend();
    if (combo("blend", blend, io::kBlendModes)) session_.set_blend(blend);
    combo("skinning", options_.scene.skinning, io::kSkinningModes);
  }

  if (ImGui::CollapsingHeader("Joints")) {
    const auto parents = model.skeleton.parents();
    std::vector<std::vector<int>> children(parents.size());
    for (std::size_t j = 0; j < parents.size(); ++j)
      if (parents[j] >= 0) children[static_cast<std::size_t>(parents[j])].push_back(static_cast<int>(j));
    ImGui::BeginChild("tree", ImVec2(0, 160), true);
    for (std::size_t j = 0; j < parents.size(); ++j)
      if (parents[j] < 0) joint_tree(static_cast<int>(j), children);
    ImGui::EndChild();
    if (joint_ >= 0 && joint_ < static_cast<int>(model.skeleton.size())) {
      anim::JointEdit e = session_.edit_of(joint_);
      std::array<float, 3> axis{static_cast<float>(e.axis.x()), static_cast<float>(e.axis.y()),
                                static_cast<float>(e.axis.z())};
      std::array<float, 3> move{static_cast<float>(e.translation.x()), static_cast<float>(e.translation.y()),
                                static_cast<float>(e.translation.z())};
      float angle = static_cast<float>(e.angle * 180 / std::numbers::pi), scale = static_cast<float>(e.scale);
      const float reach = static_cast<float>(session_.size() / 2);
      bool changed = ImGui::SliderFloat3("axis", axis.data(), -1, 1);
      changed |= ImGui::SliderFloat("angle", &angle, -180, 180, "%.1f deg");
      changed |= ImGui::SliderFloat3("translate", move.data(), -reach, reach);
      changed |= ImGui::SliderFloat("dilate", &scale, 0.1f, 3.0f, "%.3f", ImGuiSliderFlags_Logarithmic);
      const Vec3 a(axis[0], axis[1], axis[2]);
      if (changed && a.norm() > 1e-6) {
        e.axis = a;
        e.angle = angle * std::numbers::pi / 180;
        e.translation = Vec3(move[0], move[1], move[2]);
        e.scale = scale;
        guarded("joint edit", [&] { session_.set_edit(e); });
      }
    }
    if (ImGui::Button("Key pose at this time")) session_.add_key();
    ImGui::SameLine();
    ImGui::Text("%zu keys", session_.keys().size());
    ImGui::InputText("clip name", clip_name_.data(), clip_name_.size());
    if (ImGui::Button("Generate clip from keys")) {
      guarded("generate clip", [&] {
        session_.generate_clip(clip_name_.data());
        playing_ = true;
      });
    }
    ImGui::SameLine();
    if (ImGui::Button("Clear edits")) session_.clear_edits();
  }

  morph_panel();

  if (ImGui::CollapsingHeader("Surgery", ImGuiTreeNodeFlags_DefaultOpen)) {
    int tool = static_cast<int>(tool_);
    ImGui::RadioButton("camera", &tool, static_cast<int>(Tool::camera));
    ImGui::SameLine();
    ImGui::RadioButton("joint", &tool, static_cast<int>(Tool::joint));
    ImGui::SameLine();
    ImGui::RadioButton("cut", &tool, static_cast<int>(Tool::cut));
    ImGui::SameLine();
    ImGui::RadioButton("tear", &tool, static_cast<int>(Tool::tear));
    ImGui::SameLine();
    ImGui::RadioButton("drill", &tool, static_cast<int>(Tool::drill));
    tool_ = static_cast<Tool>(tool);
    ImGui::TextWrapped(
        "Left button: the tool (orbit in camera mode). Right drag: orbit; middle or shift+right: pan; wheel: zoom.");
    switch (tool_) {
      case Tool::cut:
        ImGui::TextWrapped("Click a point (the plane faces you), or drag along the cut line.");
        ImGui::Checkbox("cap", &cap_);
        if (cut_point_ && ImGui::Button("Apply cut")) apply_cut();
        break;
      case Tool::tear: {
        ImGui::TextWrapped("Press on the surface and drag: the tear follows the blade.");
        float open = static_cast<float>(open_), depth = static_cast<float>(blade_depth_),
              step = static_cast<float>(step_length_);
        if (ImGui::SliderFloat("opening", &open, 0, static_cast<float>(0.05 * session_.size()), "%.4f")) open_ = open;
        if (ImGui::SliderFloat("blade depth", &depth, 0.005f, 0.2f, "%.3f x size")) blade_depth_ = depth;
        if (ImGui::SliderFloat("step", &step, 0.002f, 0.05f, "%.3f x size")) step_length_ = step;
        break;
      }
      case Tool::drill: {
        ImGui::TextWrapped("Click a point; the axis follows the surface normal or the view.");
        float radius = static_cast<float>(radius_), depth = static_cast<float>(depth_);
        if (ImGui::SliderFloat("radius", &radius, 0.002f, 0.2f, "%.3f x size")) radius_ = radius;
        if (ImGui::SliderFloat("depth", &depth, 0.01f, 1.0f, "%.3f x size")) depth_ = depth;
        ImGui::Checkbox("wall", &wall_);
        ImGui::SameLine();
        ImGui::Checkbox("along the view", &drill_along_view_);
        if (drill_at_ && ImGui::Button("Apply drill")) apply_drill();
        break;
      }
      default:
        break;
    }
    ImGui::BeginDisabled(!session_.can_undo());
    if (ImGui::Button("Undo")) session_.undo();
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!session_.can_redo());
    if (ImGui::Button("Redo")) session_.redo();
    ImGui::EndDisabled();
    ImGui::SameLine();
    if (ImGui::Button("Reset")) session_.reset();
    for (const std::string& l : log_) ImGui::TextUnformatted(l.c_str());
  }

  tissue_panel();
  deformation_panel();

  if (ImGui::CollapsingHeader("Save", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::InputText("file", save_path_.data(), save_path_.size());
    if (ImGui::Button("Save (.glb/.gltf rigged, .obj/.ply posed)")) save(save_path_.data());
    if (ImGui::Button("Screenshot (.png)")) guarded("screenshot", [&] { screenshot(save_path_.data()); });
  }
  if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
  ImGui::End();
}

void Viewer::run() {
  const auto first = Clock::now();
  long frames = 0;
  auto last = first;
  while (!quit_ && glfwWindowShouldClose(window_.handle()) == 0) {
    glfwPollEvents();
    glfwGetFramebufferSize(window_.handle(), &fb_width_, &fb_height_);
    glfwGetWindowSize(window_.handle(), &win_width_, &win_height_);
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    frame_ms_ = 0.9 * frame_ms_ + 0.1 * dt * 1000;
    fps_ = frame_ms_ > 0 ? 1000 / frame_ms_ : 0;

    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    if (options_.script.empty()) {
      mouse();
      advance(dt);
      step_tissue(dt);
    } else {
      script_step();
      step_tissue(1.0 / 30);  // scripts run at 30 frames per second of model time, on any machine
    }
    update_preview();
    if (fb_width_ > 0 && fb_height_ > 0) {
      render_options_.width = fb_width_;
      render_options_.height = fb_height_;
      renderer_->draw(scene(), camera_, render_options_);
    }
    panel();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (!window_shot_.empty()) read_window(std::exchange(window_shot_, {}));
    glfwSwapBuffers(window_.handle());
    ++frames;
  }
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - first).count() / std::max(frames, 1L);
  if (options_.json)
    std::cout << nlohmann::json{{"frames", frames}, {"frame_milliseconds", ms}}.dump() << std::endl;
  else
    std::cout << frames << " frames, " << ms << " ms per frame" << std::endl;
}

}  // namespace

void run_viewer(session::Session& session, const ViewerOptions& options, const std::string& script_name) {
  Viewer viewer(session, options, script_name);
  viewer.run();
}

}  // namespace cgamesh::viewer
