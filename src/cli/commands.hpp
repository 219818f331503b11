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

}  // namespace rigidae::cli
