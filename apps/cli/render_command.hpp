#pragma once
// `cgamesh render`: headless pictures of models and of the results of every command.

#include <CLI/CLI.hpp>

namespace cgamesh::cli {

void add_render(CLI::App& app);

}  // namespace cgamesh::cli
