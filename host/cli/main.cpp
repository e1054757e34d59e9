// `cutwork` — design thin shells with decorative stencils that stay structurally sound.
// Every error a user can cause ends here as one line on stderr and exit code 2; a bug in cutwork
// (an internal error) exits with code 1.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <iostream>

#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/core/error.h"
#include "host/core/exit_status.h"
#include "solvers/linear/thread_policy.h"

int main(int argc, char** argv) {
  cutwork::solvers::ensure_blas_kernels(argv);  // may run cutwork again with OPENBLAS_CORETYPE set
  cutwork::solvers::settle_library_threads();
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
  } catch (...) {
    // User errors exit 2, interruptions 128 + signal, bugs in cutwork 1 (host/core/exit_status.h).
    const cutwork::ExitStatus status = cutwork::exit_status_for(std::current_exception());
    std::string hint;
    try {
      throw;
    } catch (const cutwork::SolveError&) {
      hint = cutwork::cli::solve_error_hint();
    } catch (...) {
    }
    std::cerr << status.line << hint << "\n";
    return status.code;
  }
  return 0;
}
