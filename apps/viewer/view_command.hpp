#pragma once
// cgamesh view [MODEL]: the interactive viewer (GLFW window, Dear ImGui panel).

#include <CLI/CLI.hpp>

namespace cgamesh::cli {

/// Adds the `view` command to `app`.
void add_view(CLI::App& app);

}  // namespace cgamesh::cli
