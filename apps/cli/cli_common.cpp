#include "cli_common.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <iostream>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "cgamesh/anim/pose_choice.hpp"
#include "cgamesh/errors.hpp"
#include "cgamesh/io/file_extension.hpp"
#include "cgamesh/io/model_loader.hpp"

#include "exit_codes.hpp"

namespace cgamesh::cli {

void add_load_timeout(CLI::App& app) {
  app.add_option("--load-timeout", load_timeout_seconds,
                 "seconds a model may take to load before cgamesh gives up with exit 3 (default 120)")
      ->check(CLI::PositiveNumber);
  app.fallthrough();
}

anim::RiggedModel load_model(const std::filesystem::path& path, bool print_warnings) {
  const auto budget = std::chrono::duration<double>(load_timeout_seconds);
  const auto give_up = [&] {
    std::cerr << "cgamesh: cannot load '" << path.string() << "': reading it took longer than " << load_timeout_seconds
              << " s (a corrupt file can make a reader loop forever); allow more with --load-timeout\n";
    std::_Exit(kExitBadInput);
  };
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::thread watchdog([&] {
    std::unique_lock lock(mutex);
    if (!finished.wait_for(lock, budget, [&] { return done; })) give_up();
  });
  const auto stop = [&] {
    {
      const std::lock_guard lock(mutex);
      done = true;
    }
    finished.notify_one();
    watchdog.join();
  };
  const auto start = std::chrono::steady_clock::now();
  try {
    anim::RiggedModel model = io::load_model(path);
    stop();
    // The watchdog may wake late on a busy machine: a load over its budget is refused all the same.
    if (std::chrono::steady_clock::now() - start > budget) give_up();
    if (print_warnings)
      for (const std::string& w : model.warnings)
        std::cerr << "cgamesh: warning: " << path.string() << ": " << w << "\n";
    return model;
  } catch (...) {
    stop();
    throw;
  }
}

void PoseChoice::add_to(CLI::App& sub) {
  auto* a = sub.add_option("--anim", anim,
                           anim_help +
                               " (name or index; default: the bind pose, as in every command; --time alone "
                               "picks the first clip)");
  time_option = time_range ? sub.add_option("--time", time_text,
                                             "seconds into the animation (default 0 with --anim), or START:END:N: N "
                                             "frames from START towards END, (END - START)/N s apart")
                            : sub.add_option("--time", time, "seconds into the animation (default 0 with --anim)");
  sub.add_option("--blend", blend, "key blending: format, linear or log")
      ->transform(CLI::CheckedTransformer(kBlendModes, CLI::ignore_case));
  sub.add_option("--set", sets, "JOINT:rotate=AX,AY,AZ,DEG | JOINT:translate=X,Y,Z | JOINT:scale=S (repeatable)");
  sub.add_option("--morph", morphs,
                 "TARGET=W: morph target (blend shape) TARGET at weight W, over the clip's or the file's weights "
                 "(repeatable; `info` lists the targets)");
  sub.add_flag("--bind-pose", bind, "the bind pose (the default; excludes --anim and --time)")
      ->excludes(a)
      ->excludes(const_cast<CLI::Option*>(time_option));
}

PoseChoice::Chosen PoseChoice::choose(const anim::RiggedModel& model) const {
  anim::PoseRequest request;
  request.blend = blend;
  if (!anim.empty()) request.clip = clip_index(model, anim);
  if (time_option != nullptr && time_option->count() > 0) {
    // choose_pose() refuses it too, but the user typed --time.
    if (!std::isfinite(time) || time < 0) throw InvalidInputError("--time must be a finite number >= 0");
    request.time = time;
  }
  const double reach = sets.empty() ? INFINITY : max_translation(model);
  for (const std::string& s : sets) request.edits.push_back(parse_edit(model.skeleton, s, reach));
  for (const std::string& m : morphs) request.morphs.push_back(io::parse_morph_setting(m));
  anim::ChosenPose chosen = anim::choose_pose(model, request);
  Chosen out;
  out.pose = std::move(chosen.pose);
  out.warnings = std::move(chosen.warnings);
  if (chosen.clip < 0) {
    out.report = {{"kind", "bind"}};
    out.text = "bind pose";
  } else {
    const anim::Clip& c = model.clips[static_cast<std::size_t>(chosen.clip)];
    out.report = {{"kind", "clip"}, {"clip", c.name}, {"index", chosen.clip}, {"time", chosen.time}, {"blend", blend_name(blend)}};
    out.text = "clip '" + c.name + "' (" + std::to_string(chosen.clip) + ") at t = " + number(chosen.time) + " s, " +
               blend_name(blend) + " blending";
  }
  if (!sets.empty()) {
    out.report["edits"] = sets;
    out.text += " + " + std::to_string(sets.size()) + (sets.size() == 1 ? " edit" : " edits");
  }
  if (!morphs.empty()) {
    out.report["morph"] = morphs;
    out.text += " + " + std::to_string(morphs.size()) + (morphs.size() == 1 ? " morph weight" : " morph weights");
  }
  return out;
}

std::pair<int, int> parse_size(const std::string& text, const std::string& option, int lo, int hi) {
  const std::size_t x = text.find_first_of("xX");
  const auto side = [&](const std::string& part) {
    std::size_t used = 0;
    long v = 0;
    try {
      v = std::stol(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (x == std::string::npos || used == 0 || used != part.size() || v < lo || v > hi)
      throw InvalidInputError(option + " '" + text + "': expected WIDTHxHEIGHT, each side an integer from " +
                              std::to_string(lo) + " to " + std::to_string(hi));
    return static_cast<int>(v);
  };
  return {side(text.substr(0, x)), side(x == std::string::npos ? "" : text.substr(x + 1))};
}

void add_force(CLI::App& sub, bool& force) {
  sub.add_flag("--force", force, "write the output even over an input file");
}

void check_outputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs, bool force) {
  namespace fs = std::filesystem;
  const auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::equivalent(a, b, ec) && !ec) return true;
    ec.clear();
    const fs::path ca = fs::weakly_canonical(a, ec);
    if (ec) return false;
    const fs::path cb = fs::weakly_canonical(b, ec);
    return !ec && ca == cb;
  };
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k)
      if (same(outputs[i], outputs[k]))
        throw InvalidInputError("-o: '" + outputs[k] + "' and '" + outputs[i] + "' are the same file");
    if (force) continue;
    for (const std::string& in : inputs)
      if (same(outputs[i], in))
        throw InvalidInputError("-o '" + outputs[i] + "' is the input file '" + in +
                                "': refusing to overwrite it (--force to do so)");
  }
}

void check_extension(const std::string& output, const std::vector<std::string>& allowed, const std::string& command) {
  const std::string ext = io::lower_extension(output);
  if (std::find(allowed.begin(), allowed.end(), ext) != allowed.end()) return;
  std::string list;
  for (std::size_t i = 0; i < allowed.size(); ++i)
    list += (i == 0 ? "" : i + 1 == allowed.size() ? " or " : ", ") + allowed[i];
  throw InvalidInputError("-o '" + output + "': " + command + " writes " + list + " files (the extension chooses)");
}

void check_no_empty_values(const CLI::App& app) {
  for (const CLI::Option* o : app.get_options()) {
    if (o->get_type_size_max() == 0 || o->get_expected_max() == 0 || o->count() == 0) continue;  // a flag, or not given
    for (const std::string& r : o->results())
      if (r.empty())
        throw InvalidInputError((o->get_name().empty() ? std::string("an option") : o->get_name()) +
                                ": the value is empty");
  }
  for (const CLI::App* sub : app.get_subcommands()) check_no_empty_values(*sub);
}

}  // namespace cgamesh::cli
