// `cutwork` — design thin shells with decorative stencils that stay structurally sound.
// Every error a user can cause ends here as one line on stderr and exit code 2.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <iostream>

#include "host/cli/commands.h"
#include "host/core/error.h"
#include "host/core/input_file.h"

int main(int argc, char** argv) {
  CLI::App app{
      "cutwork: thin shells with decorative stencils that stay structurally sound\n"
      "(Schumacher, Thomaszewski, Gross: Stenciling, SGP 2016)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cutwork 0.1.0");
  cutwork::cli::add_scenes_command(app);
  cutwork::cli::add_show_command(app);
  cutwork::cli::add_check_command(app);
  cutwork::cli::add_design_command(app);
  cutwork::cli::add_simulate_command(app);
  cutwork::cli::add_verify_command(app);
  cutwork::cli::add_render_command(app);
  cutwork::cli::add_sweep_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "cutwork: " << e.what() << " (see cutwork --help)\n";
    return 2;
  } catch (const cutwork::Interrupted& e) {
    std::cerr << "cutwork: " << e.what() << "\n";
    return 128 + e.signal();
  } catch (const cutwork::Error& e) {
    // One line, of bounded length, whatever a message quotes from the input.
    std::cerr << "cutwork: " << cutwork::excerpt(e.what(), 2000) << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    std::cerr << "cutwork: out of memory (try a coarser mesh resolution)\n";
    return 2;
  } catch (const std::exception& e) {
    // Anything else is a bug in cutwork, not bad input: say so, distinctly.
    std::cerr << "cutwork: internal error: " << cutwork::excerpt(e.what(), 2000) << "\n";
    return 1;
  }
  return 0;
}
