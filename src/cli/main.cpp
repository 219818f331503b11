// rigidae command line: the one place where errors become exit codes.
//   0 success, 1 a run failed, stalled, timed out or was interrupted, or output
//   was lost, 2 bad input (docs/robustness.md, "Exit codes").
#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <ctime>
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

constexpr const char* kUsage = R"(rigidae: rigid bodies and mechanisms as DAEs or ODEs, solved with SUNDIALS IDA, CVODE or ARKODE

Usage:
  rigidae solve SCENE.toml [options]     integrate a scene, write its outputs to a folder
  rigidae compare SCENE.toml [options]   every coordinates x equations x scheme side by side
  rigidae study [list|run|collect] STUDY.toml [options]
                                         accuracy studies: a grid of runs, sharded or not
  rigidae view RUN_DIR [--out FILE.html] a page that plays a run in a browser (offline)
  rigidae vtk RUN_DIR [--out DIR]        ParaView files (.pvd, .vtp) of the bodies' shapes
  rigidae animate RUN_DIR [--out F.gif]  an animation (GIF or MP4) and a strobe picture
  rigidae export --mjcf SCENE -o MODEL.xml
                                         a mechanism scene (or .urdf) as a MuJoCo model
  rigidae COMMAND --help                 the options of one command
  rigidae --help                         this text
  rigidae --version                      version of rigidae

)";

constexpr const char* kTrailer = R"(
Outputs of a run (in its folder): steps.csv (every IDA step), trajectory.csv
(the output grid), events.csv (chart switches, projections), summary.json
(configuration, counters, maxima, final state). Scene format: docs/scene_format.md.

Exit codes (every command): 0 success; 1 a run failed, stalled, timed out or
was interrupted by SIGINT/SIGTERM, or output could not be written (what was
computed is kept, summary.json says why); 2 bad input (scene or study file,
command line, an output folder not writable; nothing is run).
)";

void print_help() {
  fmt::print("{}", kUsage);
  for (const char* name : {"solve", "compare", "study"})
    fmt::print("{}\n{}\n", std::string(79, '-'), cli::command_help(cli::command_info(name)));
  for (const char* name : {"view", "vtk", "animate"})
    fmt::print("{}\n{}\n", std::string(79, '-'), cli::draw_command_help(name));
  fmt::print("{}", kTrailer);
}

// The first Ctrl-C (or TERM) asks the run to stop after the current step,
// write its summary and keep its outputs. Repeats within kSignalGrace are
// ignored: GNU timeout sends TERM to the process and then to its whole
// process group, and a shell's Ctrl-C may arrive twice; either would
// otherwise kill the process in the middle of that final flush. A repeat
// after the grace period (a run stuck inside a step, a flush that hangs)
// ends the process at once the default way (the files may then end mid-row).
constexpr long long kSignalGraceNs = 2'000'000'000;  // 2 s
std::atomic<long long> g_first_signal_ns{0};

long long monotonic_ns() {  // clock_gettime is async-signal-safe
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<long long>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

void on_signal(int sig) {
  const long long now = monotonic_ns();
  if (!g_interrupt_requested.load()) {
    g_first_signal_ns.store(now);
    g_interrupt_signal.store(sig);
    g_interrupt_requested.store(true);
    return;
  }
  if (now - g_first_signal_ns.load() < kSignalGraceNs) return;  // a repeat during the flush
  std::signal(sig, SIG_DFL);
  std::raise(sig);
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
  if (cli::is_draw_command(args[0])) return cli::draw_command_run(args[0], rest);
  if (args[0] == "export") return cli::export_command(rest);
  throw InputError(fmt::format(
      "unknown command '{}'{} (valid commands: solve, compare, study, view, vtk, animate, export; see rigidae --help)",
      text::printable(args[0]),
      cli::did_you_mean(args[0], {"solve", "compare", "study", "view", "vtk", "animate", "export"})));
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
