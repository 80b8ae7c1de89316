// The cgamesh command-line tool.
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>

#include "algebra_demo.hpp"
#include "cli_common.hpp"
#include "deform_command.hpp"
#include "model_commands.hpp"
#include "render_command.hpp"
#include "surgery_commands.hpp"
#ifdef CGAMESH_WITH_VIEWER
#include "view_command.hpp"
#endif
#include "cgamesh/errors.hpp"

#include "exit_codes.hpp"

int main(int argc, char** argv) {
  CLI::App app{"cgamesh: animate, deform, cut, tear and drill rigged models in Conformal Geometric Algebra"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cgamesh 0.1.0");
  cgamesh::cli::add_load_timeout(app);
  cgamesh::cli::add_info(app);
  cgamesh::cli::add_pose(app);
  cgamesh::cli::add_convert(app);
  cgamesh::cli::add_animate(app);
  cgamesh::cli::add_cut(app);
  cgamesh::cli::add_tear(app);
  cgamesh::cli::add_drill(app);
  cgamesh::cli::add_deform(app);
  cgamesh::cli::add_render(app);
#ifdef CGAMESH_WITH_VIEWER
  cgamesh::cli::add_view(app);
#endif
  cgamesh::cli::add_algebra_demo(app);
  // Before any command runs: `--time ''` is not 0.
  app.parse_complete_callback([&app] { cgamesh::cli::check_no_empty_values(app); });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? cgamesh::cli::kExitOk : cgamesh::cli::kExitBadArguments;
  } catch (const cgamesh::FileError& e) {
    std::cerr << "cgamesh: " << e.what() << "\n";
    return cgamesh::cli::kExitBadInput;
  } catch (const cgamesh::WriteError& e) {
    std::cerr << "cgamesh: cannot write the output: " << e.what() << "\n";
    return cgamesh::cli::kExitBadArguments;
  } catch (const cgamesh::InvalidInputError& e) {
    std::cerr << "cgamesh: invalid input: " << e.what() << "\n";
    return cgamesh::cli::kExitBadArguments;
  } catch (const cgamesh::PlatformError& e) {
    std::cerr << "cgamesh: this machine cannot do it: " << e.what() << "\n";
    return cgamesh::cli::kExitPlatform;
  } catch (const cgamesh::Error& e) {
    std::cerr << "cgamesh: " << e.what() << "\n";
    return cgamesh::cli::kExitImpossible;
  } catch (const std::exception& e) {
    std::cerr << "cgamesh: internal error: " << e.what() << "\n";
    return cgamesh::cli::kExitInternal;
  }
  return cgamesh::cli::kExitOk;
}
