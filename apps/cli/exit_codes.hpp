#pragma once
// Exit codes shared by every cgamesh command.
namespace cgamesh::cli {
inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;      ///< a bug or an unexpected failure
/// The machine lacks what the command needs (no EGL display or OpenGL 3.3 context, no display).
inline constexpr int kExitPlatform = 1;
inline constexpr int kExitBadArguments = 2;  ///< the command line is wrong
inline constexpr int kExitBadInput = 3;      ///< an input file is unreadable or invalid
inline constexpr int kExitImpossible = 4;    ///< the operation is impossible on this input
}  // namespace cgamesh::cli
