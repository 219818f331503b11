// rigidae command line: the one place where errors become exit codes.
//   0 success, 1 the solver failed (or was interrupted), 2 bad input.
#include <fmt/format.h>

#include <csignal>
#include <string>
#include <vector>

#include "commands.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/checked_file.hpp"
#include "rigidae/schemes/scheme.hpp"
#include "rigidae/solver/ida_driver.hpp"
#include "rigidae/app/command_line.hpp"
#include "rigidae/core/text.hpp"
#include "output_folder.hpp"

namespace {

using namespace rigidae;

constexpr const char* kUsage = R"(rigidae: rigid-body rotation as a DAE, solved with SUNDIALS IDA

Usage:
  rigidae solve SCENE.toml [options]     integrate a scene, write its outputs to a folder
  rigidae compare SCENE.toml [options]   every coordinates x equations x scheme side by side
  rigidae study [list|run|collect] STUDY.toml [options]
                                         accuracy studies: a grid of runs, sharded or not
  rigidae COMMAND --help                 the options of one command
  rigidae --help                         this text
  rigidae --version                      version of rigidae

)";

constexpr const char* kTrailer = R"(
Outputs of a run (in its folder): steps.csv (every IDA step), trajectory.csv
(the output grid), events.csv (chart switches, projections), summary.json
(configuration, counters, maxima, final state). Scene format: docs/scene_format.md.

Exit codes: 0 success, 1 the solver failed or was interrupted (outputs kept),
2 bad input (scene file or command line).
)";

void print_help() {
  fmt::print("{}", kUsage);
  for (const char* name : {"solve", "compare", "study"})
    fmt::print("{}\n{}\n", std::string(79, '-'), cli::command_help(cli::command_info(name)));
  fmt::print("{}", kTrailer);
}

// The first Ctrl-C (or TERM) asks the run to stop after the current step and
// keep its outputs; a second one, if the run is stuck inside a step, ends the
// process at once the default way (the CSV files may then end mid-row).
void on_signal(int sig) {
  if (g_interrupt_requested.exchange(true)) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
}

int run(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    print_help();
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    fmt::print("rigidae {}\n", RIGIDAE_VERSION);
    return 0;
  }
  // Ctrl-C or a job scheduler's TERM: stop between steps, keep what is written.
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  // Past a file-size limit (ulimit -f) a write fails with EFBIG, which the
  // checked outputs report, instead of the process dying without a word.
  std::signal(SIGXFSZ, SIG_IGN);
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (args[0] == "solve") return cli::solve_command(rest);
  if (args[0] == "compare") return cli::compare_command(rest);
  if (args[0] == "study") return cli::study_command(rest);
  throw InputError(fmt::format("unknown command '{}'{} (valid commands: solve, compare, study; see rigidae --help)",
                               text::printable(args[0]), cli::did_you_mean(args[0], {"solve", "compare", "study"})));
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const InputError& e) {
    cli::remove_rejected_output_folders();
    // Scene-file errors already read "FILE:LINE:COL: error: ..."
    const std::string msg = e.what();
    fmt::print(stderr, "{}{}\n", msg.find(": error: ") == std::string::npos ? "rigidae: error: " : "", msg);
    return 2;
  } catch (const SolverError& e) {
    fmt::print(stderr, "rigidae: solver error: {}\n", e.what());
    return 1;
  } catch (const OutputError& e) {
    fmt::print(stderr, "rigidae: error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rigidae: internal error: {}\n", e.what());
    return 1;
  }
}
