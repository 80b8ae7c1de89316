#pragma once
// Viewer scripts: a list of actions, one per line, that `cgamesh view --script FILE` runs one
// per frame, so that the viewer can be tested and demos recorded. The grammar (README, "The
// viewer") and the actions on a Session live here; the viewer adds those that need a window
// (play, drag, view, screenshot, ...).
//
//   # a comment                      words are separated by spaces; "a path" may be quoted
//   clip NAME|INDEX|bind             time SECONDS            play SECONDS (advance frame by frame)
//   blend format|linear|log          skinning cga|versor|matrix|dqs
//   color MODE   view NAME   explode AMOUNT   wait FRAMES
//   joint JOINT:rotate=AX,AY,AZ,DEG | JOINT:translate=X,Y,Z | JOINT:scale=S      unedit
//   key          generate [NAME]
//   cut NX,NY,NZ,D [cap]             tear HX,HY,HZ,TX,TY,TZ ... [open=W]
//   drag X,Y X,Y ... [open=W]        (a tear dragged through window pixels, top-left origin)
//   drill TX,TY,TZ BX,BY,BZ RADIUS [wall]
//   tissue TENSION|off (living tissue on, with that pre-tension, or off)   bake
//   deform (the viewer's --spec with its keys as set)
//   undo   redo   reset   save PATH   screenshot PATH [panel]   quit

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cgamesh/session/session.hpp"
#include "cgamesh/surgery/tear.hpp"

namespace cgamesh::session {

/// One line of a script, its words checked and its numbers read.
struct ScriptAction {
  int line = 0;                            ///< 1-based line in the script
  std::string verb;                        ///< the first word
  std::string text;                        ///< the word argument: clip, mode, view, edit, name, path
  std::vector<double> numbers;             ///< time, play, explode, wait; cut: NX,NY,NZ,D; drill: tip, base, radius
  std::vector<surgery::Scalpel> scalpels;  ///< tear: the blade at each time step
  std::vector<Eigen::Vector2d> points;     ///< drag: window pixels
  bool flag = false;                       ///< cut: cap; drill: wall; screenshot: panel
  double open = 0;                         ///< tear, drag: the opening width
};

/// The actions of `text`, in order (blank and comment lines left out).
/// @param[in] source  names the script in messages ("FILE:LINE: ...")
/// @throws InvalidInputError naming the line for an unknown action (listing the known ones), a
///         missing or extra argument, a malformed or non-finite number, or a bad mode name.
[[nodiscard]] std::vector<ScriptAction> parse_script(const std::string& text, const std::string& source);

/// Reads and parses a script file.
/// @throws FileError when the file cannot be read; InvalidInputError as parse_script().
[[nodiscard]] std::vector<ScriptAction> read_script(const std::string& path);

/// True for the actions apply() carries out on a Session; the others (play, skinning, color,
/// view, explode, drag, deform, wait, save, screenshot, quit) need the viewer.
[[nodiscard]] bool is_session_action(const std::string& verb) noexcept;

/// Carries out a session action: the report of a cut, tear or drill, nothing for the others.
/// @throws InvalidInputError for an unknown clip or joint, a bad edit, an action that is not a
///         session action; what the Session's operations throw.
std::optional<OperationReport> apply(Session& session, const ScriptAction& action);

}  // namespace cgamesh::session
