#pragma once
// Drawing figures with the Python scripts in tools/ (Debian's matplotlib
// under /usr/bin/python3). A missing script or interpreter is a warning, not
// an error: the tables and CSV files are the results, figures a view of them.
#include <string>
#include <vector>

namespace rigidae::cli {

// Runs /usr/bin/python3 tools/SCRIPT ARGS...; the script is looked up in
// $RIGIDAE_TOOLS_DIR, the source tree's tools/, then tools/ next to the
// executable's parent folder. Returns true if it ran and exited 0.
bool run_plot_script(const std::string& script, const std::vector<std::string>& args);

}  // namespace rigidae::cli
