#pragma once
// Conventions every cgamesh command shares: comma-separated vectors, joint edits, choosing a
// clip and a pose, output formats chosen by extension.

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"
#include "cgamesh/io/text_values.hpp"

namespace cgamesh::cli {

// The text forms every front end shares live in the library.
using io::blend_name;
using io::clip_index;
using io::clip_names;
using io::joint_index;
using io::kBlendModes;
using io::kMaxReach;
using io::kSkinningModes;
using io::max_translation;
using io::number;
using io::parse_edit;
using io::parse_numbers;
using io::posed_frame;

using Json = nlohmann::ordered_json;

/// `j` as indented JSON text. Names in models are not always UTF-8: invalid bytes become
/// U+FFFD instead of throwing. Every command prints its JSON through this.
template <class J>
[[nodiscard]] std::string dump_json(const J& j) {
  return j.dump(2, ' ', false, J::error_handler_t::replace);
}

/// The pose a command acts on. Every command defaults to the bind pose (the pose `info` gives
/// boxes for); --anim and/or --time choose a clip (the first when only --time is given).
struct PoseChoice {
  explicit PoseChoice(std::string help) : anim_help(std::move(help)) {}

  std::string anim_help;  ///< what --anim does, for the help text
  std::string anim;
  double time = 0;
  anim::BlendMode blend = anim::BlendMode::format;
  std::vector<std::string> sets;
  std::vector<std::string> morphs;  ///< --morph TARGET=W
  bool bind = false;
  /// --time may be a range START:END:N (render): add_to() then reads it into time_text, and the
  /// command sets `time` for each frame.
  bool time_range = false;
  std::string time_text;
  const CLI::Option* time_option = nullptr;  ///< set by add_to(); given or not

  /// The pose chosen for one model, and how to report it.
  struct Chosen {
    anim::Pose pose;
    Json report;                        ///< {"kind": "bind"} or {"kind": "clip", ...}, plus "edits"
    std::string text;                   ///< the same, in words
    std::vector<std::string> warnings;  ///< --time past the clip's end, or without a clip
  };

  /// Adds --anim, --time, --blend, --set, --morph and --bind-pose to `sub`.
  void add_to(CLI::App& sub);
  /// The chosen pose of `model`.
  /// @throws InvalidInputError for a bad time, an unknown clip, joint or morph target, or a
  ///         malformed edit or weight.
  [[nodiscard]] Chosen choose(const anim::RiggedModel& model) const;
};

/// "WIDTHxHEIGHT" as two integers, each in [lo, hi].
/// @throws InvalidInputError naming `option` otherwise.
[[nodiscard]] std::pair<int, int> parse_size(const std::string& text, const std::string& option, int lo, int hi);

/// Adds --force (write over an input file) to `sub`.
void add_force(CLI::App& sub, bool& force);

/// Refuses an output that is one of the inputs (the same file, or the same path), unless
/// `force`, and two outputs that are the same file.
/// @throws InvalidInputError naming the option.
void check_outputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs, bool force);

/// Refuses an output whose extension is not in `allowed` (lower case, with the dot), listing
/// them: what `command` writes.
/// @throws InvalidInputError.
void check_extension(const std::string& output, const std::vector<std::string>& allowed, const std::string& command);

/// Refuses an empty value given to any option of `app` or of its parsed subcommands
/// (`--time ''`): CLI11 would read it as 0 or "".
/// @throws InvalidInputError naming the option.
void check_no_empty_values(const CLI::App& app);

/// Seconds a model may take to load (--load-timeout): some readers loop forever on corrupt
/// files, and a reader cannot be interrupted, so past this the process ends (exit 3).
inline double load_timeout_seconds = 120;

/// Adds --load-timeout to `app` (given before or after the command).
void add_load_timeout(CLI::App& app);

/// io::load_model within load_timeout_seconds; past it, a message on stderr and exit 3. The
/// loader's warnings go to stderr unless the command prints them itself (`print_warnings`).
/// @throws FileError as io::load_model does.
[[nodiscard]] anim::RiggedModel load_model(const std::filesystem::path& path, bool print_warnings = true);

}  // namespace cgamesh::cli
