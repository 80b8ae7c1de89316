#pragma once
// The deform command of the CLI: motor-handle deformation from a JSON spec.

#include <CLI/CLI.hpp>

namespace cgamesh::cli {

void add_deform(CLI::App& app);

}  // namespace cgamesh::cli
