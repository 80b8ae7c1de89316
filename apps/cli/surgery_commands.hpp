#pragma once
// The surgery commands of the CLI: cut (and later tear, drill).

#include <CLI/CLI.hpp>

namespace cgamesh::cli {

void add_cut(CLI::App& app);
void add_drill(CLI::App& app);

}  // namespace cgamesh::cli
