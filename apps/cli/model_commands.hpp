#pragma once
// The model commands of the CLI: info, pose, convert, animate.

#include <CLI/CLI.hpp>

namespace cgamesh::cli {

void add_info(CLI::App& app);
void add_pose(CLI::App& app);
void add_convert(CLI::App& app);
void add_animate(CLI::App& app);

}  // namespace cgamesh::cli
