#include "view_command.hpp"

#include <filesystem>
#include <memory>
#include <string>
#include <tuple>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_writer.hpp"
#include "cgamesh/render/model_scene.hpp"
#include "cgamesh/session/script.hpp"
#include "cgamesh/session/session.hpp"

#include "cli_common.hpp"
#include "viewer.hpp"

namespace cgamesh::cli {
namespace {

struct ViewCommand {
  std::string model, script, size = "1280x800", view = "front", color = "material";
  std::string anim, spec;
  double time = 0;
  anim::SkinningMode skinning = anim::SkinningMode::cga;
  bool skeleton = false, json = false;

  /// Every action checks what it can before the window opens: a script fails at its line, fast.
  static void check_script(const std::vector<session::ScriptAction>& actions, const anim::RiggedModel& m,
                           const std::string& name) {
    for (const session::ScriptAction& a : actions) {
      try {
        std::string joint;
        if (a.verb == "color") (void)render::parse_color_mode(a.text, joint);
        if (a.verb == "view") (void)render::parse_view(a.text);
        if (a.verb == "joint") (void)parse_edit(m.skeleton, a.text, max_translation(m));
        if (a.verb == "save") check_extension(a.text, io::kModelExtensions, "save");
        if (a.verb == "screenshot") check_extension(a.text, {".png"}, "screenshot");
      } catch (...) {
        rethrow_with_context(name + ":" + std::to_string(a.line) + ": " + a.verb + ": ");
      }
    }
  }

  void run() const {
    viewer::ViewerOptions o;
    std::tie(o.width, o.height) = parse_size(size, "--size", 64, 8192);
    o.view = render::parse_view(view);
    o.scene.color = render::parse_color_mode(color, o.scene.joint);
    o.scene.skinning = skinning;
    o.scene.skeleton = skeleton;
    o.json = json;
    if (!script.empty()) o.script = session::read_script(script);
    if (!spec.empty()) {
      o.spec = deform::read_spec(spec);
      o.spec_path = spec;
    }
    anim::RiggedModel m = load_model(model);
    check_script(o.script, m, script);
    if (o.scene.color == render::ColorMode::joint) (void)joint_index(m.skeleton, o.scene.joint);
    const int clip = anim.empty() ? -1 : clip_index(m, anim);
    o.model_path = model;
    o.title = "cgamesh view " + std::filesystem::path(model).filename().string();
    session::SessionOptions options;
    options.model_file = model;
    session::Session s(std::move(m), options);
    s.set_clip(clip);
    s.set_time(time);
    viewer::run_viewer(s, o, script);
  }
};

}  // namespace

void add_view(CLI::App& app) {
  auto c = std::make_shared<ViewCommand>();
  CLI::App* sub = app.add_subcommand(
      "view", "Open a window to play, pose, cut, tear, drill and save a model by hand (needs a display)");
  sub->add_option("MODEL", c->model, "model file")->required();
  sub->add_option("--script", c->script,
                  "run the actions of this file one per frame, then close (see README, 'The viewer')");
  sub->add_option("--size", c->size, "window size WIDTHxHEIGHT")->capture_default_str();
  sub->add_option("--view", c->view, "front, back, left, right, top or iso")->capture_default_str();
  sub->add_option("--color", c->color, "material, height, normal, joint:NAME, weights, piece or new")
      ->capture_default_str();
  sub->add_option("--skinning", c->skinning, "cga, versor, matrix or dqs")
      ->transform(CLI::CheckedTransformer(kSkinningModes, CLI::ignore_case))
      ->capture_default_str();
  sub->add_option("--anim", c->anim, "start on this clip (name or index; default: the bind pose)");
  sub->add_option("--time", c->time, "start at this time (seconds)")->check(CLI::NonNegativeNumber);
  sub->add_option("--spec", c->spec,
                  "a deformation spec (as for `cgamesh deform`): its handles shown, its keys on sliders, "
                  "previewed every frame");
  sub->add_flag("--skeleton", c->skeleton, "draw the skeleton over the mesh");
  sub->add_flag("--json", c->json, "log each operation as one JSON line on stdout");
  sub->callback([c] { c->run(); });
}

}  // namespace cgamesh::cli
