#pragma once
// The subcommands of the rigidae CLI. Each returns its exit code and throws
// InputError for bad input; main() turns exceptions into exit codes.
#include <string>
#include <vector>

namespace rigidae::cli {

int solve_command(const std::vector<std::string>& args);
int compare_command(const std::vector<std::string>& args);
int study_command(const std::vector<std::string>& args);
int export_command(const std::vector<std::string>& args);

// The commands that draw a run (draw_commands.cpp): view, vtk, animate.
bool is_draw_command(const std::string& name);
int draw_command_run(const std::string& name, const std::vector<std::string>& args);
std::string draw_command_help(const std::string& name);

}  // namespace rigidae::cli
