// rigidae command line: the one place where errors become exit codes.
//   0 success, 1 the solver failed (or was interrupted), 2 bad input.
#include <fmt/format.h>

#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "rigidae/app/solve.hpp"
#include "rigidae/core/error.hpp"
#include "rigidae/io/scene_loader.hpp"
#include "rigidae/schemes/scheme.hpp"

namespace {

using namespace rigidae;

constexpr const char* kHelp = R"(rigidae: rigid-body rotation as a DAE, solved with SUNDIALS IDA

Usage:
  rigidae solve SCENE.toml [options]   integrate a scene, write its outputs to a folder
  rigidae --help                       this text
  rigidae --version                    version of rigidae and of SUNDIALS

Options of 'solve' (each overrides the scene file):
  --coordinates euler|quaternion|linear
                          rotation coordinates: Euler angles (3, singular charts,
                          switched during the run), unit quaternions (4, 1
                          constraint) or the 9 entries of R (6 constraints)
  --equations lagrange|euler
                          Lagrange form (mass matrix in the coordinates) or Euler
                          form (body angular velocity states + kinematics)
  --scheme NAME           constraint treatment: {schemes}
  --rtol X                relative tolerance, 0 < X < 1
  --atol X                absolute tolerance, 0 < X < 1
  --t-end T               end time in s (> the scene's start time)
  --out DIR               output folder (default: out/NAME-COORDINATES-EQUATIONS-SCHEME)
  --euler-sequence SEQ    initial Euler-angle chart: 'auto' or three letters (e.g. zxz)
  --no-chart-switching    stop at the Euler-angle chart's singularity margin
                          instead of switching charts
  --switch-threshold X    chart margin |det B| at which to switch, 0 < X < 1
  --max-steps N           limit on internal IDA steps
  --jacobian central|ida_dq
                          iteration matrix: rigidae's central differences
                          (default; accurate enough for index-2 forms at tight
                          tolerances) or IDA's forward difference quotients
  --quiet                 print nothing on success

Outputs (in the folder): steps.csv (every IDA step), trajectory.csv (the output
grid), events.csv (chart switches), summary.json (configuration, counters,
maxima, final state). Scene format: docs/scene_format.md.

Exit codes: 0 success, 1 the solver failed or was interrupted (outputs kept),
2 bad input (scene file or command line).
)";

std::string valid_list(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

double parse_number(const std::string& opt, const std::string& text) {
  try {
    std::size_t used = 0;
    const double x = std::stod(text, &used);
    if (used == text.size() && std::isfinite(x)) return x;
  } catch (const std::exception&) {
  }
  throw InputError(fmt::format("option {}: '{}' is not a finite number", opt, text));
}

template <typename T>
T parse_choice(const std::string& opt, const std::string& text, const std::vector<std::pair<std::string, T>>& choices) {
  std::vector<std::string> names;
  for (const auto& [name, value] : choices) {
    if (name == text) return value;
    names.push_back(name);
  }
  throw InputError(fmt::format("option {}: unknown value '{}'; valid values: {}", opt, text, valid_list(names)));
}

struct SolveOptions {
  std::string scene_path;
  std::string out;
  bool quiet = false;
};

// Applies command-line overrides to the scene, checking each value.
SolveOptions parse_solve(const std::vector<std::string>& args, Scene& scene, bool& have_scene) {
  SolveOptions o;
  std::vector<std::pair<std::string, std::string>> overrides;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= args.size()) throw InputError(fmt::format("option {} needs a value (see rigidae --help)", a));
      return args[++i];
    };
    if (a == "--quiet") o.quiet = true;
    else if (a == "--no-chart-switching") overrides.emplace_back(a, "");
    else if (a == "--out") o.out = value();
    else if (a.rfind("--", 0) == 0) {
      static const std::vector<std::string> known = {"--coordinates", "--equations", "--scheme", "--rtol", "--atol",
                                                     "--t-end", "--euler-sequence", "--switch-threshold", "--max-steps",
                                                     "--jacobian"};
      if (std::find(known.begin(), known.end(), a) == known.end())
        throw InputError(fmt::format("unknown option '{}'; see rigidae --help", a));
      overrides.emplace_back(a, value());
    } else if (o.scene_path.empty()) o.scene_path = a;
    else throw InputError(fmt::format("unexpected argument '{}': solve takes one scene file", a));
  }
  if (o.scene_path.empty()) throw InputError("solve needs a scene file: rigidae solve SCENE.toml");
  scene = io::load_scene(o.scene_path);
  have_scene = true;

  for (const auto& [opt, text] : overrides) {
    if (opt == "--coordinates")
      scene.formulation.coordinates = parse_choice<Coordinates>(
          opt, text, {{"euler", Coordinates::EulerAngles}, {"quaternion", Coordinates::Quaternion}, {"linear", Coordinates::Linear}});
    else if (opt == "--equations")
      scene.formulation.equations = parse_choice<Equations>(opt, text, {{"lagrange", Equations::Lagrange}, {"euler", Equations::Euler}});
    else if (opt == "--scheme") {
      const auto names = scheme_names();
      if (std::find(names.begin(), names.end(), text) == names.end())
        throw InputError(fmt::format("option --scheme: unknown value '{}'; valid values: {}", text, valid_list(names)));
      scene.formulation.scheme = text;
    } else if (opt == "--rtol" || opt == "--atol" || opt == "--switch-threshold") {
      const double x = parse_number(opt, text);
      if (!(x > 0 && x < 1)) throw InputError(fmt::format("option {}: {} is outside (0, 1)", opt, text));
      (opt == "--rtol" ? scene.solver.rtol : opt == "--atol" ? scene.solver.atol : scene.formulation.euler.switch_threshold) = x;
    } else if (opt == "--t-end") {
      const double x = parse_number(opt, text);
      if (!(x > scene.time.start))
        throw InputError(fmt::format("option --t-end: {} must be greater than the scene's start time {}", text, scene.time.start));
      scene.time.end = x;
      scene.time.output_step = std::min(scene.time.output_step, x - scene.time.start);
    } else if (opt == "--max-steps") {
      const double x = parse_number(opt, text);
      if (!(x >= 1) || x != std::floor(x)) throw InputError(fmt::format("option --max-steps: {} is not a positive integer", text));
      scene.solver.max_steps = static_cast<long>(x);
    } else if (opt == "--euler-sequence") {
      if (text == "auto") scene.formulation.euler.sequence.reset();
      else {
        try {
          scene.formulation.euler.sequence = so3::parse_euler_sequence(text, false);
        } catch (const std::invalid_argument& e) {
          throw InputError(fmt::format("option --euler-sequence: {} (or 'auto')", e.what()));
        }
      }
    } else if (opt == "--jacobian") {
      scene.solver.jacobian = parse_choice<std::string>(opt, text, {{"central", "central"}, {"ida_dq", "ida_dq"}});
    } else if (opt == "--no-chart-switching") scene.formulation.euler.switching = false;
  }
  return o;
}

void print_report(const Scene& scene, const SolveOutcome& o) {
  const RunResult& r = o.run;
  const IdaCounters& c = r.counters;
  const Observation& f = o.extremes.last;
  fmt::print("rigidae {}: {} ({})\n", RIGIDAE_VERSION, scene.name, scene.source);
  fmt::print("  formulation   {} with scheme {}\n", o.representation, o.scheme);
  if (!o.note.empty()) fmt::print("  note          {}\n", o.note);
  fmt::print("  tolerances    rtol {:g}, atol {:g}\n", scene.solver.rtol, scene.solver.atol);
  fmt::print("  status        {}{}\n", to_string(r.status),
             r.status == RunStatus::Success ? fmt::format(": t = {:g} s reached", r.t_reached) : ": " + r.message);
  fmt::print("  work          {} steps, {} residual evaluations ({} for Jacobians), {} Jacobians, {:.3f} s wall\n",
             c.steps, c.residual_evals + c.jacobian_residual_evals, c.jacobian_residual_evals, c.jacobian_evals,
             o.wall_seconds);
  fmt::print("  failures      {} error-test, {} Newton convergence\n", c.error_test_fails, c.nonlinear_conv_fails);
  fmt::print("  final t       {:.9g} s\n", f.t);
  fmt::print("  final q_WB    ({:.8f}, {:.8f}, {:.8f}, {:.8f})\n", f.q_WB(0), f.q_WB(1), f.q_WB(2), f.q_WB(3));
  fmt::print("  final omega_B ({:.6f}, {:.6f}, {:.6f}) rad/s\n", f.omega_B(0), f.omega_B(1), f.omega_B(2));
  fmt::print("  max drift     position {:.2e}, velocity {:.2e}\n", o.extremes.max_drift_position,
             o.extremes.max_drift_velocity);
  fmt::print("  invariants    max |energy rel. error| {:.2e}, max |vertical momentum rel. error| {:.2e}\n",
             o.extremes.max_abs_energy_error, o.extremes.max_abs_vertical_momentum_error);
  for (std::size_t i = 0; i < o.multiplier_names.size() && o.extremes.steps_recorded > 0; ++i)
    fmt::print("  multiplier    {} in [{:.4g}, {:.4g}]\n", o.multiplier_names[i], o.extremes.multiplier_min(i),
               o.extremes.multiplier_max(i));
  if (!r.switches.empty())
    fmt::print("  charts        {} switches ({} restarts); first at t = {:.6g} s ({} -> {})\n", r.switches.size(),
               c.restarts, r.switches.front().t, r.switches.front().from, r.switches.front().to);
  fmt::print("  outputs       {}/ (steps.csv, trajectory.csv, events.csv, summary.json)\n", o.out_dir.string());
}

void on_sigint(int) { g_interrupt_requested.store(true); }

int run(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    fmt::print(kHelp, fmt::arg("schemes", valid_list(scheme_names())));
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version") {
    fmt::print("rigidae {}\n", RIGIDAE_VERSION);
    return 0;
  }
  if (args[0] != "solve")
    throw InputError(fmt::format("unknown command '{}'; valid commands: solve (see rigidae --help)", args[0]));

  Scene scene;
  bool have_scene = false;
  const SolveOptions opt = parse_solve({args.begin() + 1, args.end()}, scene, have_scene);
  const std::filesystem::path out =
      opt.out.empty() ? std::filesystem::path("out") / default_run_name(scene) : std::filesystem::path(opt.out);
  std::signal(SIGINT, on_sigint);
  const SolveOutcome o = solve_scene(scene, out);
  if (!opt.quiet || o.run.status != RunStatus::Success) print_report(scene, o);
  if (o.run.status != RunStatus::Success) {
    fmt::print(stderr, "rigidae: error: {}\n", o.run.message);
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const InputError& e) {
    // Scene-file errors already read "FILE:LINE:COL: error: ..."
    const std::string msg = e.what();
    fmt::print(stderr, "{}{}\n", msg.find(": error: ") == std::string::npos ? "rigidae: error: " : "", msg);
    return 2;
  } catch (const SolverError& e) {
    fmt::print(stderr, "rigidae: solver error: {}\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rigidae: internal error: {}\n", e.what());
    return 1;
  }
}
