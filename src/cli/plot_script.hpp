#pragma once
// Drawing figures with the Python scripts in tools/ (Debian's matplotlib
// under /usr/bin/python3). A missing script or interpreter is a warning, not
// an error: the tables and CSV files are the results, figures a view of them.
#include <filesystem>
#include <string>
#include <vector>

namespace rigidae::cli {

// Runs /usr/bin/python3 tools/SCRIPT ARGS...; the script is looked up in
// $RIGIDAE_TOOLS_DIR, then relative to the executable: ../share/rigidae/tools
// (installed), share/rigidae/tools (the build tree's link to tools/).
// RIGIDAE_SHOW_PLOT_SCRIPT set in the environment prints the script's path
// to stderr. Returns true if it ran and exited 0.
bool run_plot_script(const std::string& script, const std::vector<std::string>& args);

// The tools that draw a run (rigidae view, vtk, animate: tools/*_run.py)
// are found the same way, but their output is the command's result: a
// missing script or a failure is an error. Returns the script's exit code.
int run_tool_script(const std::string& script, const std::vector<std::string>& args);

// share/rigidae/RELATIVE relative to the executable: ../share/rigidae
// (installed), share/rigidae beside it (the build tree). Empty when absent.
std::filesystem::path find_shared_file(const std::string& relative);

}  // namespace rigidae::cli
