#pragma once
/// The `cutwork` subcommands. Each add_*_command registers one subcommand (with its --help) on
/// the application; its callback may throw cutwork::Error, which main() turns into one line on
/// stderr and exit code 2.
namespace CLI {
class App;
}

namespace cutwork::cli {

void add_scenes_command(CLI::App& app);
void add_show_command(CLI::App& app);
void add_check_command(CLI::App& app);
void add_design_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_verify_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_sweep_command(CLI::App& app);

}  // namespace cutwork::cli
