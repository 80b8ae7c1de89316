#pragma once
// `cgamesh algebra-demo`: one TRS versor applied to a point, a sphere and a plane, checked
// against the 4x4 matrix, and a keyframe pair blended linearly and logarithmically.

#include <CLI/CLI.hpp>

namespace cgamesh::cli {

/// Adds the subcommand to `app`; `run` is set to its handler.
void add_algebra_demo(CLI::App& app);

}  // namespace cgamesh::cli
