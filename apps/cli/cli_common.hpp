#pragma once
// Conventions every cgamesh command shares: comma-separated vectors, joint edits, choosing a
// clip and a pose, output formats chosen by extension.

#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "cgamesh/anim/pose.hpp"
#include "cgamesh/anim/rigged_model.hpp"
#include "cgamesh/anim/skinning.hpp"

namespace cgamesh::cli {

extern const std::map<std::string, anim::BlendMode> kBlendModes;
extern const std::map<std::string, anim::SkinningMode> kSkinningModes;

/// Exactly `count` comma-separated finite numbers.
/// @throws InvalidInputError naming `what` otherwise.
[[nodiscard]] std::vector<double> parse_numbers(const std::string& text, std::size_t count, const std::string& what);

/// "JOINT:rotate=AX,AY,AZ,DEG" | "JOINT:translate=X,Y,Z" | "JOINT:scale=S".
/// @throws InvalidInputError for an unknown joint or a malformed edit.
[[nodiscard]] anim::JointEdit parse_edit(const anim::Skeleton& skeleton, const std::string& text);

/// The clip named or numbered `anim`; the first clip (or -1 without clips) when empty.
/// @throws InvalidInputError when there is no such clip.
[[nodiscard]] int clip_index(const anim::RiggedModel& model, const std::string& anim);

/// The pose options of the surgery commands and `render`: a clip at a time, user edits, or the
/// bind pose (the default).
struct PoseChoice {
  explicit PoseChoice(std::string help) : anim_help(std::move(help)) {}

  std::string anim_help;  ///< what --anim does, for the help text
  std::string anim;
  double time = 0;
  anim::BlendMode blend = anim::BlendMode::format;
  std::vector<std::string> sets;
  const CLI::Option* time_option = nullptr;  ///< set by add_to(); given or not

  /// Adds --anim, --time, --blend and --set to `sub`.
  void add_to(CLI::App& sub);
  /// The chosen pose of `model`.
  /// @throws InvalidInputError for a bad time, an unknown clip or joint, or a malformed edit.
  [[nodiscard]] anim::Pose pose(const anim::RiggedModel& model) const;
};

/// World-space positions of every mesh in `pose`.
[[nodiscard]] std::vector<mesh::RowMatrixXf<3>> posed_positions(const anim::RiggedModel& model, const anim::Pose& pose,
                                                                anim::SkinningMode mode);

/// Seconds a model may take to load (--load-timeout): some readers loop forever on corrupt
/// files, and a reader cannot be interrupted, so past this the process ends (exit 3).
inline double load_timeout_seconds = 120;

/// Adds --load-timeout to `app` (given before or after the command).
void add_load_timeout(CLI::App& app);

/// io::load_model within load_timeout_seconds; past it, a message on stderr and exit 3. The
/// loader's warnings go to stderr unless the command prints them itself (`print_warnings`).
/// @throws FileError as io::load_model does.
[[nodiscard]] anim::RiggedModel load_model(const std::filesystem::path& path, bool print_warnings = true);

/// True for a .glb or .gltf path (any case).
[[nodiscard]] bool is_gltf_path(const std::filesystem::path& path);

}  // namespace cgamesh::cli
