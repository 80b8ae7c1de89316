#pragma once
// The surgery commands of the CLI: cut, tear and drill.

#include <CLI/CLI.hpp>

namespace cgamesh::cli {

void add_cut(CLI::App& app);
void add_drill(CLI::App& app);
void add_tear(CLI::App& app);

}  // namespace cgamesh::cli
