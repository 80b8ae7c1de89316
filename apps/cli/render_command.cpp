#include "render_command.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "cgamesh/errors.hpp"
#include "cgamesh/io/model_loader.hpp"
#include "cgamesh/io/atomic_file.hpp"
#include "cgamesh/io/file_extension.hpp"
#include "cgamesh/render/animation.hpp"
#include "cgamesh/render/camera.hpp"
#include "cgamesh/render/headless_context.hpp"
#include "cgamesh/render/model_scene.hpp"
#include "cgamesh/render/renderer.hpp"

#include "cli_common.hpp"

namespace cgamesh::cli {
namespace {

/// The largest number of views in one contact sheet.
constexpr int kMaxTurntable = 64;
/// The most pixel memory the frames of one render may hold (they are encoded together).
constexpr double kMaxAnimationBytes = 4.0 * 1024 * 1024 * 1024;

struct RenderCommand {
  std::vector<std::string> models;
  std::string output;
  PoseChoice pose{"pose the models in this animation"};
  anim::SkinningMode skinning = anim::SkinningMode::cga;
  std::string color = "material", size = "1280x960", view, camera, bg = "1,1,1";
  double fov = 35;
  bool frame = false, wireframe = false, skeleton = false, json = false, force = false;
  int turntable = 0;

  void run() const {
    // Every argument is checked before any model is read or any context made.
    const std::string ext = io::lower_extension(output);
    if (ext != ".png" && ext != ".webp")
      throw InvalidInputError("-o '" + output + "': the output must be a .png file (or .webp for an animation)");
    check_outputs({output}, models, force);
    render::RenderOptions options;
    std::tie(options.width, options.height) = parse_size(size, "--size", 1, render::kMaxImageSide);
    const auto bgv = parse_numbers(bg, 3, "--bg");
    for (const double c : bgv)
      if (c < 0 || c > 1) throw InvalidInputError("--bg: each component must be in [0, 1], got '" + bg + "'");
    options.background = Eigen::Vector3d(bgv[0], bgv[1], bgv[2]).cast<float>();
    options.wireframe = wireframe;
    render::validate(options);
    if (!(fov > 0 && fov < 180)) throw InvalidInputError("--fov must be in (0, 180) degrees");
    render::ModelSceneOptions scene_options;
    scene_options.color = render::parse_color_mode(color, scene_options.joint);
    scene_options.skinning = skinning;
    scene_options.skeleton = skeleton;
    std::optional<render::Camera> given;
    if (!camera.empty()) {
      const auto c = parse_numbers(camera, 9, "--camera");
      given = render::Camera{{c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]}, fov};
      render::validate(*given);
    }
    const render::View named = render::parse_view(view.empty() ? "front" : view);
    if (turntable < 0 || turntable > kMaxTurntable)
      throw InvalidInputError("--turntable must be 0 to " + std::to_string(kMaxTurntable));
    const int views = std::max(turntable, 1);
    const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(views))));
    const int rows = (views + columns - 1) / columns;
    if (static_cast<long>(options.width) * columns > render::kMaxImageSide ||
        static_cast<long>(options.height) * rows > render::kMaxImageSide)
      throw InvalidInputError("--turntable " + std::to_string(turntable) + " at --size " + size +
                              " makes a sheet larger than " + std::to_string(render::kMaxImageSide) + " pixels a side");
    const std::optional<render::FrameTimes> range = frame_times();
    const int frames = range ? range->frames : 1;
    const double frame_bytes = 4.0 * options.width * columns * options.height * rows;
    if (frame_bytes * frames > kMaxAnimationBytes)
      throw InvalidInputError("--time " + pose.time_text + " at --size " + size + " makes " + std::to_string(frames) +
                              " pictures of " + number(frame_bytes / 1048576.0) + " MiB: at most " +
                              number(kMaxAnimationBytes / 1048576.0) + " MiB in all (fewer frames or a smaller --size)");

    const auto start = std::chrono::steady_clock::now();
    std::vector<anim::RiggedModel> loaded;
    loaded.reserve(models.size());
    for (const std::string& path : models) loaded.push_back(cli::load_model(path, false));
    std::vector<std::string> warnings;
    for (std::size_t i = 0; i < loaded.size(); ++i)
      for (const std::string& w : loaded[i].warnings) warnings.push_back(models[i] + ": " + w);
    // One scene per frame, each model posed at the frame's time.
    Json poses = Json::array();
    std::string pose_text;
    std::vector<render::Scene> scenes;
    render::Box box;
    for (int k = 0; k < frames; ++k) {
      PoseChoice at = pose;
      at.time = range ? range->time(k) : one_time();
      std::vector<render::ModelInstance> instances;
      for (std::size_t i = 0; i < loaded.size(); ++i) {
        PoseChoice::Chosen chosen = at.choose(loaded[i]);
        for (const std::string& w : chosen.warnings)
          if (std::find(warnings.begin(), warnings.end(), models[i] + ": " + w) == warnings.end())
            warnings.push_back(models[i] + ": " + w);
        if (k == 0) {
          if (i == 0 || pose_text != chosen.text) pose_text += (i == 0 ? "" : "; ") + chosen.text;
          poses.push_back(chosen.report);
        }
        instances.push_back({&loaded[i], std::move(chosen.pose)});
      }
      scenes.push_back(render::model_scene(instances, scene_options, k == 0 ? &warnings : nullptr));
      const render::Box b = scenes.back().bounds();
      if (!b.empty()) {
        box.add(b.lo);
        box.add(b.hi);
      }
    }
    if (range)
      pose_text += ", " + std::to_string(frames) + " frames from t = " + number(range->start) + " to " +
                   number(range->end) + " s";
    const auto scene_done = std::chrono::steady_clock::now();

    // One camera for every frame, framing all of them, so that the model moves in the picture.
    const double aspect = static_cast<double>(options.width) / options.height;
    render::Camera cam =
        given ? (frame ? render::frame(box, *given, aspect) : *given) : render::frame(box, named, fov, aspect);
    std::vector<render::Camera> cameras;
    for (int k = 0; k < views; ++k) cameras.push_back(render::orbit(cam, 2 * std::numbers::pi * k / views));
    const std::string view_name = given ? std::string("the --camera") : "the view '" + (view.empty() ? "front" : view) + "'";
    const std::string edge_on = render::edge_on_warning(box, cameras, view_name);
    if (!edge_on.empty()) warnings.push_back(edge_on);
    for (const std::string& w : warnings) std::cerr << "cgamesh: warning: " << w << "\n";
    render::HeadlessContext context;
    render::Renderer renderer;
    std::vector<render::Image> pictures;
    bool blank = false;
    for (const render::Scene& scene : scenes) {
      std::vector<render::Image> images;
      for (const render::Camera& c : cameras) images.push_back(renderer.render(scene, c, options));
      if (const std::string b = render::blank_warning(images, view_name); edge_on.empty() && !b.empty() && !blank) {
        std::cerr << "cgamesh: warning: " << b << "\n";
        warnings.push_back(b);
        blank = true;
      }
      pictures.push_back(views == 1 ? std::move(images.front())
                                    : render::contact_sheet(images, columns, options.background));
    }
    const auto render_done = std::chrono::steady_clock::now();
    const std::vector<std::string> written = write(pictures, range);

    const auto ms = [](auto a, auto b) { return std::chrono::duration<double, std::milli>(b - a).count(); };
    Json summary = {
        {"output", output},
        {"files", written},
        {"frames", frames},
        {"width", options.width * (views == 1 ? 1 : columns)},
        {"height", options.height * (views == 1 ? 1 : rows)},
        {"views", views},
        {"renderer", context.description()},
        {"camera",
         {{"eye", {cam.eye.x(), cam.eye.y(), cam.eye.z()}},
          {"target", {cam.target.x(), cam.target.y(), cam.target.z()}},
          {"up", {cam.up.x(), cam.up.y(), cam.up.z()}},
          {"fov", cam.fov_degrees}}},
        {"pose", poses.size() == 1 ? poses[0] : poses},
        {"milliseconds", {{"load_and_pose", ms(start, scene_done)}, {"render", ms(scene_done, render_done)}}},
        {"warnings", warnings}};
    if (range)
      summary["time"] = {{"start", range->start}, {"end", range->end}, {"frame_seconds", range->frame_seconds()}};
    if (json) {
      std::cout << dump_json(summary) << "\n";
      return;
    }
    std::cout << "render " << models.size() << (models.size() == 1 ? " model" : " models") << " in the " << pose_text
              << ", " << summary["width"] << "x" << summary["height"] << " pixels\n  -> " << written.front()
              << (written.size() > 1 ? " ... " + written.back() : std::string()) << "\n";
  }

  /// The frames of --time START:END:N; none for one time (then set in pose.time).
  [[nodiscard]] std::optional<render::FrameTimes> frame_times() const {
    if (pose.time_option == nullptr || pose.time_option->count() == 0) return std::nullopt;
    if (pose.time_text.find(':') != std::string::npos) return render::FrameTimes::parse(pose.time_text, "--time");
    return std::nullopt;
  }

  /// --time as one number (0 without it).
  [[nodiscard]] double one_time() const {
    if (pose.time_option == nullptr || pose.time_option->count() == 0) return 0;
    return parse_numbers(pose.time_text, 1, "--time")[0];
  }

  /// Writes the pictures: one PNG; an animated WebP; or, for PNG and a time range, one PNG per
  /// frame (NAME_000.png ...), all or none. Returns the files written.
  [[nodiscard]] std::vector<std::string> write(const std::vector<render::Image>& pictures,
                                               const std::optional<render::FrameTimes>& range) const {
    if (io::lower_extension(output) == ".webp") {
      render::AnimationOptions a;
      if (range) a.frame_seconds = range->frame_seconds();
      render::write_webp_animation(pictures, output, a);
      return {output};
    }
    if (!range) {
      render::write_png(pictures.front(), output);
      return {output};
    }
    const std::filesystem::path base(output);
    const int digits = std::max(3, static_cast<int>(std::to_string(pictures.size() - 1).size()));
    std::vector<io::EncodedFile> files;
    for (std::size_t k = 0; k < pictures.size(); ++k) {
      std::string index = std::to_string(k);
      index.insert(0, static_cast<std::size_t>(digits) - index.size(), '0');
      files.push_back({base.parent_path() / (base.stem().string() + "_" + index + base.extension().string()),
                       render::encode_png(pictures[k])});
    }
    io::write_files_atomically(files);
    std::vector<std::string> out;
    for (const io::EncodedFile& f : files) out.push_back(f.path.string());
    return out;
  }
};

}  // namespace

void add_render(CLI::App& app) {
  auto o = std::make_shared<RenderCommand>();
  CLI::App* sub = app.add_subcommand(
      "render", "Render models to a PNG, or a time range to an animated WebP, headless (EGL; no display or GPU needed)");
  sub->add_option("MODEL", o->models, "model files (several are drawn together, e.g. the pieces of a cut)")->required();
  sub->add_option("-o,--output", o->output,
                  "output .png (with --time START:END:N: NAME_000.png, one per frame) or .webp (an animated WebP)")
      ->required();
  o->pose.time_range = true;
  o->pose.add_to(*sub);
  add_force(*sub, o->force);
  sub->add_option("--skinning", o->skinning, "skinning: cga, versor, matrix or dqs")
      ->transform(CLI::CheckedTransformer(kSkinningModes, CLI::ignore_case));
  sub->add_option("--color", o->color,
                  "material | height | normal | joint:NAME (influence of one joint) | weights | piece | new (vertices "
                  "made by surgery)")
      ->capture_default_str();
  sub->add_flag("--wireframe", o->wireframe, "draw the triangle edges");
  sub->add_flag("--skeleton", o->skeleton, "draw the joints and bones over the mesh");
  sub->add_option("--size", o->size, "picture size WIDTHxHEIGHT")->capture_default_str();
  auto* view = sub->add_option("--view", o->view, "front, back, left, right, top or iso (default front)");
  auto* camera = sub->add_option("--camera", o->camera, "EX,EY,EZ,TX,TY,TZ,UX,UY,UZ: eye, target and up (look-at)");
  view->excludes(camera);
  sub->add_option("--fov", o->fov, "vertical field of view in degrees")->capture_default_str();
  sub->add_flag("--frame", o->frame, "fit the camera to the bounding box (the default without --camera)");
  sub->add_option("--bg", o->bg, "background colour R,G,B in [0, 1]")->capture_default_str();
  sub->add_option("--turntable", o->turntable, "N views around the model in one contact sheet");
  sub->add_flag("--json", o->json, "print the picture's size, camera, renderer and timings");
  sub->callback([o] { o->run(); });
}

}  // namespace cgamesh::cli
